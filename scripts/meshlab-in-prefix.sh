#!/usr/bin/env bash
# Lets Debian's MeshLab 2020.09 load the gdm plugin installed in a prefix other
# than /usr, without root and without touching /usr.
#
#   cmake --install build --prefix ~/gdm          # the plugin: ~/gdm/lib/x86_64-linux-gnu/meshlab/plugins
#   bash scripts/meshlab-in-prefix.sh ~/gdm       # stages ~/gdm/bin/meshlab and ~/gdm/bin/meshlabserver
#   ~/gdm/bin/meshlab                              # MeshLab with its own plugins and gdm's
#   xvfb-run -a ~/gdm/bin/meshlabserver -i in.ply -o out.ply -s script.mlx
#
# Debian's MeshLab searches plugins only in <its binary's folder>/../lib/
# x86_64-linux-gnu/meshlab/plugins (and has no per-user plugin folder), so
# this copies /usr/bin/meshlab and /usr/bin/meshlabserver into <prefix>/bin
# and links libmeshlab-common.so and MeshLab's own plugins next to gdm's.
# Undo: remove <prefix>/bin/meshlab{,server}, <prefix>/lib/x86_64-linux-gnu/meshlab/libmeshlab-common.so
# and the symbolic links in the plugins folder (they point into /usr).
set -euo pipefail
if [ $# -ne 1 ]; then
  echo "usage: $0 <prefix where gdm is installed>" >&2
  exit 2
fi
prefix="$(cd "$1" && pwd)"
system_lib="${GDM_MESHLAB_LIB_DIR:-/usr/lib/x86_64-linux-gnu/meshlab}"
lib="$prefix/lib/x86_64-linux-gnu/meshlab"
if [ ! -f "$lib/plugins/libfilter_gdm.so" ]; then
  echo "meshlab-in-prefix: no $lib/plugins/libfilter_gdm.so: install gdm (with the MeshLab plugin) into $prefix first" >&2
  exit 1
fi
if [ "$prefix" = /usr ]; then
  echo "meshlab-in-prefix: gdm is in /usr: Debian's meshlab already loads it" >&2
  exit 0
fi
if [ ! -x /usr/bin/meshlabserver ] || [ ! -f "$system_lib/libmeshlab-common.so" ]; then
  echo "meshlab-in-prefix: Debian's meshlab is not installed (apt-get install meshlab)" >&2
  exit 1
fi
mkdir -p "$prefix/bin"
for exe in meshlab meshlabserver; do
  if [ -x "/usr/bin/$exe" ]; then cp -f "/usr/bin/$exe" "$prefix/bin/$exe"; fi
done
ln -sfn "$system_lib/libmeshlab-common.so" "$lib/libmeshlab-common.so"
for p in "$system_lib"/plugins/*.so; do
  name="$(basename "$p")"
  [ "$name" = libfilter_gdm.so ] && continue
  ln -sfn "$p" "$lib/plugins/$name"
done
echo "meshlab-in-prefix: $prefix/bin/meshlab and $prefix/bin/meshlabserver load $lib/plugins/libfilter_gdm.so"
