#!/usr/bin/env bash
# Configures and builds grip in ./build (Release). Extra arguments go to cmake's configure.
set -euo pipefail
cd "$(dirname "$0")/.."
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
if [ ! -f build/CMakeCache.txt ]; then
  cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DGRIP_WERROR=ON "$@" >/dev/null
fi
cmake --build build --parallel "$(nproc)"
