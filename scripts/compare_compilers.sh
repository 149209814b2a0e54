#!/usr/bin/env bash
# Builds the runtime and tests/determinism/hash_scenes with g++ and with clang++ (Release,
# the same flags, separate build dirs build-gcc/ and build-clang/), runs both and diffs the
# scene hashes. Exits non-zero when they differ. See docs/determinism.md.
set -euo pipefail
cd "$(dirname "$0")/.."
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
jobs=$(nproc)
for pair in gcc:g++ clang:clang++; do
  name=${pair%%:*} cxx=${pair#*:}
  cc=${cxx/++/}
  [ "$name" = gcc ] && cc=gcc
  cmake -S . -B "build-$name" "${generator[@]}" -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_C_COMPILER="$cc" -DCMAKE_CXX_COMPILER="$cxx" \
    -DGRIP_BUILD_VOXEL=OFF -DGRIP_BUILD_BENCH=OFF >/dev/null
  cmake --build "build-$name" --parallel "$jobs" --target hash_scenes
  "build-$name/tests/hash_scenes" >"build-$name/hashes.txt"
done
if diff -u build-gcc/hashes.txt build-clang/hashes.txt; then
  echo "compare_compilers: g++ and clang++ agree on $(wc -l <build-gcc/hashes.txt) scenes"
else
  echo "compare_compilers: g++ and clang++ hashes DIFFER (see the diff above)" >&2
  exit 1
fi
