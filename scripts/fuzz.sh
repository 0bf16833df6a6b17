#!/usr/bin/env bash
# Builds the libFuzzer targets of test/fuzz with clang (coverage + AddressSanitizer
# + UndefinedBehaviorSanitizer, ccache) into build-fuzz/ and runs each for
# SECONDS (default 60) on a copy of its committed corpus (test/fuzz/corpus/<target>).
#
#   bash scripts/fuzz.sh [seconds] [target...]
#
# Exits non-zero when any target finds a crash, a sanitizer report, a hang
# (-timeout) or an allocation or RSS above its limit; the input is kept as a
# file (its path is printed) under build-fuzz/fuzz-runs/<time>/<target>/,
# with the run's log. Reproduce: build-fuzz/test/fuzz/<target> <file>.
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
seconds="${1:-60}"
shift || true
targets=("$@")
if [ "${#targets[@]}" = 0 ]; then targets=(fuzz_image_reader fuzz_mesh_reader fuzz_pipeline); fi
build="${GDM_FUZZ_BUILD_DIR:-$here/build-fuzz}"
export CCACHE_BASEDIR="$here" CCACHE_NOHASHDIR=1

cc=clang-14 cxx=clang++-14
command -v "$cxx" >/dev/null || { cc=clang cxx=clang++; }
cmake -S "$here" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=RelWithDebInfo \
  -DCMAKE_C_COMPILER="$cc" -DCMAKE_CXX_COMPILER="$cxx" -DGDM_BUILD_FUZZERS=ON \
  -DGDM_BUILD_TESTS=OFF -DGDM_BUILD_BENCHMARKS=OFF -DGDM_BUILD_DEMO=OFF \
  -DGDM_BUILD_ITK=OFF -DGDM_BUILD_MESHLAB_PLUGIN=OFF >"$build.configure.log" 2>&1 ||
  { cat "$build.configure.log"; exit 1; }
ninja -C "$build" "${targets[@]}" >"$build.build.log" 2>&1 ||
  { grep -E "error|FAILED" -A3 "$build.build.log" | head -80; exit 1; }

# Per target: -timeout (s) for one input, the RSS limit and the largest single
# allocation (MB). The image reader reads with a 64 MiB limit of float voxels.
declare -A timeout=([fuzz_image_reader]=10 [fuzz_mesh_reader]=10 [fuzz_pipeline]=30)
declare -A malloc_mb=([fuzz_image_reader]=512 [fuzz_mesh_reader]=256 [fuzz_pipeline]=256)

runs="$build/fuzz-runs/$(date +%Y%m%d-%H%M%S)"
export ASAN_OPTIONS="${ASAN_OPTIONS:-detect_leaks=1:allocator_may_return_null=0}"
export UBSAN_OPTIONS="${UBSAN_OPTIONS:-print_stacktrace=1:halt_on_error=1}"
# Leaks inside Debian's ITK that gdm cannot avoid (each one listed there with its input).
export LSAN_OPTIONS="${LSAN_OPTIONS:-suppressions=$here/scripts/lsan-suppressions.txt:print_suppressions=0}"
failed=0
for t in "${targets[@]}"; do
  dir="$runs/$t"
  mkdir -p "$dir/corpus" "$dir/crashes"
  if [ -d "$here/test/fuzz/corpus/$t" ]; then cp -r "$here/test/fuzz/corpus/$t/." "$dir/corpus/"; fi
  rc=0
  # GDM_FUZZ_SEED fixes libFuzzer's random seed (CI sets it; 0 = a new one each run).
  (cd "$dir" && "$build/test/fuzz/$t" -seed="${GDM_FUZZ_SEED:-0}" -max_total_time="$seconds" -timeout="${timeout[$t]}" \
    -rss_limit_mb=2048 -malloc_limit_mb="${malloc_mb[$t]}" -max_len=8192 -print_final_stats=1 \
    -artifact_prefix="$dir/crashes/" "$dir/corpus" >"$dir/log" 2>&1) || rc=$?
  execs="$(grep -oE "stat::number_of_executed_units: *[0-9]+" "$dir/log" | grep -oE "[0-9]+$" || echo "?")"
  if [ "$rc" != 0 ]; then
    failed=1
    echo "fuzz: $t FAILED (exit $rc) after $execs inputs; log $dir/log"
    grep -E "^==[0-9]+==ERROR|runtime error|SUMMARY|ALARM|out-of-memory|uncaught|deadly signal" "$dir/log" | head -5 | sed 's/^/  /'
    for f in "$dir"/crashes/*; do [ -e "$f" ] && echo "  input kept: $f"; done
  else
    echo "fuzz: $t ok, $seconds s, $execs inputs, corpus $(ls "$dir/corpus" | wc -l) files"
  fi
done
exit "$failed"
