#!/usr/bin/env bash
# Sets up the machine, builds everything and runs the whole test suite:
# the Release build's tests (core, ITK module, MeshLab plugin, the Snakemake
# cohort workflow: ctest gdm_workflow, skipped without snakemake), the Python
# module's tests, the install (scripts/test-install.sh: a temporary prefix,
# the downstream projects of test/downstream, the plugin loaded from the
# prefix, the .deb), the ITK module again as an ITK external module, then the
# core's, the pipeline's, the image reader's and the gdm command's tests again
# under AddressSanitizer + UndefinedBehaviorSanitizer, then the fuzz targets
# for 30 s each (scripts/fuzz.sh), then a short benchmark run (reported, not
# asserted).
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
jobs="$(nproc)"

bash "$here/scripts/setup.sh"

echo "== build (Release)"
bash "$here/scripts/build.sh"
echo "== tests (Release)"
ctest --test-dir "$here/build" --output-on-failure -j "$jobs" --timeout 900 -E '^gdm_python$'

echo "== Python module (pytest)"
if [ -d "$here/build/python/gdm" ]; then
  # Debian's interpreter: the one the module and python3-numpy are built for.
  set +e
  PYTHONPATH="$here/build/python" /usr/bin/python3 -m pytest -q -rs -p no:cacheprovider "$here/python/tests"
  status=$?
  set -e
  if [ "$status" = 5 ]; then
    echo "pytest collected no test in python/tests: the Python tests are missing" >&2
    exit 1
  elif [ "$status" != 0 ]; then
    exit "$status"
  fi
else
  echo "skipped: the Python module was not built (pybind11-dev or python3-dev missing, or -DGDM_BUILD_PYTHON=OFF)"
fi

echo "== install: temporary prefix, downstream projects, MeshLab plugin from the prefix, Debian package"
bash "$here/scripts/test-install.sh" "$here/build"

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
  -DGDM_BUILD_MESHLAB_PLUGIN=OFF -DGDM_BUILD_PYTHON=OFF >"$sanitize.configure.log" 2>&1 || { cat "$sanitize.configure.log"; exit 1; }
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

# Fuzzing (test/fuzz, libFuzzer): 30 s per target keeps CI inside its budget
# (three targets: about 1.5 minutes plus the first build of build-fuzz/,
# some 10 minutes on 2 cores, ccache afterwards); fails on any crash found.
echo "== fuzzing (30 s per target)"
GDM_FUZZ_SEED=1 bash "$here/scripts/fuzz.sh" 30

echo "== benchmark (short run, reported only)"
"$here/build/test/benchmark/gdm_core_benchmark" --benchmark_min_time=0.05 2>&1 | grep -v "^\*\*\*WARNING"

echo "== benchmark study against the peers (--quick: one small case per method, reported only)"
bash "$here/scripts/benchmark-study.sh" --quick 2>&1 | tail -n 3
