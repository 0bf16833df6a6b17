#!/usr/bin/env bash
# Sets up the machine, builds everything and runs the whole test suite:
# the Release build's tests (core, ITK module, MeshLab plugin), the ITK
# module again as an ITK external module, then the core's, the pipeline's,
# the image reader's and the gdm command's tests again under
# AddressSanitizer + UndefinedBehaviorSanitizer, then a short benchmark run
# (reported, not asserted).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
jobs="$(nproc)"

bash "$here/scripts/setup.sh"

echo "== build (Release)"
bash "$here/scripts/build.sh"
echo "== tests (Release)"
ctest --test-dir "$here/build" --output-on-failure -j "$jobs" --timeout 900

echo "== ITK module built as an ITK external module (ITK's module machinery)"
bash "$here/itk-module/scripts/build-external.sh" "$here/build-itk-external"

echo "== build (core, pipeline, image reader, gdm command; AddressSanitizer + UndefinedBehaviorSanitizer)"
# ITK itself is not instrumented; gdm's own code (and the gdm binary the CLI
# tests run) is. Only the test targets are built: not the ITK filter, its
# example, the demo or MeshLab.
sanitize="$here/build-sanitize"
sanitize_start=$(date +%s)
export CCACHE_BASEDIR="$here" CCACHE_NOHASHDIR=1
cmake -S "$here" -B "$sanitize" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo -DGDM_SANITIZE=ON \
  -DGDM_BUILD_TESTS=ON -DGDM_BUILD_BENCHMARKS=OFF -DGDM_BUILD_DEMO=OFF -DGDM_BUILD_ITK=ON \
  -DGDM_BUILD_MESHLAB_PLUGIN=OFF >"$sanitize.configure.log" 2>&1 || { cat "$sanitize.configure.log"; exit 1; }
cmake --build "$sanitize" --target gdm_core_tests gdm_accuracy_tests gdm_pipeline_tests gdm_image_io_tests \
  gdm_cli_tests -- -k 0 >"$sanitize.build.log" 2>&1 ||
  { grep -E "error|FAILED" -A3 "$sanitize.build.log" | head -80; exit 1; }
echo "   built in $(( $(date +%s) - sanitize_start )) s"
echo "== tests (core, pipeline, image reader, gdm command; sanitizers)"
tests_start=$(date +%s)
ASAN_OPTIONS=detect_leaks=1:abort_on_error=1 UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1 \
  LSAN_OPTIONS="suppressions=$here/scripts/lsan-suppressions.txt" \
  ctest --test-dir "$sanitize" --output-on-failure -j "$jobs" --timeout 1800 \
  -E '^(itkGeometricallyDeformedModelGTestDriver_NOT_BUILT|itkGDMDicomExample)$'
echo "   tests ran in $(( $(date +%s) - tests_start )) s (sanitizer stage: $(( $(date +%s) - sanitize_start )) s)"

echo "== benchmark (short run, reported only)"
"$here/build/test/benchmark/gdm_core_benchmark" --benchmark_min_time=0.05 2>&1 | grep -v "^\*\*\*WARNING"

echo "== benchmark study against the peers (--quick: one small case per method, reported only)"
bash "$here/scripts/benchmark-study.sh" --quick 2>&1 | tail -n 3
