#!/usr/bin/env bash
# Point fields of scan sequences (frames of their own point counts, format 1.1): what keeping
# them costs in the archive, against xz -9e of the field bytes alone.
#
#   tools/scan_fields_bench.sh build/capz [SCAN_DATA] [WORKDIR]
#
# Per sequence of SCAN_DATA (default ../shared/data/scan: its folders of PCD frames whose point
# counts differ) and bound (1 mm, 1 cm): the archive's bytes with --drop-fields and with the
# fields kept, both in bits per point (all frames), the fields' bits per point (the difference),
# and xz -9e of the field bytes alone: each field's bytes in point order (frames concatenated, as
# the take and ATTR hold them; taken from the frames decompressed as binary PCD, which are the
# source's fields byte for byte), one xz -9e -T1 stream per field, summed.
#
# ATTR_ERROR=NAME=B[,NAME=B...] (environment): the fields kept with --attr-error, each NAME=B
# used on the sequences that have a float field NAME (the others' fields stay exact); the xz
# column stays that of the exact fields.
set -euo pipefail
capz=$(readlink -f "$1")
data=${2:-$(dirname "$0")/../../shared/data/scan}
work=${3:-$(mktemp -d)}
mkdir -p "$work"
py=/usr/bin/python3
# Every field but x y z of a folder of binary PCD frames, one file per field in $2.
split_fields() {
  $py - "$1" "$2" <<'PY'
import os, sys
src, out = sys.argv[1], sys.argv[2]
cols = {}
for name in sorted(os.listdir(src)):
    b = open(os.path.join(src, name), 'rb').read()
    head, pos = {}, 0
    while True:
        end = b.index(b'\n', pos)
        line = b[pos:end].decode().split()
        pos = end + 1
        if line and not line[0].startswith('#'):
            head[line[0]] = line[1:]
        if line and line[0] == 'DATA':
            break
    assert head['DATA'] == ['binary'], name
    sizes = [int(s) * int(c) for s, c in zip(head['SIZE'], head['COUNT'])]
    stride, n = sum(sizes), int(head['POINTS'][0])
    body, off = b[pos:pos + stride * n], 0
    for f, s in zip(head['FIELDS'], sizes):
        if f not in ('x', 'y', 'z'):
            col = bytearray(s * n)
            for k in range(s):
                col[k::s] = body[off + k::stride]
            cols.setdefault(f, bytearray()).extend(col)
        off += s
for i, (f, col) in enumerate(cols.items()):
    open(os.path.join(out, '%02d_%s.raw' % (i, f)), 'wb').write(col)
PY
}
echo "| sequence | points | bound | capz --drop-fields (bpp) | capz, fields kept (bpp) | fields (bpp) | xz -9e of the fields (bpp) | fields / xz |"
echo "|---|---:|---|---:|---:|---:|---:|---:|"
for d in "$data"/*/; do
  s=$(basename "$d")
  [ "$s" = single ] && continue
  for b in 1mm 1cm; do
    "$capz" compress "$d" --max-error $b --drop-fields -o "$work/$s.$b.drop.capz" -f -q
    ae=()
    if [ -n "${ATTR_ERROR:-}" ]; then
      first=$(ls "$d" | head -1)
      # The float fields of the sequence (its first frame's header), then the bounds that name one.
      floats=$(head -c 4096 "$d/$first" | tr -d '\r' | awk '$1=="FIELDS"{n=NF; for(i=2;i<=NF;i++) f[i]=$i}
        $1=="TYPE"{for(i=2;i<=NF;i++) if($i=="F") print f[i]}' | grep -vx '[xyz]' || true)
      keep=$(echo "$ATTR_ERROR" | tr ',' '\n' | while IFS== read -r name bound; do
        if echo "$floats" | grep -qx "$name"; then echo "$name=$bound"; fi; done | paste -sd, -)
      if [ -n "$keep" ]; then ae=(--attr-error "$keep"); fi
    fi
    "$capz" compress "$d" --max-error $b "${ae[@]}" -o "$work/$s.$b.capz" -f -q
    n=$("$capz" info "$work/$s.$b.capz" | sed -n 's/.*, \([0-9]*\) points in all.*/\1/p')
    if [ ! -f "$work/$s.fields.xz" ]; then
      rm -rf "$work/$s.bin" "$work/$s.raw"
      mkdir -p "$work/$s.raw"
      "$capz" decompress "$work/$s.$b.capz" -o "$work/$s.bin/" --pcd-data binary -f -q
      split_fields "$work/$s.bin" "$work/$s.raw"
      x=0
      for f in "$work/$s.raw"/*.raw; do x=$((x + $(xz -9e -T1 -c "$f" | wc -c))); done
      echo $x >"$work/$s.fields.xz"
    fi
    x=$(cat "$work/$s.fields.xz")
    a=$(stat -c %s "$work/$s.$b.drop.capz")
    k=$(stat -c %s "$work/$s.$b.capz")
    $py -c "a,k,x,n=$a,$k,$x,$n; print('| %s | %d | %s | %.2f | %.2f | %.2f | %.2f | %.2f |' % ('$s', n, '$b', 8*a/n, 8*k/n, 8*(k-a)/n, 8*x/n, (k-a)/x))"
  done
done
