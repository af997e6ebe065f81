#!/usr/bin/env bash
# The table of docs/BENCHMARKS.md "Scans: speed": capz against TMC13's octree coder with its
# default options, on pandar64-factory20's first sweep (01.pcd, a one-frame take) and on its 20
# sweeps (p20), as given (binary_compressed) and as binary PCD (the issue's frames, by `capz
# convert`), at 1 mm, each row a tools/paired_time.sh pair (whole-process CPU, user + sys,
# medians; the ratio is the median of the pairs' ratios).
#
#   tools/scan_bench/speed.sh [-n PAIRS] CAPZ [TMC3] [SCAN_DATA]
#
# CAPZ: the capz binary (its libcapz_pcl_*.so beside it); TMC3: tools/scan_bench/build_peers.sh's
# (default /work/build-peers/tmc13/tmc3/tmc3); SCAN_DATA: ../shared/data/scan. PAIRS: 3.
# TMC13 reads the same grid integers capz codes as binary PLY (frames.py: capz_step(0.001,
# max |x|), quantise), p20 as one 20-frame stream with the sequence's box (by default TMC13
# clamps later frames to the first's). Its decoder runs on its own streams. capz decodes its
# --drop-fields archives back to PCD files.
set -euo pipefail
pairs=3
[ "${1:-}" = -n ] && { pairs=$2; shift 2; }
[ $# -ge 1 ] || { sed -n 2,15p "$0"; exit 2; }
here="$(cd "$(dirname "$0")" && pwd)"
capz=$(readlink -f "$1")
tmc3=$(readlink -f "${2:-/work/build-peers/tmc13/tmc3/tmc3}")
data=$(readlink -f "${3:-$here/../../../shared/data/scan}")
[ -x "$capz" ] && [ -x "$tmc3" ] && [ -d "$data/pandar64-factory20" ] ||
  { echo "speed.sh: needs CAPZ, TMC3 and SCAN_DATA/pandar64-factory20" >&2; exit 2; }
pair="$here/../paired_time.sh"
w=$(mktemp -d)
trap 'rm -rf "$w"' EXIT
cp -r "$data/pandar64-factory20" "$w/p20"
cp "$w/p20/01.pcd" "$w/01.pcd"

# The grid integers as PLY, and the sequence's box for TMC13's options.
box=$(/usr/bin/python3 - "$here" "$w" <<'EOF'
import glob, os, sys
sys.path.insert(0, sys.argv[1])
import numpy as np
import frames as fr, pcd
w = sys.argv[2]
def plys(files, out):
    xyz = [pcd.read_xyz(f)[0] for f in files]
    xyz = [a[np.isfinite(a).all(axis=1)] for a in xyz]
    step = fr.capz_step(0.001, max(float(np.abs(a).max()) for a in xyz))
    q = [fr.quantise(a, step) for a in xyz]
    os.makedirs(out)
    for k, a in enumerate(q):
        fr.write_ply(os.path.join(out, 'f%04d.ply' % k), a.astype(np.float32))
    allq = np.concatenate(q)
    return allq.min(axis=0), allq.max(axis=0) - allq.min(axis=0) + 1
plys([os.path.join(w, '01.pcd')], os.path.join(w, 'ply1'))
lo, size = plys(sorted(glob.glob(os.path.join(w, 'p20', '*.pcd'))), os.path.join(w, 'ply20'))
print('%d,%d,%d %d,%d,%d' % (tuple(lo) + tuple(size)))
EOF
)
origin=${box% *} whd=${box#* }
enc1="$tmc3 --mode=0 --uncompressedDataPath=$w/ply1/f0000.ply --compressedStreamPath=$w/f.bin"
enc20="$tmc3 --mode=0 --uncompressedDataPath=$w/ply20/f%04d.ply --firstFrameNum=0 --frameCount=20"
enc20="$enc20 --autoSeqBbox=0 --seqOrigin=$origin --seqSizeWhd=$whd --compressedStreamPath=$w/s20.bin"
$enc1 >/dev/null 2>&1
$enc20 >/dev/null 2>&1
"$capz" compress "$w/01.pcd" --max-error 1mm --drop-fields -q -f -o "$w/swd.capz"
"$capz" compress "$w/p20" --max-error 1mm --drop-fields -q -f -o "$w/p20d.capz"
# The issue's frames: the same 20 sweeps as binary PCD (every field kept), and their archive.
"$capz" convert "$w/p20" "$w/p20b" --pcd-encoding binary -q -f
"$capz" compress "$w/p20b" --max-error 1mm --drop-fields -q -f -o "$w/p20bd.capz"

# row NAME SWEEPS TMC13_COMMAND -- CAPZ_ARGS...: one pair, one table row.
row() {
  local name=$1 sweeps=$2 vs=$3 out a b r
  shift 4
  out=$("$pair" -n "$pairs" --vs "$vs" -- "$capz" "$@")
  a=$(awk '$1 == "A:" && NF > 2 && $2 ~ /^[0-9.]+$/ { print $2 }' <<<"$out")
  b=$(awk '$1 == "B:" && NF > 2 && $2 ~ /^[0-9.]+$/ { print $2 }' <<<"$out")
  r=$(awk '/^A\/B cpu/ { print $(NF - 1) }' <<<"$out")
  printf '| %s | %s | %s | %.2f | %.3f |\n' "$name" "$a" "$b" "$r" "$(awk -v a="$a" -v n="$sweeps" 'BEGIN { print a / n }')"
}
echo "capz: $capz ($("$capz" --version 2>/dev/null | head -n 1)); $pairs pairs; $(date -u '+%F %H:%M UTC'); load $(cut -d' ' -f1-3 /proc/loadavg)"
echo
echo "| run (1 mm) | capz CPU s | TMC13 CPU s | capz / TMC13 | capz a sweep |"
echo "|---|---:|---:|---:|---:|"
row "encode one sweep, \`--drop-fields\`" 1 "$enc1" -- \
  compress "$w/01.pcd" --max-error 1mm --drop-fields -q -f -o "$w/a.capz"
row "encode one sweep, fields" 1 "$enc1" -- compress "$w/01.pcd" --max-error 1mm -q -f -o "$w/a.capz"
row "encode p20, \`--drop-fields\`" 20 "$enc20" -- \
  compress "$w/p20" --max-error 1mm --drop-fields -q -f -o "$w/a.capz"
row "encode p20, fields" 20 "$enc20" -- compress "$w/p20" --max-error 1mm -q -f -o "$w/a.capz"
row "encode p20, \`--drop-fields --no-check\` (no self-check)" 20 "$enc20" -- \
  compress "$w/p20" --max-error 1mm --drop-fields --no-check -q -f -o "$w/a.capz"
row "decode one sweep, \`--drop-fields\` archive (to .pcd)" 1 \
  "$tmc3 --mode=1 --compressedStreamPath=$w/f.bin --reconstructedDataPath=$w/dec.ply" -- \
  decompress "$w/swd.capz" -q -f -o "$w/swd.pcd"
row "decode p20, \`--drop-fields\` archive (to PCD files)" 20 \
  "$tmc3 --mode=1 --compressedStreamPath=$w/s20.bin --firstFrameNum=0 --reconstructedDataPath=$w/d%04d.ply" -- \
  decompress "$w/p20d.capz" -q -f -o "$w/p20d.out/"
row "encode p20 as binary PCD, \`--drop-fields\`" 20 "$enc20" -- \
  compress "$w/p20b" --max-error 1mm --drop-fields -q -f -o "$w/a.capz"
row "decode p20 as binary PCD, \`--drop-fields\` archive (to PCD files)" 20 \
  "$tmc3 --mode=1 --compressedStreamPath=$w/s20.bin --firstFrameNum=0 --reconstructedDataPath=$w/d%04d.ply" -- \
  decompress "$w/p20bd.capz" -q -f -o "$w/p20bd.out/"
echo
echo "TMC13's one-sweep stream: $(stat -c %s "$w/f.bin") B; p20: $(stat -c %s "$w/s20.bin") B"
