#!/usr/bin/env bash
# Threads inside one take (capz compress/decompress -T N), timed as whole processes.
#
#   tools/threads_bench.sh [--build DIR] [--work DIR] [--minutes M] [--runs N] [--threads "1 2"]
#
# The take: tools/capz_synth loops the real take c3d/c3dorg/sample_37/ART-Human_2persons_integer.c3d
# (../shared/data) forwards and backwards into M minutes (default 10) at 200 Hz, 100 markers,
# float C3D (120,000 frames, 144 MB of raw float32 positions for 10 minutes). Each run is one
# process: `capz compress take.c3d -o t.capz -f -q -T N` (default bound 0.1 mm, with the
# self-check, HASH and residue) and `capz decompress t.capz -o t.c3d -f -q -T N` (the original
# rebuilt at the bound). The thread counts run in turn, A B A B ..., N runs each (default 7), so a drift of
# the shared machine hits all of them alike; the table gives medians of wall and CPU (user + sys)
# seconds, MB/s of raw float32 positions per wall second, and each count's median wall-time
# speed-up over the first count computed pair by pair (same round).
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
build=$here/build
work=${TMPDIR:-/tmp}/capz-threads-bench
minutes=10
runs=7
threads="1 2"
while [ $# -gt 0 ]; do
  case "$1" in
    --build) build=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --minutes) minutes=$2; shift 2 ;;
    --runs) runs=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    -h|--help) sed -n 2,14p "$0"; exit 0 ;;
    *) echo "threads_bench.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
capz=$build/capz
synth=$build/tools/capz_synth
src=$here/../shared/data/c3d/c3dorg/sample_37/ART-Human_2persons_integer.c3d
for f in "$capz" "$synth" "$src"; do
  [ -e "$f" ] || { echo "threads_bench.sh: missing $f" >&2; exit 2; }
done
mkdir -p "$work"
. "$here/tools/bench_common.sh"
take=$(bench_take "$synth" "$src" "$work" "$minutes")
"$capz" compress "$take" -o "$work/ref.capz" -f -q
raw=$("$capz" info "$work/ref.capz" --json | python3 -c \
  'import json,sys; j=json.load(sys.stdin); print(j["frames"]*j["points"]*12)')

# One timed process: appends "op threads round wall cpu" to the log.
log=$work/times.txt
: > "$log"
timed() { bench_timed "$log" "$@"; }  # op threads round command...
for op in compress decompress; do
  for r in $(seq 0 "$runs"); do  # round 0 is a warm-up, not counted
    for t in $threads; do
      if [ "$op" = compress ]; then
        timed compress "$t" "$r" "$capz" compress "$take" -o "$work/t$t.capz" -f -q -T "$t"
      else
        timed decompress "$t" "$r" "$capz" decompress "$work/ref.capz" -o "$work/t$t.c3d" -f -q \
          -T "$t"
      fi
    done
  done
  first=${threads%% *}
  for t in $threads; do  # the outputs never depend on the thread count
    if [ "$op" = compress ]; then
      cmp "$work/t$t.capz" "$work/ref.capz"
    else
      cmp "$work/t$t.c3d" "$work/t$first.c3d"
    fi
  done
done

python3 - "$log" "$raw" "$minutes" "$threads" <<'PY'
import statistics, sys
log, raw, minutes, threads = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4].split()
rows = [l.split() for l in open(log)]
print(f"take: {minutes} min, {raw / 1e6:.1f} MB raw float32 positions; medians of "
      f"{max(int(r[2]) for r in rows)} runs per cell (warm-up not counted)")
print("| op | -T | wall s | CPU s | MB/s (wall) | speed-up vs -T %s (pairwise median) |" % threads[0])
print("|---|---|---|---|---|---|")
for op in ("compress", "decompress"):
    def cell(t):
        return {int(r[2]): (float(r[3]), float(r[4])) for r in rows
                if r[0] == op and r[1] == t and int(r[2]) > 0}
    base = cell(threads[0])
    for t in threads:
        c = cell(t)
        wall = statistics.median(v[0] for v in c.values())
        cpu = statistics.median(v[1] for v in c.values())
        ratio = statistics.median(base[k][0] / c[k][0] for k in c)
        print(f"| {op} | {t} | {wall:.2f} | {cpu:.2f} | {raw / 1e6 / wall:.1f} | {ratio:.2f}x |")
PY
