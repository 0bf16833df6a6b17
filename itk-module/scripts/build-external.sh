#!/usr/bin/env bash
# Builds itk-module/ standalone as an ITK *external module* (ITK's module
# machinery: ITKModuleExternal.cmake, itk_module_impl, itk_module_test,
# CreateGoogleTestDriver), with ITK's CMake helpers from Debian's ITK source
# package (scripts/setup.sh puts them in .third_party/itk-cmake), then runs
# its tests. Everything is written below the build folder (default
# <repo>/build-itk-external); nothing is written into /usr.
#
#   itk-module/scripts/build-external.sh [build folder]
set -euo pipefail

module="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
repo="$(cd "$module/.." && pwd)"
helpers="${GDM_ITK_CMAKE_HELPERS:-$repo/.third_party/itk-cmake}"
build="${1:-$repo/build-itk-external}"

if [ ! -f "$helpers/ITKModuleExternal.cmake" ]; then
  echo "build-external: no ITK CMake helpers in $helpers; run scripts/setup.sh first" >&2
  exit 1
fi

mkdir -p "$build"
export CCACHE_BASEDIR="$repo" CCACHE_NOHASHDIR=1
stamp="$build/.build-external-stamp"
touch "$stamp"

generator=()
if command -v ninja >/dev/null 2>&1; then generator=(-G Ninja); fi
cmake -S "$module" -B "$build" "${generator[@]}" \
  -DGDM_ITK_EXTERNAL_MODULE=ON -DGDM_ITK_CMAKE_HELPERS="$helpers" -DBUILD_TESTING=ON
cmake --build "$build"
ctest --test-dir "$build" --output-on-failure

# The machinery writes module files below ITK_DIR; make sure none went to the system ITK.
leaked="$(find /usr/lib/cmake/ITK-5.2 /usr/include/ITK-5.2 -newer "$stamp" -print 2>/dev/null | head -n 5)"
if [ -n "$leaked" ]; then
  echo "build-external: files were written into the system ITK:" >&2
  echo "$leaked" >&2
  exit 1
fi
