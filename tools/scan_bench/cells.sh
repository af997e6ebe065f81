#!/usr/bin/env bash
# The any/kept table of docs/BENCHMARKS.md "Scans with `--point-order any`": each shared scan
# input x bound x point order compressed with --drop-fields, then checked by `capz verify
# --against` its source. One line per archive in OUT.tsv:
#   input  bound  order  bits-a-point  bytes  verify-exit-status (0: the bound holds)
#
#   tools/scan_bench/cells.sh BUILD/capz OUT.tsv
#
# Environment: ORDS (default "kept any"), BOUNDS (default "1mm 1cm"), INPUTS (paths under
# DATA, default the three sequences and every single sweep), DATA (default ../shared/data/scan
# beside the repository). Needs /usr/bin/python3 (json) for `capz info --json`.
set -u
[ $# -eq 2 ] || { sed -n 2,11p "$0" >&2; exit 2; }
capz=$(readlink -f "$1")
out=$2
here=$(cd "$(dirname "$0")/../.." && pwd)
data=${DATA:-$here/../shared/data/scan}
ords=${ORDS:-"kept any"}
bounds=${BOUNDS:-"1mm 1cm"}
inputs=${INPUTS:-"pandar64-factory20 robosense-e1 robosense-helios16p $(cd "$data" && ls single/*.pcd)"}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
: >"$out"
for s in $inputs; do
  for e in $bounds; do
    for o in $ords; do
      if ! "$capz" compress "$data/$s" --max-error "$e" --drop-fields --point-order "$o" \
        -o "$work/x.capz" -f -q; then
        printf '%s\t%s\t%s\tFAIL\n' "$s" "$e" "$o" >>"$out"
        continue
      fi
      bits=$("$capz" info "$work/x.capz" --json |
        /usr/bin/python3 -c 'import json,sys; print(json.load(sys.stdin)["bpvf"])')
      "$capz" verify "$work/x.capz" --against "$data/$s" >/dev/null 2>&1
      held=$?
      printf '%s\t%s\t%s\t%s\t%s\t%s\n' "$(basename "$s" .pcd)" "$e" "$o" "$bits" \
        "$(stat -c %s "$work/x.capz")" "$held" >>"$out"
    done
  done
done
