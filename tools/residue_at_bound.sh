#!/usr/bin/env bash
# Bytes of the per-window C3D residue (C3DP) in archives at the CLI's default bound, every
# shared C3D: what keeping everything but the coordinates exact costs at a bound (issue #14).
# Usage: tools/residue_at_bound.sh [CAPZ] [SHARED_C3D_DIR] > out.txt; prints a summary at the end.
set -euo pipefail
B=${1:-build/capz}
D=${2:-../shared/data/c3d}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
find "$D" -iname "*.c3d" | sort | while read -r f; do
  if "$B" compress "$f" -o "$tmp/a.capz" -f -q 2>/dev/null; then
    tot=$(stat -c %s "$tmp/a.capz")
    c=$("$B" info "$tmp/a.capz" | grep chunks: | grep -o "C3DP [0-9.]* [KMi]*B" || true)
    echo "$tot|$c|${f#"$D"/}"
  fi
done | python3 -c '
import sys, statistics
rows = []
for l in sys.stdin:
    tot, c, f = l.rstrip("\n").split("|", 2)
    b = 0.0
    if c:
        _, v, u = c.split()
        b = float(v) * {"B": 1, "KiB": 1024, "MiB": 1048576}[u]
    rows.append((b / int(tot), b, int(tot), f))
    print("%7.3f%% %8d %9d %s" % (100 * b / int(tot), b, int(tot), f))
print("files %d, with C3DP %d, median %.3f%%, worst %.2f%%, all C3DP %d of %d bytes (%.3f%%)" % (
    len(rows), sum(1 for r in rows if r[1] > 0), 100 * statistics.median(r[0] for r in rows),
    100 * max(r[0] for r in rows), sum(r[1] for r in rows), sum(r[2] for r in rows),
    100 * sum(r[1] for r in rows) / sum(r[2] for r in rows)))
'
