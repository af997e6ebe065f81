#!/usr/bin/env bash
# The table of docs/BENCHMARKS.md "Scans: memory" (issue #37's target: a 1000-frame sequence
# peaks where a 50-frame one does): peak resident set (GNU time's %M) of compress, verify,
# decompress and convert on folders of 50 and 1000 sweeps, hard links cycling through
# pandar64-factory20's 20 sweeps (113k points each, binary_compressed PCD) under new names.
#
#   tools/scan_bench/memory.sh CAPZ [SCAN_DATA] [COUNTS]
#
# CAPZ: the capz binary (its libcapz_pcl_*.so beside it); SCAN_DATA: ../shared/data/scan;
# COUNTS: the folder sizes, "50 1000" by default. The work folder is made beside the system's
# temporary files (1000 hard links, archives, and the decoded and converted folders: about 2 GB).
set -euo pipefail
[ $# -ge 1 ] || { sed -n 2,11p "$0"; exit 2; }
here="$(cd "$(dirname "$0")" && pwd)"
capz=$(readlink -f "$1")
data=$(readlink -f "${2:-$here/../../../shared/data/scan}")
counts=${3:-50 1000}
[ -x "$capz" ] && [ -d "$data/pandar64-factory20" ] ||
  { echo "memory.sh: needs CAPZ and SCAN_DATA/pandar64-factory20" >&2; exit 2; }
w=$(mktemp -d)
trap 'rm -rf "$w"' EXIT
cp -r "$data/pandar64-factory20" "$w/src"
fr=("$w"/src/*.pcd)

# peak LABEL COMMAND...: the command's peak RSS in MB (10^6 bytes), and its CPU seconds.
peak() {
  shift
  /usr/bin/time -f "%M %U %S" -o "$w/t" "$@" >/dev/null 2>"$w/err" ||
    { echo "memory.sh: failed: $*" >&2; tail -n 3 "$w/err" >&2; exit 1; }
  awk '{ printf "%.1f MB (%.1f s)", $1 * 1024 / 1e6, $2 + $3 }' "$w/t"
}

declare -A m
for n in $counts; do
  d="$w/p$n"
  mkdir -p "$d"
  for ((i = 0; i < n; i++)); do ln "${fr[$((i % ${#fr[@]}))]}" "$d/$(printf f%05d.pcd "$i")"; done
  m[c1mm,$n]=$(peak c "$capz" compress "$d" --max-error 1mm --drop-fields -q -f -o "$w/a$n.capz")
  m[c1cm,$n]=$(peak c "$capz" compress "$d" --max-error 1cm --drop-fields --point-order any -q -f \
    -o "$w/b$n.capz")
  m[ver,$n]=$(peak v "$capz" verify "$w/a$n.capz" --against "$d" -q)
  m[dec,$n]=$(peak d "$capz" decompress "$w/a$n.capz" -q -f -o "$w/out$n/")
  rm -rf "$w/out$n"
  m[ply,$n]=$(peak p "$capz" convert "$d" "$w/ply$n/" --to ply -q -f)
  rm -rf "$w/ply$n" "$w/b$n.capz"
done

echo "capz: $capz; $(date -u '+%F %H:%M UTC'); load $(cut -d' ' -f1-3 /proc/loadavg)"
echo
printf '| run |'; for n in $counts; do printf ' %s sweeps |' "$n"; done; echo
printf '|---|'; for n in $counts; do printf -- '---:|'; done; echo
for r in "c1mm:compress, 1 mm, \`--drop-fields\`" \
  "c1cm:compress, 1 cm, \`--drop-fields --point-order any\`" \
  "ver:verify \`--against\` the folder" "dec:decompress to a PCD folder" \
  "ply:convert to a PLY folder"; do
  printf '| %s |' "${r#*:}"
  for n in $counts; do printf ' %s |' "${m[${r%%:*},$n]}"; done
  echo
done
