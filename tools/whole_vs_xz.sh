#!/usr/bin/env bash
# tools/whole_vs_xz.sh BIN OUT.tsv (from the repository root): per shared C3D with analog, .capz size at defaults and at
# --lossless against xz -9e of the original file.
BIN=$1; OUT=$2; T=$(mktemp -d)
echo -e "file\tbytes\txz9e\tcapz_default\tcapz_lossless\tanalog_channels" > "$OUT"
find ${CAPZ_SHARED_DATA:-../shared/data}/c3d -iname '*.c3d' | sort | while IFS= read -r f; do
  ch=$("$BIN" info "$f" 2>/dev/null | grep -a -i "analog" | head -1 | grep -oE '[0-9]+ channels' | grep -oE '[0-9]+')
  [ -n "$ch" ] && [ "$ch" -gt 0 ] || continue
  sz=$(stat -c %s "$f"); xzs=$(xz -9e -c "$f" | wc -c)
  "$BIN" compress "$f" -o "$T/a.capz" -f -q 2>/dev/null && d=$(stat -c %s "$T/a.capz") || d=NA
  "$BIN" compress "$f" --lossless -o "$T/b.capz" -f -q 2>/dev/null && l=$(stat -c %s "$T/b.capz") || l=NA
  echo -e "${f#${CAPZ_SHARED_DATA:-../shared/data}/c3d/}\t$sz\t$xzs\t$d\t$l\t$ch" >> "$OUT"
done
rm -rf "$T"
