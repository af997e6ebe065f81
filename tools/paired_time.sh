#!/usr/bin/env bash
# Two commands timed as whole processes, in turn, with GNU time (the method of the paired CPU
# figures in docs/BENCHMARKS.md "Scans: speed"):
#
#   tools/paired_time.sh [-n RUNS] [--warmup W] [--vs 'COMMAND_B'] -- COMMAND_A [ARG ...]
#
# W warm-up runs of each command (default 1, not counted), then A B A B ... RUNS times each
# (default 5). Printed for each command: median [min-max] of CPU seconds (user + sys of the
# finished process, start-up included), wall seconds and peak RSS in MiB, all from
# /usr/bin/time -f "%e %U %S %M" (10 ms resolution); then the median [min-max] of the pairs'
# CPU ratios A/B (pairing keeps the ratio meaningful when the machine's speed drifts). Quote
# medians. COMMAND_B is one string split into words as the shell splits them (quotes honoured,
# no globbing; it is eval'd, so $ and backquotes expand): a command that needs a pipe or a
# redirection is written sh -c '...', e.g. --vs "sh -c 'yes | head -c 1000000 >/dev/null'".
# Standard input is /dev/null and the commands' output is discarded. Exit status: 1 if a run
# exits non-zero (the last lines of its stderr are shown), 2 on unusable arguments.
set -euo pipefail
me=paired_time.sh runs=5 warmup=1 vs="" b=()
usage() { echo "usage: tools/$me [-n RUNS] [--warmup W] [--vs 'COMMAND_B'] -- COMMAND_A [ARG ...]" >&2; exit 2; }
while [ $# -gt 0 ]; do
  case "$1" in
    -n) [ $# -ge 2 ] || usage; runs=$2; shift 2 ;;
    --warmup) [ $# -ge 2 ] || usage; warmup=$2; shift 2 ;;
    --vs) [ $# -ge 2 ] || usage; vs=$2; shift 2 ;;
    --) shift; break ;;
    -h|--help) sed -n 2,16p "$0"; exit 0 ;;
    -*) echo "$me: unknown option $1" >&2; usage ;;
    *) break ;;
  esac
done
[ $# -gt 0 ] || usage
[[ $runs =~ ^[1-9][0-9]*$ && $warmup =~ ^[0-9]+$ ]] || { echo "$me: RUNS >= 1, W >= 0" >&2; exit 2; }
if [ -n "$vs" ]; then
  set -f
  eval "b=($vs)" || { echo "$me: cannot split --vs '$vs'" >&2; exit 2; }
  set +f
  [ ${#b[@]} -gt 0 ] || usage
fi
[ -x /usr/bin/time ] || { echo "$me: needs GNU time at /usr/bin/time" >&2; exit 2; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# timed TAG ROUND COMMAND...: one run; appends "TAG ROUND wall user sys KiB" to $tmp/log.
timed() {
  local tag=$1 round=$2 st=0
  shift 2
  /usr/bin/time -f "%e %U %S %M" -o "$tmp/t" "$@" </dev/null >/dev/null 2>"$tmp/err" || st=$?
  if [ "$st" -ne 0 ]; then
    [[ $round == w* ]] && round="warm-up ${round#w}" || round="run $round"
    echo "$me: $tag ($round) exited with status $st: $*" >&2
    tail -n 5 "$tmp/err" >&2
    exit 1
  fi
  echo "$tag $round $(tail -n 1 "$tmp/t")" >>"$tmp/log"
}

for ((i = 1; i <= warmup; i++)); do
  timed A "w$i" "$@"
  [ ${#b[@]} -eq 0 ] || timed B "w$i" "${b[@]}"
done
: >"$tmp/log"
for ((i = 1; i <= runs; i++)); do
  timed A "$i" "$@"
  [ ${#b[@]} -eq 0 ] || timed B "$i" "${b[@]}"
done

echo "A: $*"
[ ${#b[@]} -eq 0 ] || echo "B: $vs"
awk -v runs="$runs" -v warmup="$warmup" -v paired=${#b[@]} '
  function stat(a, n, f,   i, j, x, m) {   # "median [min-max]" of a[1..n]
    for (i = 2; i <= n; i++) { x = a[i]; for (j = i - 1; j >= 1 && a[j] > x; j--) a[j + 1] = a[j]; a[j + 1] = x }
    m = n % 2 ? a[(n + 1) / 2] : (a[n / 2] + a[n / 2 + 1]) / 2
    return sprintf(f " [" f "-" f "]", m, a[1], a[n])
  }
  { cpu[$1, $2] = $4 + $5; wall[$1, $2] = $3; kib[$1, $2] = $6 }
  END {
    printf "%s runs%s, %d warm-up each; median [min-max]\n", runs, paired ? " in turn (A B A B ...)" : "", warmup
    printf "%-3s %-26s %-26s %s\n", "", "cpu s (user + sys)", "wall s", "peak MiB"
    for (t = 1; t <= (paired ? 2 : 1); t++) {
      tag = t == 1 ? "A" : "B"
      for (i = 1; i <= runs; i++) { c[i] = cpu[tag, i]; w[i] = wall[tag, i]; k[i] = kib[tag, i] / 1024 }
      printf "%-3s %-26s %-26s %s\n", tag ":", stat(c, runs, "%.3f"), stat(w, runs, "%.3f"), stat(k, runs, "%.1f")
    }
    if (!paired) exit
    n = 0
    for (i = 1; i <= runs; i++) if (cpu["B", i] > 0) r[++n] = cpu["A", i] / cpu["B", i]
    if (n) printf "A/B cpu, median of %d pairs: %s\n", n, stat(r, n, "%.3f")
    else print "A/B cpu: n/a (B under /usr/bin/time'"'"'s 10 ms in every pair)"
  }' "$tmp/log"
