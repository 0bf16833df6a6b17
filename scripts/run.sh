#!/usr/bin/env bash
# Quick start: sets up the machine, builds, and runs gdm on its embedded
# CT-like phantom (data/phantom.mha), writing out/phantom.ply and out/phantom.json.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
bash "$here/scripts/setup.sh"
bash "$here/scripts/build.sh"
mkdir -p "$here/out"
"$here/build/itk-module/apps/gdm" -o "$here/out/phantom.ply" --report "$here/out/phantom.json"
