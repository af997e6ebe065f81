#!/usr/bin/env bash
# Installs what capz needs to build, test and benchmark on Debian 12, if it is missing.
# Runs as root or through sudo. Safe to run again: installed packages are skipped.
set -euo pipefail
pkgs=(build-essential cmake ninja-build ccache pkg-config
      libpcl-dev libeigen3-dev libflann-dev libboost-program-options-dev libgtest-dev
      libxxhash-dev libzstd-dev liblzma-dev pybind11-dev python3-dev python3-pytest
      clang libclang-rt-14-dev clang-format
      xz-utils zstd zfp fpzip-utils draco flac wavpack python3 python3-matplotlib python3-numpy
      parallel slurm-wlm munge)
missing=()
for p in "${pkgs[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  exit 0
fi
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO=sudo
echo "installing: ${missing[*]}" >&2
$SUDO apt-get update -qq
DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
