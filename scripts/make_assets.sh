#!/usr/bin/env bash
# Regenerates the committed concave-object assets (assets/concave/) with the project's own code:
# each built-in object's repaired mesh (.off) and its runtime asset at every level of detail.
# Usage: scripts/make_assets.sh [path/to/grip]   (default: build/apps/grip)
set -euo pipefail
cd "$(dirname "$0")/.."
grip=${1:-build/apps/grip}
out=assets/concave
mkdir -p "$out"
for name in mug axe torus l-block figurine; do
  "$grip" prep --builtin "$name" --export-mesh "$out/$name.off" --lod all -o "$out/${name}_{lod}.grip"
done
