#!/usr/bin/env bash
# Configures and builds gdm into build/ (Release, Ninja, ccache when present).
# Extra arguments go to CMake's configure step.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${GDM_BUILD_DIR:-$here/build}"
# Let ccache reuse objects across clones in other folders.
export CCACHE_BASEDIR="$here" CCACHE_NOHASHDIR=1
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
  -DGDM_BUILD_TESTS=ON -DGDM_BUILD_BENCHMARKS=ON -DGDM_BUILD_MESHLAB_PLUGIN=ON -DGDM_BUILD_ITK=ON "$@" >"$build.configure.log" 2>&1 ||
  { cat "$build.configure.log"; exit 1; }
cmake --build "$build" -- -k 0 >"$build.build.log" 2>&1 || { grep -E "error|FAILED" -A3 "$build.build.log" | head -80; exit 1; }
