#!/usr/bin/env bash
# Installs the built capz Python package (build/python/capz, scripts/build.sh makes it) for
# Debian's /usr/bin/python3, into its site-packages under /usr/local, so that
#   /usr/bin/python3 -c "import capz"
# works from anywhere. Runs as root or through sudo. PCD folders are read through the PCL module
# of the build tree (build/libcapz_pcl_io.so), so keep the build where it is.
set -euo pipefail
cd "$(dirname "$0")/.."
src=build/python/capz
if [ ! -f "$src/__init__.py" ] || ! ls "$src"/_capz*.so >/dev/null 2>&1; then
  echo "install-python.sh: $src is not built (run scripts/build.sh; needs pybind11-dev)" >&2
  exit 1
fi
dest=$(/usr/bin/python3 -c 'import site; print(site.getsitepackages()[0])')
sudo=""
[ "$(id -u)" = 0 ] || sudo=sudo
$sudo mkdir -p "$dest"
$sudo rm -rf "$dest/capz.new"
$sudo cp -r "$src" "$dest/capz.new"
$sudo rm -rf "$dest/capz"
$sudo mv "$dest/capz.new" "$dest/capz"
cd / && /usr/bin/python3 -c "import capz, sys; print('capz Python package installed:', capz.__file__)"
