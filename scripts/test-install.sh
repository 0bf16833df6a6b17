#!/usr/bin/env bash
# Tests gdm as users install it, from a build folder (default build/, built by
# scripts/build.sh with the ITK part and the MeshLab plugin):
#  1. `cmake --install --prefix P` into a temporary P: the layout, the SONAMEs,
#     the relative RUNPATHs; DESTDIR puts every file below DESTDIR/<prefix>
#     and the install manifest uninstalls it completely;
#  2. pkg-config: a program compiled and linked with `pkg-config gdm-core`;
#  3. two downstream projects from test/downstream, configured against P only:
#     cpp (gdm::core + gdm::pipeline deform a sphere in a phantom it makes) and
#     itk (reader -> smoothing -> the ITK filter -> mesh writer on P's phantom);
#  4. the installed gdm and its man page; the MeshLab plugin loaded from P by a
#     meshlabserver staged there (scripts/meshlab-in-prefix.sh) under xvfb-run;
#  5. the Debian package (cpack -G DEB): its files and its Depends (dpkg-deb).
# Installing the .deb for real is not done here (see README, "Install").
#   scripts/test-install.sh [build folder]
set -euo pipefail
here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
build="$(cd "${1:-${GDM_BUILD_DIR:-$here/build}}" && pwd)"
work="$(mktemp -d "${TMPDIR:-/tmp}/gdm-install-test.XXXXXX")"
trap 'rm -rf "$work"' EXIT
prefix="$work/prefix"
multiarch="$(dpkg-architecture -qDEB_HOST_MULTIARCH 2>/dev/null || echo x86_64-linux-gnu)"
libdir="$prefix/lib/$multiarch"
export CCACHE_BASEDIR="$here" CCACHE_NOHASHDIR=1
failures=0
ok() { echo "  ok: $*"; }
fail() { echo "  FAIL: $*" >&2; failures=$((failures + 1)); }
check() { local what="$1"; shift; if "$@" >>"$work/log" 2>&1; then ok "$what"; else fail "$what (log: $(tail -n 20 "$work/log"))"; fi; }

echo "== install into a temporary prefix"
cmake --install "$build" --prefix "$prefix" >"$work/install.log"
for f in bin/gdm share/gdm/phantom.mha share/man/man1/gdm.1.gz share/doc/gdm/README.md \
    include/gdm/deformer.h include/gdm/pipeline.h include/gdm/image_io.h \
    include/gdm/itk/itkGeometricallyDeformedModelImageToMeshFilter.h \
    include/gdm/itk/itkGeometricallyDeformedModelImageToMeshFilter.hxx include/gdm/itk/itkGDMVolumeConversion.h \
    "lib/$multiarch/libgdm_core.so" "lib/$multiarch/libgdm_pipeline.so" "lib/$multiarch/libgdm_image_io.so" \
    "lib/$multiarch/cmake/gdm/gdmConfig.cmake" "lib/$multiarch/cmake/gdm/gdmConfigVersion.cmake" \
    "lib/$multiarch/cmake/gdm/gdmTargets.cmake" "lib/$multiarch/cmake/gdm/gdmItkTargets.cmake" \
    "lib/$multiarch/cmake/gdm/gdmImageIOTargets.cmake" \
    "lib/$multiarch/pkgconfig/gdm-core.pc" "lib/$multiarch/pkgconfig/gdm-pipeline.pc" \
    "lib/$multiarch/meshlab/plugins/libfilter_gdm.so" lib/cmake/ITK-5.2/Modules/GeometricallyDeformedModel.cmake; do
  [ -e "$prefix/$f" ] || fail "missing $f"
done
ok "layout below the prefix"
if grep -v "^$prefix/" <(sed -n 's/^-- \(Installing\|Up-to-date\): //p' "$work/install.log") | grep -q .; then
  fail "files installed outside the prefix: $(grep -v "^$prefix/" <(sed -n 's/^-- \(Installing\|Up-to-date\): //p' "$work/install.log"))"
else
  ok "nothing installed outside the prefix"
fi
for l in core pipeline image_io; do
  soname="$(readelf -d "$libdir/libgdm_$l.so" | sed -n 's/.*(SONAME).*\[\(.*\)\]/\1/p')"
  if [[ "$soname" =~ ^libgdm_$l\.so\.[0-9]+\.[0-9]+$ ]] && [ -f "$libdir/$soname" ]; then ok "SONAME $soname"; else fail "libgdm_$l.so SONAME '$soname'"; fi
done
runpath() { readelf -d "$1" | sed -n 's/.*(RUNPATH).*\[\(.*\)\]/\1/p'; }
[ "$(runpath "$prefix/bin/gdm")" = "\$ORIGIN/../lib/$multiarch" ] && ok "gdm's RUNPATH is relative" || fail "gdm RUNPATH $(runpath "$prefix/bin/gdm")"
[ "$(runpath "$libdir/meshlab/plugins/libfilter_gdm.so")" = "\$ORIGIN/../.." ] && ok "the plugin's RUNPATH is relative" ||
  fail "plugin RUNPATH $(runpath "$libdir/meshlab/plugins/libfilter_gdm.so")"
from_prefix() {  # every libgdm_* a binary loads comes from the prefix's library folder
  local n=0 path
  while read -r path; do
    [ "$(dirname "$(realpath "$path")")" = "$(realpath "$libdir")" ] || { echo "$1 loads $path" >>"$work/log"; return 1; }
    n=$((n + 1))
  done < <(ldd "$1" | sed -n 's/.*libgdm_[a-z_]*\.so[.0-9]* => \([^ ]*\) .*/\1/p')
  [ "$n" -ge "$2" ]
}
check "gdm loads gdm's libraries from the prefix" from_prefix "$prefix/bin/gdm" 3
check "the plugin loads gdm's libraries from the prefix" from_prefix "$libdir/meshlab/plugins/libfilter_gdm.so" 3

echo "== DESTDIR and uninstall"
DESTDIR="$work/destdir" cmake --install "$build" --prefix /opt/gdm-test >"$work/destdir.log"
outside="$(cd "$work/destdir" && find . \( -type f -o -type l \) | grep -v '^./opt/gdm-test/' || true)"
[ -z "$outside" ] && ok "DESTDIR: every file below DESTDIR/opt/gdm-test" || fail "DESTDIR: files outside: $outside"
# Uninstall as documented: remove the files the install manifest lists.
sed "s|^|$work/destdir|" "$build/install_manifest.txt" | xargs rm -f
left="$(find "$work/destdir" \( -type f -o -type l \) | head -n 5)"
[ -z "$left" ] && ok "install_manifest.txt removes every installed file" || fail "left after uninstall: $left"

echo "== pkg-config"
export PKG_CONFIG_PATH="$libdir/pkgconfig"
printf '#include "gdm/seed.h"\n#include <iostream>\nint main() { auto m = gdm::make_icosahedron({0, 0, 0}, 1.0);\n  std::cout << m.n_faces() << std::endl; return m.n_faces() == 20 ? 0 : 1; }\n' >"$work/pc.cpp"
# shellcheck disable=SC2046
check "compiled and linked with \`pkg-config --cflags --libs gdm-core\`" \
  g++ -std=c++17 "$work/pc.cpp" -o "$work/pc" $(pkg-config --cflags --libs gdm-core) -Wl,-rpath,"$libdir"
check "the pkg-config program runs" "$work/pc"
[ "$(pkg-config --variable=libdir gdm-core)" -ef "$libdir" ] && ok "gdm-core.pc is relocatable" || fail "gdm-core.pc libdir $(pkg-config --variable=libdir gdm-core)"

# A downstream project sees only the prefix: no package registry, no build tree.
downstream() {
  local name="$1"
  cmake -S "$here/test/downstream/$name" -B "$work/$name" -G Ninja -DCMAKE_BUILD_TYPE=Release \
    -DCMAKE_PREFIX_PATH="$prefix" -DCMAKE_FIND_USE_PACKAGE_REGISTRY=OFF >"$work/$name.configure.log" 2>&1 &&
    cmake --build "$work/$name" >"$work/$name.build.log" 2>&1 ||
    { cat "$work/$name.configure.log" "$work/$name.build.log" >>"$work/log"; return 1; }
  local dir
  dir="$(sed -n 's/^gdm_DIR:PATH=//p' "$work/$name/CMakeCache.txt")"
  [ "$dir" -ef "$libdir/cmake/gdm" ] || { echo "gdm_DIR=$dir, not the prefix's" >>"$work/log"; return 1; }
}
echo "== downstream C++ project (test/downstream/cpp: gdm::core + gdm::pipeline)"
check "configured and built against the prefix only" downstream cpp
check "deform_sphere: a closed genus-0 mesh with the ball's volume" "$work/cpp/deform_sphere" "$work/sphere.ply"
echo "== downstream ITK project (test/downstream/itk: reader -> smoothing -> the filter -> mesh writer)"
check "configured and built against the prefix only" downstream itk
check "phantom_to_mesh on the installed phantom: a closed mesh written" \
  "$work/itk/phantom_to_mesh" "$prefix/share/gdm/phantom.mha" "$work/phantom-itk.vtk"

echo "== the installed command and its man page"
check "gdm from the prefix on its phantom (share/gdm)" env -u GDM_DATA_DIR "$prefix/bin/gdm" --quiet -o "$work/phantom.ply"
man_page() {  # roff with every section; rendered by man when man-db is there
  zcat "$prefix/share/man/man1/gdm.1.gz" | grep -q '^\.TH GDM 1' || return 1
  for s in NAME SYNOPSIS DESCRIPTION OPTIONS '"EXIT STATUS"'; do
    zcat "$prefix/share/man/man1/gdm.1.gz" | grep -qxF ".SH $s" || { echo "man page lacks $s" >>"$work/log"; return 1; }
  done
  zcat "$prefix/share/man/man1/gdm.1.gz" | grep -qF '.B \-\-lod\-face\-area X' || return 1
  if command -v man >/dev/null; then man -l "$prefix/share/man/man1/gdm.1.gz" 2>/dev/null | grep -q -- '--lod-face-area'; fi
}
check "man page: sections and the options of gdm --help" man_page

echo "== the MeshLab plugin loaded from the prefix (staged meshlabserver, xvfb-run)"
if command -v xvfb-run >/dev/null && [ -x /usr/bin/meshlabserver ]; then
  check "scripts/meshlab-in-prefix.sh stages meshlabserver" bash "$here/scripts/meshlab-in-prefix.sh" "$prefix"
  # The committed default script (meshlab-plugin/scripts/), with the volume and T 400.
  sed -e "s|value=\"\" exts_cardinality=\"0\" name=\"volume_file\"|value=\"$prefix/share/gdm/phantom.mha\" exts_cardinality=\"0\" name=\"volume_file\"|" \
    -e 's|value="true" name="threshold_otsu"|value="false" name="threshold_otsu"|' \
    -e 's|value="0" name="threshold"|value="400" name="threshold"|' \
    "$here/meshlab-plugin/scripts/from_volume.mlx" >"$work/from_volume.mlx"
  plugin_run() {
    (cd "$work" && xvfb-run -a "$prefix/bin/meshlabserver" -o "$work/plugin.ply" -m vq -s "$work/from_volume.mlx") \
      >"$work/meshlab.log" 2>&1 || true
    grep -q "converged" "$work/meshlab.log" && [ -s "$work/plugin.ply" ] ||
      { cat "$work/meshlab.log" >>"$work/log"; return 1; }
  }
  check "meshlabserver from the prefix runs the gdm filter on the phantom" plugin_run
  faces="$(sed -n 's/^element face //p' "$work/plugin.ply" 2>/dev/null | head -n1)"
  [ "${faces:-0}" -gt 100 ] && ok "the plugin's mesh: $faces faces" || fail "the plugin's mesh has ${faces:-no} faces"
else
  echo "  skipped: no xvfb-run or no /usr/bin/meshlabserver"
fi

echo "== Debian package (cpack -G DEB)"
rm -f "$build"/gdm_*.deb
(cd "$build" && cpack -G DEB >"$work/cpack.log" 2>&1) || { cat "$work/cpack.log"; fail "cpack -G DEB"; }
deb="$(ls "$build"/gdm_*.deb 2>/dev/null | head -n1)"
if [ -n "$deb" ]; then
  ok "built $(basename "$deb")"
  dpkg-deb -c "$deb" | awk '{print $6}' | sed 's|^\./|/|' >"$work/deb.files"
  for f in /usr/bin/gdm /usr/share/gdm/phantom.mha /usr/share/man/man1/gdm.1.gz /usr/include/gdm/deformer.h \
      /usr/include/gdm/image_io.h /usr/include/gdm/itk/itkGeometricallyDeformedModelImageToMeshFilter.h \
      "/usr/lib/$multiarch/libgdm_core.so.0.1.0" "/usr/lib/$multiarch/libgdm_pipeline.so.0.1.0" \
      "/usr/lib/$multiarch/libgdm_image_io.so.0.1.0" "/usr/lib/$multiarch/cmake/gdm/gdmConfig.cmake" \
      "/usr/lib/$multiarch/pkgconfig/gdm-core.pc" "/usr/lib/$multiarch/meshlab/plugins/libfilter_gdm.so" \
      /usr/lib/cmake/ITK-5.2/Modules/GeometricallyDeformedModel.cmake; do
    grep -qxF "$f" "$work/deb.files" || fail "the .deb lacks $f"
  done
  grep -v '^/usr/' "$work/deb.files" | grep -qv '^/$' && fail "the .deb has files outside /usr" || ok "the .deb's files: all below /usr, the expected ones present"
  depends="$(dpkg-deb -f "$deb" Depends)"
  echo "  Depends: $depends"
  for p in libc6 libstdc++6 libinsighttoolkit5.2 libopenmesh; do
    grep -q "$p" <<<"$depends" || fail "Depends lacks $p"
  done
  grep -q -- "-dev" <<<"$depends" && fail "Depends names a -dev package" || ok "Depends computed by dpkg-shlibdeps (runtime packages only)"
  dpkg-deb -I "$deb" shlibs >/dev/null 2>&1 && ok "the .deb declares its shared libraries (shlibs)" || fail "no shlibs control file"
fi

if [ "$failures" -gt 0 ]; then
  echo "test-install: $failures check(s) failed" >&2
  exit 1
fi
echo "test-install: all checks passed"
