#!/usr/bin/env bash
# META chunk bytes (with framing) of a lossless .capz against `xz -9e` of the C3D parameter
# section it carries (the blocks from the header's parameter pointer, as many as the section's
# header says, or up to the data start when that is further), every shared C3D (issue #13 item 5). Usage: tools/meta_vs_xz.sh [CAPZ] [C3D_DIR]
set -euo pipefail
B=${1:-build/capz}
D=${2:-../shared/data/c3d}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
find "$D" -iname "*.c3d" | sort | while read -r f; do
  "$B" compress "$f" --lossless -o "$tmp/a.capz" -f -q 2>/dev/null || continue
  meta=$("$B" info "$tmp/a.capz" | grep -o "META [0-9.]* [KMi]*B" || true)
  python3 - "$f" "$tmp/p.bin" <<'PY'
import sys
import struct
a = open(sys.argv[1], 'rb').read()
p = (a[0] - 1) * 512
n = a[p + 2] * 512 if p + 2 < len(a) else 0
# The section runs to the data start (header word 9) when the file says more there than in the
# section's own block count, as older writers do.
ds = (struct.unpack('<H', a[16:18])[0] - 1) * 512 if len(a) >= 18 else 0
if a[p + 3:p + 4] == b'\x56':  # MIPS: big-endian header words
    ds = (struct.unpack('>H', a[16:18])[0] - 1) * 512
if p < ds <= len(a) and ds - p > n:
    n = ds - p
open(sys.argv[2], 'wb').write(a[p:p + n])
PY
  x=$(xz -9e -c "$tmp/p.bin" | wc -c)
  echo "$meta|$x|${f#"$D"/}"
done | python3 -c '
import sys, statistics
r = []
for l in sys.stdin:
    m, x, f = l.rstrip("\n").split("|", 2)
    if not m: continue
    _, v, u = m.split()
    b = float(v) * {"B": 1, "KiB": 1024, "MiB": 1048576}[u]
    r.append((b / int(x), b, int(x), f))
    print("%6.3f %8d %8d %s" % (b / int(x), b, int(x), f))
r.sort()
print("files %d: META / xz -9e of the parameter section: median %.3f, worst %.3f (%s), above 1: %d" % (
    len(r), statistics.median(q[0] for q in r), r[-1][0], r[-1][3], sum(1 for q in r if q[0] > 1)))
'
