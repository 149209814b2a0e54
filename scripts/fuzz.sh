#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan, fuzz/) in build-fuzz/ and runs each from
# its committed seed corpus fuzz/corpus/<target>/ for a fixed number of inputs with a fixed
# seed (FUZZ_RUNS, default 100000; FUZZ_SEED, default 1), so that CI's run is the same run every
# time: it passes or fails on the code, not on luck. FUZZ_SECONDS=N fuzzes for N seconds with
# a random seed instead (for finding new bugs locally).
# New interesting inputs go to build-fuzz/corpus/<target>/ when hunting (kept between runs, not
# committed) and to a fresh build-fuzz/run/<target>/ in a fixed-seed run.
# Exits non-zero on the first crash, leak or timeout; the input is kept in
# build-fuzz/crashes/<target>/ (see docs/fuzzing.md for turning it into a regression test).
# FUZZ_TARGETS="scene asset" runs a subset.
set -euo pipefail
cd "$(dirname "$0")/.."
runs=${FUZZ_RUNS:-100000}
seed=${FUZZ_SEED:-1}
if [ -n "${FUZZ_SECONDS:-}" ]; then
  budget=(-max_total_time="$FUZZ_SECONDS")
  what="${FUZZ_SECONDS} s"
else
  what="seed $seed"
fi
# FUZZ_RUNS_MESH overrides the count for the mesh target alone (CGAL makes it the slowest).
runsFor() { if [ "$1" = mesh ]; then echo "${FUZZ_RUNS_MESH:-$runs}"; else echo "$runs"; fi; }
read -r -a targets <<<"${FUZZ_TARGETS:-scene recording asset mesh}"
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
cmake -S . -B build-fuzz "${generator[@]}" -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER=clang -DCMAKE_CXX_COMPILER=clang++ -DGRIP_BUILD_FUZZ=ON \
  -DGRIP_BUILD_TESTS=OFF -DGRIP_BUILD_BENCH=OFF -DGRIP_BUILD_VOXEL=OFF -DGRIP_WERROR=ON >/dev/null
cmake --build build-fuzz --parallel "$(nproc)" --target "${targets[@]/#/fuzz_}"
# A fixed-seed run repeats itself only if nothing else varies: -reload=0 stops libFuzzer from
# re-reading its corpus on the clock, and address-space randomisation is turned off because
# CGAL orders some containers by pointer, which changes the code paths an input takes.
norandom=()
if setarch "$(uname -m)" -R true 2>/dev/null; then
  norandom=(setarch "$(uname -m)" -R)
elif [ -z "${FUZZ_SECONDS:-}" ]; then
  echo "fuzz: cannot turn off address-space randomisation here; the run may differ from CI's" >&2
fi
for t in "${targets[@]}"; do
  # Hunting keeps what it finds in build-fuzz/corpus/; a fixed-seed run starts from the
  # committed corpus alone (an empty build-fuzz/run/), as it does on a fresh clone.
  found="build-fuzz/corpus/$t"
  if [ -z "${FUZZ_SECONDS:-}" ]; then
    budget=(-runs="$(runsFor "$t")" -seed="$seed")
    found="build-fuzz/run/$t"
    rm -rf "$found"
  fi
  mkdir -p "$found" "build-fuzz/crashes/$t"
  log="build-fuzz/fuzz_$t.log"
  # -timeout: one input taking 10 s is a hang; -rss_limit_mb: an input may not need 2 GB.
  if ! "${norandom[@]}" "build-fuzz/fuzz/fuzz_$t" "${budget[@]}" -reload=0 -timeout=10 -rss_limit_mb=2048 \
      -print_final_stats=1 -artifact_prefix="build-fuzz/crashes/$t/" \
      "$found" "fuzz/corpus/$t" >"$log" 2>&1; then
    tail -n 60 "$log"
    echo "fuzz: $t FAILED (input in build-fuzz/crashes/$t/, log $log)" >&2
    exit 1
  fi
  executed=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo '?')
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -n 1 | grep -o '[0-9]*' || echo '?')
  echo "fuzz: $t ok ($what, $executed inputs, coverage $cov edges)"
done
