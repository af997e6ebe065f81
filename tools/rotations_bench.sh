#!/usr/bin/env bash
# The rotation takes of issue #38 (item 2) against `xz -9e` of the file: archive bytes at the
# default bound and with --lossless, the ROTW bytes and the other bytes (`capz compress -v`), and
# the archive over xz. The takes are written by tools/capz_rotation_takes (the C3D writer of
# tests/support/rotation_c3d.h). BEFORE, when given, is a second capz binary measured the same
# way (e.g. one built at an earlier commit).
# Usage: tools/rotations_bench.sh [BUILD_DIR] [BEFORE_CAPZ]
set -euo pipefail
B=${1:-build}
BEFORE=${2:-}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$B/tools/capz_rotation_takes" "$tmp" >/dev/null
echo "| take | file B | xz -9e B | target | capz | archive B | ROTW B | other B | x xz |"
echo "|---|---|---|---|---|---|---|---|---|"
for f in "$tmp"/*.c3d; do
  name=$(basename "$f" .c3d)
  size=$(stat -c %s "$f")
  x=$(xz -9e -c "$f" | wc -c)
  for target in default --lossless; do
    opt=()
    [ "$target" = --lossless ] && opt=(--lossless)
    for which in before after; do
      bin="$B/capz"
      if [ "$which" = before ]; then
        [ -n "$BEFORE" ] || continue
        bin=$BEFORE
      fi
      v=$("$bin" compress -f -v "${opt[@]}" "$f" -o "$tmp/a.capz" 2>&1)
      z=$(stat -c %s "$tmp/a.capz")
      rot=$(grep -o "rotations [0-9]* B" <<<"$v" | grep -o "[0-9]*")
      other=$(grep -o "other [0-9]* B" <<<"$v" | grep -o "[0-9]*")
      ratio=$(python3 -c "print(f'{$z / $x:.3f}')")
      echo "| $name | $size | $x | ${target#--} | $which | $z | $rot | $other | $ratio |"
    done
  done
done
