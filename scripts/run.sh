#!/usr/bin/env bash
# Quick start: sets up the machine, builds, and runs gdm on its embedded default.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/setup.sh"
bash "$here/scripts/build.sh"
mkdir -p "$here/out"
"$here/build/common/gdm_demo" branching "$here/out/branching.off"
echo "wrote $here/out/branching.off"
