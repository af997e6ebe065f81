#!/bin/bash
# Batch speed of `capz compress` / `capz decompress` with -T 1 against -T N, whole processes,
# side by side in one run (issue 17: a batch of 50 takes with -T 2 at least 1.8x faster than one
# at a time). Prints a markdown table (best of REPS wall times) and checks that the archives and
# the decompressed files are the same bytes for both thread counts.
#
#   tools/batch_speed.sh CAPZ TAKES_DIR [COUNT=50] [THREADS=2] [REPS=3] [capz compress options...]
#
# TAKES_DIR: the first COUNT .c3d / .trc files below it (sorted) are copied to a temporary folder.
set -euo pipefail
[[ $# -ge 2 ]] || { sed -n '2,9p' "$0" >&2; exit 1; }
capz=$(readlink -f "$1") src=$2 count=${3:-50} threads=${4:-2} reps=${5:-3}
shift $(($# < 5 ? $# : 5))
work=$(mktemp -d "${TMPDIR:-/tmp}/capz-batch-speed-XXXXXX")
trap 'rm -rf "$work"' EXIT
mkdir "$work/in"
i=0
while IFS= read -r -d '' f; do
  i=$((i + 1))
  ext=${f##*.}
  cp "$f" "$work/in/$(printf 'take%03d' "$i").${ext,,}"
done < <(find "$src" -type f \( -iname '*.c3d' -o -iname '*.trc' \) -print0 | sort -z | head -z -n "$count")
[[ $i -gt 0 ]] || { echo "no .c3d or .trc below $src" >&2; exit 1; }
mb=$(du -sm "$work/in" | cut -f1)

# best wall seconds of REPS runs of: capz ARGS (outputs into a fresh folder OUT each time)
best() {
  local out=$1 b=""
  shift
  for ((r = 0; r < reps; r++)); do
    rm -rf "$out"
    local t0 t1
    t0=$(date +%s.%N)
    "$capz" "$@" --output-dir-mirror "$out" >/dev/null
    t1=$(date +%s.%N)
    b=$(echo "$t0 $t1 ${b:-1e9}" | awk '{ d = $2 - $1; print (d < $3 ? d : $3) }')
  done
  echo "$b"
}

cd "$work"
c1=$(best z1 compress -q -r -T 1 "$@" in)
cn=$(best zn compress -q -r -T "$threads" "$@" in)
diff -r z1 zn >/dev/null || { echo "archives differ between -T 1 and -T $threads" >&2; exit 1; }
d1=$(best d1 decompress -q -r -T 1 z1)
dn=$(best dn decompress -q -r -T "$threads" z1)
diff -r d1 dn >/dev/null || { echo "decompressed files differ between -T 1 and -T $threads" >&2; exit 1; }
echo "$i takes, $mb MB, $(nproc) cores, capz compress options: ${*:-(defaults)}"
echo
echo "| command | -T 1 (s) | -T $threads (s) | speedup |"
echo "|---|---|---|---|"
awk -v a="$c1" -v b="$cn" 'BEGIN { printf "| compress | %.2f | %.2f | %.2fx |\n", a, b, a / b }'
awk -v a="$d1" -v b="$dn" 'BEGIN { printf "| decompress | %.2f | %.2f | %.2fx |\n", a, b, a / b }'
