#!/usr/bin/env bash
# Builds the libFuzzer targets (clang, ASan + UBSan, fuzz/) in build-fuzz/ and runs each from
# its committed seed corpus fuzz/corpus/<target>/ for a fixed number of inputs with a fixed
# seed (FUZZ_RUNS, default 100000; FUZZ_SEED, default 1), so that CI's run is the same run every
# time: it passes or fails on the code, not on luck. FUZZ_SECONDS=N fuzzes for N seconds with
# a random seed instead (for finding new bugs locally).
# New interesting inputs go to build-fuzz/corpus/<target>/ when hunting (kept between runs, not
# committed); a fixed-seed run works in /tmp/grip-fuzz-stage/ (see below).
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
# ...and the run must not see where the clone is or what the caller's environment holds: a
# fixed-seed run copies the fuzzer and the committed corpus to one fixed directory and runs
# there with a minimal environment (two clones at different paths, or one run from a shell
# and one from CI, otherwise took different paths through CGAL from the same inputs).
stage=/tmp/grip-fuzz-stage
root=$(pwd)
for t in "${targets[@]}"; do
  mkdir -p "build-fuzz/crashes/$t"
  log="$root/build-fuzz/fuzz_$t.log"
  if [ -z "${FUZZ_SECONDS:-}" ]; then
    # A fixed-seed run starts from the committed corpus alone, as on a fresh clone; what it
    # finds stays in the stage directory.
    rm -rf "$stage" && mkdir -p "$stage/found" "$stage/crashes"
    cp "build-fuzz/fuzz/fuzz_$t" "$stage/fuzz"
    cp -r "fuzz/corpus/$t" "$stage/corpus"
    run=(env -i PATH=/usr/bin:/bin LANG=C.UTF-8 "${norandom[@]}" ./fuzz -runs="$(runsFor "$t")"
      -seed="$seed")
    where=$stage
    dirs=(found corpus)
    artifacts=crashes/
  else
    # Hunting keeps what it finds in build-fuzz/corpus/ between runs.
    mkdir -p "build-fuzz/corpus/$t"
    run=("${norandom[@]}" "build-fuzz/fuzz/fuzz_$t" "${budget[@]}")
    where=$root
    dirs=("build-fuzz/corpus/$t" "fuzz/corpus/$t")
    artifacts="build-fuzz/crashes/$t/"
  fi
  # -timeout: one input taking 10 s is a hang; -rss_limit_mb: an input may not need 2 GB.
  if ! (cd "$where" && "${run[@]}" -reload=0 -timeout=10 -rss_limit_mb=2048 \
      -print_final_stats=1 -artifact_prefix="$artifacts" "${dirs[@]}") >"$log" 2>&1; then
    [ "$where" = "$root" ] || cp "$stage"/crashes/* "build-fuzz/crashes/$t/" 2>/dev/null || true
    tail -n 60 "$log"
    echo "fuzz: $t FAILED (input in build-fuzz/crashes/$t/, log $log)" >&2
    exit 1
  fi
  executed=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$log" | grep -o '[0-9]*$' || echo '?')
  cov=$(grep -o 'cov: [0-9]*' "$log" | tail -n 1 | grep -o '[0-9]*' || echo '?')
  ft=$(grep -o 'ft: [0-9]*' "$log" | tail -n 1 | grep -o '[0-9]*' || echo '?')
  echo "fuzz: $t ok ($what, $executed inputs, coverage $cov edges, $ft features)"
done
