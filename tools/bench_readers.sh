#!/bin/sh
# Issue #38 items 1 and 3: what --lossless costs on files other tools write, against xz -9e of
# the same bytes in the same run.
#   comma TRC: each OpenSim TRC of ../shared/data/trc/opensim re-saved as a spreadsheet and as
#              pyomeca writes it (data/make_comma_trc.py), against the tab-separated original,
#              each form compressed under the original's file name (META keeps the name), so
#              that the last column compares the same take saved two ways;
#   ascii PCD: one organized sequence in six writers' spellings (data/make_ascii_pcd.py), xz -9e
#              of the frame files concatenated in order.
# usage: tools/bench_readers.sh [BUILD_DIR] [WORK_DIR]   (prints markdown tables)
set -eu
BUILD=${1:-build}
WORK=${2:-$(mktemp -d)}
CAPZ="$BUILD/capz"
DATA=../shared/data/trc/opensim
size() { wc -c < "$1" | tr -d ' '; }
xz_size() { xz -9e -T1 -c "$@" | wc -c | tr -d ' '; }
ratio() { awk -v a="$1" -v b="$2" 'BEGIN { printf "%.3f", a / b }'; }

mkdir -p "$WORK/trc" "$WORK/pcd"
echo "| TRC | form | bytes | xz -9e | capz --lossless | capz / xz | capz / tab form's capz |"
echo "|---|---|---:|---:|---:|---:|---:|"
for src in "$DATA"/*.trc; do
  stem=$(basename "$src" .trc)
  python3 data/make_comma_trc.py "$src" -o "$WORK/trc" > /dev/null
  "$CAPZ" compress -q -f --lossless "$src" -o "$WORK/trc/$stem.tab.capz"
  tab=$(size "$WORK/trc/$stem.tab.capz")
  for form in tab sheet sheet-crlf sheet-gen pyomeca; do
    f="$WORK/trc/$stem.$form.trc"
    [ "$form" = tab ] && f="$src"
    mkdir -p "$WORK/trc/$form"
    cp "$f" "$WORK/trc/$form/$stem.trc"
    "$CAPZ" compress -q -f --lossless "$WORK/trc/$form/$stem.trc" -o "$WORK/trc/$stem.$form.capz"
    "$CAPZ" test -q "$WORK/trc/$stem.$form.capz" > /dev/null
    c=$(size "$WORK/trc/$stem.$form.capz")
    x=$(xz_size "$f")
    echo "| $stem | $form | $(size "$f") | $x | $c | $(ratio "$c" "$x") | $(ratio "$c" "$tab") |"
  done
done

echo
python3 data/make_ascii_pcd.py "$WORK/pcd" > /dev/null
echo "| convention | frame files' bytes | xz -9e | capz --lossless | capz / xz |"
echo "|---|---:|---:|---:|---:|"
for conv in pcl repr f32 savetxt fixed open3d; do
  d="$WORK/pcd/$conv"
  bytes=$(cat "$d"/*.pcd | wc -c | tr -d ' ')
  x=$(cat "$d"/*.pcd | xz -9e -T1 | wc -c | tr -d ' ')
  "$CAPZ" compress -q -f --lossless "$d" -o "$WORK/pcd/$conv.capz"
  "$CAPZ" test -q "$WORK/pcd/$conv.capz" > /dev/null
  c=$(size "$WORK/pcd/$conv.capz")
  echo "| $conv | $bytes | $x | $c | $(ratio "$c" "$x") |"
done
