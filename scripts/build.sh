#!/usr/bin/env bash
# Configures and builds grip in ./build (Release). Extra arguments go to cmake's configure.
set -euo pipefail
cd "$(dirname "$0")/.."
generator=()
command -v ninja >/dev/null && generator=(-G Ninja)
if [ ! -f build/CMakeCache.txt ]; then
  # The peers (Bullet, ODE) are built too, so the side-by-side programs and their test run.
  cmake -S . -B build "${generator[@]}" -DCMAKE_BUILD_TYPE=Release -DGRIP_WERROR=ON \
    -DGRIP_WITH_BULLET=ON -DGRIP_WITH_ODE=ON "$@" >/dev/null
fi
cmake --build build --parallel "$(nproc)"
