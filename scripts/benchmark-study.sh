#!/usr/bin/env bash
# Runs the side-by-side benchmark study against the peers (VTK flying edges,
# the 3D Slicer chain, ITK's BinaryMask3DMeshSource and simplex deformable
# model, CGAL Mesh_3) and writes the report, plots and pictures to
# docs/benchmarks/. Sets the machine up and builds first (scripts/setup.sh,
# scripts/build.sh). Renders offscreen under xvfb-run.
#
#   bash scripts/benchmark-study.sh            # the whole study (15 to 30 minutes on 2 cores, with their load)
#   bash scripts/benchmark-study.sh --quick    # one small case per method, one run (CI), into build/benchmark-study-quick
#
# Other arguments go to gdm_benchmark_study (--runs N, --threads N, --out DIR, --budget SECONDS,
# --only WORD: only the cases whose id contains WORD, repeatable, e.g. --only bottle --only channels,
# --only topo for the topology group (hollow sphere, tori, whole tooth);
# --noise-sigma S: the Gaussian-noise phantoms' sigma (default 20, 13 % of the contrast 150),
# --noise-seed N: their noise fields from seed N on (default 7), to try other noise than the report's;
# with --only, pass an --out other than docs/benchmarks so the full report stays whole).
# GDM_BUILD_DIR picks the build folder (default build/); GDM_SHARED_DIR the
# folder holding data/ (default ../shared); GDM_STUDY_CMAKE_ARGS extra CMake arguments.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="${GDM_BUILD_DIR:-$here/build}"
shared="${GDM_SHARED_DIR:-$here/../shared}"

bash "$here/scripts/setup.sh"
# shellcheck disable=SC2086
GDM_BUILD_DIR="$build" bash "$here/scripts/build.sh" ${GDM_STUDY_CMAKE_ARGS:-}
study="$build/test/benchmark/study/gdm_benchmark_study"
if [ ! -x "$study" ]; then
  echo "benchmark-study: $study was not built (it needs libvtk9-dev and libcgal-dev; see $build.configure.log)" >&2
  exit 1
fi

out="$here/docs/benchmarks"
for a in "$@"; do
  if [ "$a" = "--quick" ]; then out="$build/benchmark-study-quick"; fi
done
commit="$(git -C "$here" rev-parse --short HEAD 2>/dev/null || echo unknown)"
if [ -n "$(git -C "$here" status --porcelain --untracked-files=no 2>/dev/null || true)" ]; then
  commit="$commit (with uncommitted changes)"
fi
# A later --out among "$@" overrides this one. The X display number starts at a
# random point: parallel xvfb-run -a calls starting at the same number can share
# (and lose) one server. -noreset: each picture opens and closes its own X
# connection, and an X server resets when its last client leaves; a window
# opened during the reset failed (XSync crashed, or VTK aborted on "bad X server
# connection") in 9 of 40 quick runs, which is how CI's run of stop 65 ended
# with exit 139; with -noreset none of 40 did.
xvfb-run -a -n "$((100 + RANDOM % 800))" -s "-screen 0 1280x1024x24 -noreset" "$study" --out "$out" --data "$shared/data" --commit "$commit" "$@"
