#!/usr/bin/env bash
# Two capz binaries against each other on one take, as whole processes, in alternation.
#
#   tools/ab_speed.sh --base OLD_CAPZ --new NEW_CAPZ [--work DIR] [--minutes M] [--runs N]
#                     [--threads T]
#
# The take is threads_bench.sh's: tools/capz_synth loops c3d/c3dorg/sample_37/
# ART-Human_2persons_integer.c3d (../shared/data) into M minutes (default 10; 144 MB of raw
# float32 positions). Each round runs `capz compress take.c3d -o X -f -q -T T` (default bound,
# self-check, HASH and residue) and `capz decompress X -o Y -f -q -T T` with the base binary,
# then the same with the new one (A B A B ...), N rounds (default 7) after a warm-up round. The
# table gives medians of wall and CPU (user + sys) seconds, MB/s of raw float32 positions per
# wall and per CPU second, and the median of the per-round ratios base / new. On a shared
# machine the CPU figures are the steadier ones. The script fails unless both binaries write
# the same .capz and the same decompressed C3D.
set -euo pipefail
here=$(cd "$(dirname "$0")/.." && pwd)
base="" new="" work=${TMPDIR:-/tmp}/capz-ab-speed minutes=10 runs=7 threads=1
while [ $# -gt 0 ]; do
  case "$1" in
    --base) base=$2; shift 2 ;;
    --new) new=$2; shift 2 ;;
    --work) work=$2; shift 2 ;;
    --minutes) minutes=$2; shift 2 ;;
    --runs) runs=$2; shift 2 ;;
    --threads) threads=$2; shift 2 ;;
    -h|--help) sed -n 2,15p "$0"; exit 0 ;;
    *) echo "ab_speed.sh: unknown option $1" >&2; exit 2 ;;
  esac
done
synth=$here/build/tools/capz_synth
src=$here/../shared/data/c3d/c3dorg/sample_37/ART-Human_2persons_integer.c3d
for f in "$base" "$new" "$synth" "$src"; do
  [ -n "$f" ] && [ -e "$f" ] || { echo "ab_speed.sh: missing ${f:-a --base or --new binary}" >&2; exit 2; }
done
mkdir -p "$work"
. "$here/tools/bench_common.sh"
take=$(bench_take "$synth" "$src" "$work" "$minutes")
"$base" compress "$take" -o "$work/ref.capz" -f -q
raw=$("$base" info "$work/ref.capz" --json | python3 -c \
  'import json,sys; j=json.load(sys.stdin); print(j["frames"]*j["points"]*12)')
log=$work/times.txt
: > "$log"
timed() { bench_timed "$log" "$@"; }  # op which round command...
for r in $(seq 0 "$runs"); do  # round 0 is a warm-up, not counted
  for which in base new; do
    bin=$base
    [ "$which" = new ] && bin=$new
    timed compress "$which" "$r" "$bin" compress "$take" -o "$work/$which.capz" -f -q -T "$threads"
    timed decompress "$which" "$r" "$bin" decompress "$work/ref.capz" -o "$work/$which.c3d" -f -q \
      -T "$threads"
  done
done
cmp "$work/base.capz" "$work/new.capz"
cmp "$work/base.c3d" "$work/new.c3d"

python3 - "$log" "$raw" "$minutes" "$threads" "$(cut -d' ' -f1-3 /proc/loadavg)" <<'PY'
import statistics, sys
log, raw, minutes, threads, load = sys.argv[1], int(sys.argv[2]), sys.argv[3], sys.argv[4], sys.argv[5]
rows = [l.split() for l in open(log)]
print(f"take: {minutes} min, {raw / 1e6:.1f} MB raw float32 positions; -T {threads}; medians of "
      f"{max(int(r[2]) for r in rows)} rounds (warm-up not counted); load average at the end {load}")
print("| op | binary | wall s | CPU s | MB/s (wall) | MB/s (CPU) | base / new (wall) | base / new (CPU) |")
print("|---|---|---|---|---|---|---|---|")
for op in ("compress", "decompress"):
    cell = {w: {int(r[2]): (float(r[3]), float(r[4])) for r in rows
                if r[0] == op and r[1] == w and int(r[2]) > 0} for w in ("base", "new")}
    for w in ("base", "new"):
        c = cell[w]
        wall = statistics.median(v[0] for v in c.values())
        cpu = statistics.median(v[1] for v in c.values())
        ratio = ["", ""]
        if w == "new":
            ratio = [f"{statistics.median(cell['base'][k][i] / c[k][i] for k in c):.3f}x"
                     for i in (0, 1)]
        print(f"| {op} | {w} | {wall:.2f} | {cpu:.2f} | {raw / 1e6 / wall:.1f} | "
              f"{raw / 1e6 / cpu:.1f} | {ratio[0]} | {ratio[1]} |")
PY
