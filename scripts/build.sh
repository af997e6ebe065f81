#!/usr/bin/env bash
# Configures and builds capz (Release, ccache) into build/. Extra arguments go to cmake.
set -euo pipefail
cd "$(dirname "$0")/.."
source scripts/build_env.sh
cmake -S . -B build $(capz_generator build) -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
cmake --build build -j"$(nproc)"
