# Sourced by tools/threads_bench.sh and tools/ab_speed.sh: the synthetic take and the timer.

# bench_take SYNTH SRC WORK MINUTES: the take SRC looped into MINUTES minutes by capz_synth
# (made once, kept in WORK); prints its path.
bench_take() {
  local take=$3/take-$4min.c3d
  [ -s "$take" ] || "$1" "$2" "$take" --minutes "$4" >/dev/null
  echo "$take"
}

# bench_timed LOG OP WHICH ROUND COMMAND...: runs COMMAND (stdout discarded) and appends
# "OP WHICH ROUND wall-seconds cpu-seconds" (user + sys) to LOG.
bench_timed() {
  local log=$1 op=$2 which=$3 r=$4 wall user sys
  shift 4
  /usr/bin/time -f "%e %U %S" -o "$log.one" "$@" >/dev/null
  read -r wall user sys < "$log.one"
  echo "$op $which $r $wall $(python3 -c "print($user + $sys)")" >> "$log"
}
