#!/usr/bin/env bash
# Builds the scan benchmark's outside peers out of the repository tree (never needed by CI):
#   TMC13 (MPEG G-PCC reference)  -> $OUT/tmc13/tmc3/tmc3
#   Cloudini's library + our probe -> $OUT/cloudini/libcloudini_lib.a, $OUT/scan_cloudini
# Usage: tools/scan_bench/build_peers.sh [OUT=/work/build-peers]
# The sources are the copies in ../shared/third_party (see their ORIGIN.md); -j2 on a shared machine.
set -euo pipefail
here="$(cd "$(dirname "$0")" && pwd)"
root="$(cd "$here/../.." && pwd)"
tp="${THIRD_PARTY:-$root/../shared/third_party}"
[ -d "$tp/mpeg-pcc-tmc13" ] || tp=/work/shared/third_party
out="${1:-/work/build-peers}"
mkdir -p "$out"

if [ ! -x "$out/tmc13/tmc3/tmc3" ]; then
  cmake -S "$tp/mpeg-pcc-tmc13" -B "$out/tmc13" -DCMAKE_BUILD_TYPE=Release >/dev/null
  cmake --build "$out/tmc13" -j2
fi

if [ ! -f "$out/cloudini/libcloudini_lib.a" ]; then
  cmake -S "$tp/cloudini/cloudini_lib" -B "$out/cloudini" -DCMAKE_BUILD_TYPE=Release \
        -DCLOUDINI_FORCE_VENDORED_DEPS=OFF -DCLOUDINI_BUILD_TOOLS=OFF -DBUILD_TESTING=OFF >/dev/null
  cmake --build "$out/cloudini" -j2
fi

# Our own probe (tools/scan_bench/scan_cloudini.cpp) against Cloudini's public API.
if [ "$here/scan_cloudini.cpp" -nt "$out/scan_cloudini" ] || [ ! -x "$out/scan_cloudini" ]; then
  inc=()
  for d in "$tp/cloudini/cloudini_lib/include" "$out/cloudini/include" "$out/cloudini"; do
    [ -d "$d" ] && inc+=("-I$d")
  done
  g++ -std=c++20 -O2 -DNDEBUG "${inc[@]}" "$here/scan_cloudini.cpp" "$out/cloudini/libcloudini_lib.a" \
      -lzstd -llz4 -o "$out/scan_cloudini"
fi
echo "peers in $out: tmc13/tmc3/tmc3 scan_cloudini"
