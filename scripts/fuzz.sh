#!/usr/bin/env bash
# Runs one libFuzzer target (docs/RELIABILITY.md) for SECONDS (default 600), one job, seeded from
# a scratch copy of its committed corpus, so the run's new inputs do not land in git:
#   scripts/fuzz.sh read_c3d 600
# Needs the clang build: CC=clang CXX=clang++ cmake -S . -B build-fuzz -DCAPZ_BUILD_FUZZERS=ON
#   -DCAPZ_BUILD_TESTS=OFF -DCAPZ_BUILD_BENCH=OFF -DCAPZ_SANITIZE=address,undefined
#   -DCMAKE_BUILD_TYPE=RelWithDebInfo && cmake --build build-fuzz -j2
# Findings (crash-*, timeout-*, oom-*, leak-*) are written to $WORK/findings/; the log to
# $WORK/fuzz.log. WORK defaults to /tmp/capz-fuzz-TARGET.
set -euo pipefail
cd "$(dirname "$0")/.."
target=${1:?usage: scripts/fuzz.sh TARGET [SECONDS]}
seconds=${2:-600}
work=${WORK:-/tmp/capz-fuzz-$target}
exe=$PWD/build-fuzz/tests/fuzz/fuzz_$target
[ -x "$exe" ] || { echo "no $exe: build build-fuzz first (see the top of this script)" >&2; exit 1; }
case $target in
  read_c3d) dict=$PWD/tests/fuzz/dict/read_c3d.dict ;;
  read_trc) dict=$PWD/tests/fuzz/dict/read_trc.dict ;;
  parse_container | simple_decompress | ragged_decompress) dict=$PWD/tests/fuzz/dict/capz.dict ;;
  *) dict= ;;
esac
rm -rf "$work"
mkdir -p "$work/corpus" "$work/findings"
cp tests/fuzz/corpus/"$target"/* "$work/corpus/" 2>/dev/null || true
cd "$work"  # -jobs=1 makes libFuzzer write fuzz-0.log in the current directory
set +e
nice -n 5 "$exe" -jobs=1 -workers=1 -max_total_time="$seconds" -rss_limit_mb=2048 -timeout=10 \
  -print_final_stats=1 -artifact_prefix="$work/findings/" ${dict:+-dict=$dict} \
  corpus >driver.log 2>&1
status=$?
set -e
cat driver.log fuzz-0.log >fuzz.log 2>/dev/null || true
echo "$target: exit $status, $(ls corpus | wc -l) corpus files ($(du -sh corpus | cut -f1))," \
  "$(ls findings | wc -l) findings; log $work/fuzz.log"
grep -E '^#[0-9]+.*cov:' fuzz.log | tail -1 || true
# Coverage-guided only when the libraries are instrumented: a target sees tens of thousands of
# counters with them and about 190 (its own) without (tests/fuzz/CMakeLists.txt).
counters=$(sed -nE 's/.*Loaded 1 modules +\(([0-9]+) inline.*/\1/p' fuzz.log | head -1)
if [ "${counters:-0}" -lt 2000 ]; then
  echo "warning: only ${counters:-0} coverage counters: the library is not instrumented," \
    "so this run was not coverage-guided (rebuild build-fuzz)" >&2
fi
grep -E '^stat::' fuzz.log || true
exit $status
