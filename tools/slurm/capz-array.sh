#!/bin/bash
# capz on a Slurm job array: one list of takes per array task (docs/ARCHIVE.md).
#
#   tools/slurm/capz-array.sh --split TAKES.txt K LISTS     # once: TAKES.txt (one path a line)
#                                                           # cut into LISTS/list.0 .. list.K-1
#   sbatch --array=0-$((K-1)) tools/slurm/capz-array.sh LISTS [capz compress options...]
#
# Task i runs `capz compress` on every take of LISTS/list.i (-T: the task's CPUs), with the
# options given after LISTS (e.g. --lossless --output-dir-mirror /archive/capz), and writes
# LISTS/report.i.jsonl (one JSON line per take; `ok` false for a take that failed). A task exits
# non-zero when any of its takes failed; the others still have their outputs. Outputs are never
# overwritten without -f, so a requeued task reports the takes it already did as failures:
# rerun it with -f, or drop the done takes from its list. CAPZ names the capz binary (default:
# capz on PATH).
#SBATCH --job-name=capz
#SBATCH --cpus-per-task=2
#SBATCH --output=capz-%A_%a.out
set -euo pipefail

if [[ "${1:-}" == "--split" ]]; then
  [[ $# -eq 4 ]] || { echo "usage: $0 --split TAKES.txt K LISTS" >&2; exit 1; }
  takes=$2 k=$3 lists=$4
  [[ "$k" =~ ^[1-9][0-9]*$ ]] || { echo "$0: K must be a positive number, got '$k'" >&2; exit 1; }
  mkdir -p "$lists"
  for ((i = 0; i < k; i++)); do : >"$lists/list.$i"; done
  # Round robin, so every list gets takes of every part of the archive.
  awk -v k="$k" -v dir="$lists" 'NF { print > (dir "/list." ((n++) % k)) }' "$takes"
  exit 0
fi

[[ $# -ge 1 ]] || { echo "usage: $0 LISTS [capz compress options...]  (or --split)" >&2; exit 1; }
lists=$1
shift
: "${SLURM_ARRAY_TASK_ID:?not set: run under sbatch --array (or set it as Slurm would)}"
list="$lists/list.$SLURM_ARRAY_TASK_ID"
[[ -f "$list" ]] || { echo "$0: no $list for task $SLURM_ARRAY_TASK_ID" >&2; exit 1; }
mapfile -t takes < <(grep -v '^[[:space:]]*$' "$list")
if [[ ${#takes[@]} -eq 0 ]]; then
  echo "$0: $list is empty: nothing to do" >&2
  exit 0
fi
exec "${CAPZ:-capz}" compress -q -T "${SLURM_CPUS_PER_TASK:-1}" \
  --report "$lists/report.$SLURM_ARRAY_TASK_ID.jsonl" "$@" -- "${takes[@]}"
