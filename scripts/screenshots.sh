#!/usr/bin/env bash
# Regenerates the PNG screenshots in docs/images/ with Debian's chromium (headless): the whole
# viewer on the first scene given (viewer.png), then the 3D view of each other scene
# (NAME.png), each at its frame of largest contact force. Needs a build (scripts/build.sh).
#   bash scripts/screenshots.sh [SCENE...]
set -euo pipefail
cd "$(dirname "$0")/.."
scenes=("$@")
((${#scenes[@]})) || scenes=(grasp_lift grasp_lift push_box handover balance_two_hands spin_two_hands)
[ -x build/apps/grip ] || bash scripts/build.sh
GRIP_WEB_MODULES="$PWD/build/apps/web/npm/node_modules" \
  node web/tools/screenshots.mjs "$PWD/build/apps/grip" docs/images build/screenshots "${scenes[@]}"
