#!/usr/bin/env bash
# Installs everything gdm needs on Debian 12 (bookworm): the build tools, the
# libraries, Debian's MeshLab and the MeshLab headers from Debian's source
# package. Idempotent: prints nothing and changes nothing when all is there.
set -euo pipefail

here="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
third_party="${GDM_THIRD_PARTY_DIR:-$here/.third_party}"

packages=(
  build-essential cmake ninja-build ccache pkg-config
  clang-14 libfuzzer-14-dev libclang-rt-14-dev
  libeigen3-dev libgtest-dev libgmock-dev libbenchmark-dev libopenmesh-dev
  libinsighttoolkit5-dev libfftw3-dev libgdcm-tools libvtk9-dev libcgal-dev
  meshlab qtbase5-dev libqt5opengl5-dev libglew-dev xvfb xauth dpkg-dev
  python3 python3-dev pybind11-dev python3-numpy python3-pytest python3-nibabel python3-meshio
  snakemake python3-yaml python3-vtk9 python3-matplotlib python3-pydicom
)

sudo_cmd=()
if [ "$(id -u)" != 0 ]; then sudo_cmd=(sudo); fi

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done

updated=0
apt_update() {
  if [ "$updated" = 0 ]; then
    # Third-party repositories on some machines may be unreachable; Debian's are what count.
    "${sudo_cmd[@]}" apt-get update -qq >/dev/null 2>&1 || true
    updated=1
  fi
}

if [ "${#missing[@]}" -gt 0 ]; then
  echo "setup: installing ${missing[*]}"
  apt_update
  DEBIAN_FRONTEND=noninteractive "${sudo_cmd[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
fi

# MeshLab 2020.09 ships no headers: take src/common and vcglib from Debian's source package.
meshlab_src="$third_party/meshlab-src"
if [ ! -f "$meshlab_src/src/common/interfaces.h" ]; then
  echo "setup: fetching the MeshLab headers from Debian's meshlab source package"
  src_list=/etc/apt/sources.list.d/gdm-deb-src.sources
  if ! grep -rqsE "^(Types:.*deb-src|deb-src)" /etc/apt/sources.list /etc/apt/sources.list.d/; then
    mirror="$( (grep -shoE 'https?://[^ ]*/debian/?$' /etc/apt/sources.list.d/*.sources /etc/apt/sources.list || true) | head -n1)"
    mirror="${mirror:-http://deb.debian.org/debian}"
    printf 'Types: deb-src\nURIs: %s\nSuites: bookworm\nComponents: main\nSigned-By: /usr/share/keyrings/debian-archive-keyring.gpg\n' \
      "$mirror" | "${sudo_cmd[@]}" tee "$src_list" >/dev/null
    updated=0
  fi
  apt_update
  work="$(mktemp -d)"
  (cd "$work" && apt-get source -qq --download-only meshlab >/dev/null 2>&1)
  dsc="$(ls "$work"/meshlab_*.dsc | head -n1)"
  (cd "$work" && dpkg-source -x "$dsc" unpacked >/dev/null)
  rm -rf "$meshlab_src"
  mkdir -p "$meshlab_src"
  cp -r "$work/unpacked/src" "$meshlab_src/src"
  cp -r "$work/unpacked/vcglib" "$meshlab_src/vcglib"
  rm -rf "$work"
fi

# --- ITK external-module CMake helpers (itk-module) -------------------------
# ITKModuleExternal.cmake, ITKModuleMacros.cmake, CreateTestDriver and friends
# are not in Debian's binary ITK package: take ITK's CMake/ folder from Debian's
# insighttoolkit5 source package (needs the deb-src entry set up above).
itk_cmake="$third_party/itk-cmake"
if [ ! -f "$itk_cmake/ITKModuleExternal.cmake" ]; then
  echo "setup: fetching ITK's CMake helpers from Debian's insighttoolkit5 source package"
  apt_update
  work="$(mktemp -d)"
  (cd "$work" && apt-get source -qq --download-only insighttoolkit5 >/dev/null 2>&1)
  orig="$(ls "$work"/insighttoolkit5_*.orig.tar.* | head -n1)"
  tar -xf "$orig" -C "$work" --wildcards '*/CMake/*'
  top="$(cd "$work" && ls -d */CMake/ITKModuleExternal.cmake | head -n1)"
  rm -rf "$itk_cmake"
  mkdir -p "$(dirname "$itk_cmake")"
  cp -r "$work/$(dirname "$top")" "$itk_cmake"
  rm -rf "$work"
fi
# --- end of the ITK external-module block -----------------------------------
