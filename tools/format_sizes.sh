#!/usr/bin/env bash
# Two capz binaries' archive sizes on every shared take: each C3D and TRC file and each PCD
# folder under ../shared/data (c3d/, trc/, pcd/), compressed at the defaults and with --lossless.
#
#   tools/format_sizes.sh --base OLD_CAPZ --new NEW_CAPZ [--work DIR] [--out FILE.tsv]
#
# Writes one line per take and target (take, target, base bytes, new bytes, new - base, whether
# the two archives agree byte for byte after their 15-byte file headers) to FILE.tsv (default
# WORK/sizes.tsv), checks that the new binary's --lossless archive decompresses to the original
# bytes (each file, or each frame file of a folder), and prints the totals, the largest growth
# and the count of takes beyond max(0.5%, 100 B). Takes the base cannot compress are listed and
# left out of the totals. Fails when a --lossless round trip differs.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
base="" new="" work=${TMPDIR:-/tmp}/capz-format-sizes out=""
while [ $# -gt 0 ]; do
  case "$1" in
    --base) base=$2; shift 2 ;;
    --new) new=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --out) out=$2; shift 2 ;;
    -h|--help) sed -n 2,12p "$0"; exit 0 ;;
    *) echo "format_sizes.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
data=$here/../shared/data
for f in "$base" "$new" "$data"; do
  [ -n "$f" ] && [ -e "$f" ] || { echo "format_sizes.sh: missing ${f:-a --base or --new binary}" >&2; exit 2; }
done
mkdir -p "$work"
out=${out:-$work/sizes.tsv}
: > "$out"
fails=0
takes() {
  find "$data/c3d" "$data/trc" -type f \( -iname '*.c3d' -o -iname '*.trc' \) | sort
  for d in "$data"/pcd/*/; do [ -n "$(find "$d" -maxdepth 1 -name '*.pcd' -print -quit)" ] && echo "${d%/}"; done
}
while IFS= read -r take; do
  name=${take#"$data"/}
  for target in default lossless; do
    opt=()
    [ "$target" = lossless ] && opt=(--lossless)
    rm -rf "$work/b.capz" "$work/n.capz" "$work/back"
    if ! "$base" compress "$take" -o "$work/b.capz" -f -q "${opt[@]}" 2>/dev/null; then
      printf '%s\t%s\tfailed\t-\t-\t-\n' "$name" "$target" >> "$out"
      continue
    fi
    "$new" compress "$take" -o "$work/n.capz" -f -q "${opt[@]}"
    b=$(stat -c %s "$work/b.capz") n=$(stat -c %s "$work/n.capz")
    same=no
    cmp -s <(tail -c +16 "$work/b.capz") <(tail -c +16 "$work/n.capz") && same=yes
    printf '%s\t%s\t%d\t%d\t%d\t%s\n' "$name" "$target" "$b" "$n" "$((n - b))" "$same" >> "$out"
    if [ "$target" = lossless ]; then
      if [ -d "$take" ]; then
        "$new" decompress "$work/n.capz" -o "$work/back" -f -q
        diff -rq "$take" "$work/back" >/dev/null || { echo "lossless differs: $name" >&2; fails=$((fails + 1)); }
      else
        back=$work/back.${take##*.}
        "$new" decompress "$work/n.capz" -o "$back" -f -q
        cmp -s "$take" "$back" || { echo "lossless differs: $name" >&2; fails=$((fails + 1)); }
        rm -f "$back"
      fi
    fi
  done
done < <(takes)
python3 - "$out" <<'PY'
import sys
rows = [l.rstrip('\n').split('\t') for l in open(sys.argv[1])]
ok = [r for r in rows if r[2] != 'failed']
for target in ('default', 'lossless'):
    rs = [r for r in ok if r[1] == target]
    b = sum(int(r[2]) for r in rs); n = sum(int(r[3]) for r in rs)
    worst = max(rs, key=lambda r: int(r[4]) / max(int(r[2]), 1))
    over = [r for r in rs if int(r[4]) > max(0.005 * int(r[2]), 100)]
    same = sum(r[5] == 'yes' for r in rs)
    print('%-8s %3d takes: base %d B, new %d B (%+d B, %+.4f%%); payload identical after the '
          'header in %d; largest change %s %+d B (%+.4f%%); beyond max(0.5%%, 100 B): %d'
          % (target, len(rs), b, n, n - b, 100.0 * (n - b) / b, same, worst[0], int(worst[4]),
             100.0 * int(worst[4]) / int(worst[2]), len(over)))
failed = [r[0] + ' ' + r[1] for r in rows if r[2] == 'failed']
if failed:
    print('the base binary failed on %d: %s' % (len(failed), ', '.join(failed)))
PY
[ "$fails" = 0 ] || { echo "format_sizes.sh: $fails --lossless round trips differ" >&2; exit 1; }
