#!/usr/bin/env bash
# tools/analog_lossy_bench.sh BIN OUT.tsv [BOUNDS] (from the repository root): per shared C3D with
# analog channels, the whole .capz at the defaults and with --analog-max-error BOUNDS (default
# the issue's example set) against xz -9e of the original file; every lossy archive is checked
# with `capz verify --against` (the column `verify` says holds / FAILS) and decompressed to a C3D.
BIN=$1; OUT=$2; BOUNDS=${3:-N=0.05,Nmm=5,V=1e-5,mV=0.01}; T=$(mktemp -d)
echo -e "file\tbytes\txz9e\tcapz_default\tcapz_lossy\tanalog_channels\tlossy_channels\tverify" > "$OUT"
find ${CAPZ_SHARED_DATA:-../shared/data}/c3d -iname '*.c3d' | sort | while IFS= read -r f; do
  ch=$("$BIN" info "$f" 2>/dev/null | grep -i "^analog" | head -1 | grep -oE '[0-9]+ channels' | grep -oE '[0-9]+')
  [ -n "$ch" ] && [ "$ch" -gt 0 ] || continue
  sz=$(stat -c %s "$f"); xzs=$(xz -9e -c "$f" | wc -c)
  "$BIN" compress "$f" -o "$T/a.capz" -f -q 2>/dev/null && d=$(stat -c %s "$T/a.capz") || d=NA
  if "$BIN" compress "$f" --analog-max-error "$BOUNDS" -o "$T/b.capz" -f -q 2>/dev/null; then
    l=$(stat -c %s "$T/b.capz")
    n=$("$BIN" info "$T/b.capz" --json | python3 -c 'import json,sys; print(len(json.load(sys.stdin)["analog_bounds"]))')
    v=FAILS
    "$BIN" verify "$T/b.capz" --against "$f" -q && "$BIN" decompress "$T/b.capz" -o "$T/b.c3d" -f -q && v=holds
  else
    l=NA; n=NA; v=NA
  fi
  echo -e "${f#${CAPZ_SHARED_DATA:-../shared/data}/c3d/}\t$sz\t$xzs\t$d\t$l\t$ch\t$n\t$v" >> "$OUT"
done
rm -rf "$T"
python3 - "$OUT" <<'PY'
import sys, statistics
rows = [l.rstrip("\n").split("\t") for l in open(sys.argv[1])][1:]
ok = [r for r in rows if r[4] != "NA" and r[3] != "NA"]
big = [r for r in ok if int(r[1]) >= 100000]
lossy = [r for r in big if r[6] not in ("0", "NA")]
def summary(rs, col):
    q = [int(r[col]) / int(r[2]) for r in rs]
    return "median %.3f, worst %.2f, %d of %d within 0.6x" % (
        statistics.median(q), max(q), sum(x <= 0.6 for x in q), len(q)) if q else "none"
print("takes >= 100 KB with analog: %d; with a lossy channel: %d; verify fails: %d" % (
    len(big), len(lossy), sum(r[7] != "holds" for r in ok if r[6] not in ("0", "NA"))))
print("defaults / xz -9e:", summary(big, 3))
print("--analog-max-error / xz -9e:", summary(big, 4))
print("  on the takes with a lossy channel, defaults:", summary(lossy, 3))
print("  on the takes with a lossy channel, lossy:   ", summary(lossy, 4))
PY
