#!/usr/bin/env bash
# Point-field sequences (issue #15): capz against xz -9e and zstd -19 of the same binary PCD
# frames, lossless and at a bound, with encode / decode CPU speed. The sequences are made by
# tools/make_scan_sequences.py (a depth camera rendering a shared mesh animation, a spinning
# LiDAR, and one driven through the scene), so every figure is reproducible from the command below.
#
#   tools/fields_bench.sh build/capz [SHARED_DATA] [WORKDIR]
#
# Prints a markdown table: bytes of the frames, of xz -9e and zstd -19 of them (the frames
# concatenated, as `cat *.pcd | xz -9e`), and of capz (lossless, and --max-error 0.001 in the
# data's units with every field still lossless), each as a ratio to xz; the point fields'
# share of the capz archive (attribute_bytes); CPU seconds to encode and decode.
set -euo pipefail
capz=$(readlink -f "$1")
shared=${2:-$(dirname "$0")/../../shared/data}
work=${3:-$(mktemp -d)}
py=/usr/bin/python3
gen="$(dirname "$0")/make_scan_sequences.py"
mkdir -p "$work"
[ -d "$work/depth" ] || $py "$gen" depth "$shared/pcd/horse-gallop" "$work/depth" --frames 40 --width 160 --height 120
[ -d "$work/lidar" ] || $py "$gen" lidar "$work/lidar" --frames 40 --rings 16 --steps 720
# A driven LiDAR (points in sensor order, the scene sliding by) with a reflectivity field: where
# ATTR's nearest-earlier-point predictors (FORMAT.md 13.5) have something to find.
[ -d "$work/lidar_drive" ] || $py "$gen" lidar "$work/lidar_drive" --frames 40 --rings 16 --steps 720 \
  --order azimuth --drive 0.5 --reflectivity
echo "| sequence | frames x points | fields | frames (bytes) | xz -9e | zstd -19 | capz lossless | x xz | capz 0.001 | x xz | fields share (lossless) | encode s | decode s |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|"
for s in depth lidar lidar_drive; do
  d="$work/$s"
  raw=$(cat "$d"/*.pcd | wc -c)
  xz=$(cat "$d"/*.pcd | xz -9e -T1 -c | wc -c)
  zs=$(cat "$d"/*.pcd | zstd -19 -q -c | wc -c)
  t0=$(date +%s.%N)
  j=$("$capz" compress "$d" -o "$work/$s.l.capz" -f --lossless --json)
  t1=$(date +%s.%N)
  "$capz" decompress "$work/$s.l.capz" -o "$work/$s.back/" -f -q
  t2=$(date +%s.%N)
  "$capz" compress "$d" -o "$work/$s.b.capz" -f --max-error 0.001 -q
  l=$(stat -c %s "$work/$s.l.capz")
  b=$(stat -c %s "$work/$s.b.capz")
  ab=$(echo "$j" | $py -c 'import json,sys; print(json.load(sys.stdin)["attribute_bytes"])')
  shape=$("$capz" info --json "$d" | $py -c 'import json,sys; j=json.load(sys.stdin); print("%d x %d" % (j["frames"], j["points"]))')
  fields=$("$capz" info --json "$d" | $py -c 'import json,sys; j=json.load(sys.stdin); print(" ".join(f["name"] for f in j["variant"]["fields"][3:]))')
  # Every coordinate and every field byte back (capz verify: the archive's promise, fields
  # included), and the decompressed folder reads back to the same take.
  "$capz" verify "$work/$s.l.capz" --against "$d" -q
  "$capz" verify "$work/$s.l.capz" --against "$work/$s.back" -q
  "$capz" verify "$work/$s.b.capz" --against "$d" -q
  $py - "$s" "$shape" "$fields" "$raw" "$xz" "$zs" "$l" "$b" "$ab" "$t0" "$t1" "$t2" <<'PY'
import sys
s, shape, fields, raw, xz, zs, l, b, ab, t0, t1, t2 = sys.argv[1:]
raw, xz, zs, l, b, ab = map(int, (raw, xz, zs, l, b, ab))
print(f"| {s} | {shape} | {fields} | {raw:,} | {xz:,} | {zs:,} | {l:,} | {l/xz:.3f} | {b:,} | {b/xz:.3f} | {ab/l:.0%} | {float(t1)-float(t0):.2f} | {float(t2)-float(t1):.2f} |")
PY
done
