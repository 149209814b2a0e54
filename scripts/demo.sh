#!/usr/bin/env bash
# Quick start 1: install what is missing, build, run the demo scene.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/setup.sh
bash scripts/build.sh
./build/apps/grip demo "$@"
