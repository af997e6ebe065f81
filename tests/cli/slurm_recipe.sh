#!/usr/bin/env bash
# docs/ARCHIVE.md's Slurm recipe on a real Slurm: a private single-node cluster (munged, slurmctld,
# slurmd) started in a temporary folder, the recipe run as written (find, --split, sbatch --wait
# --array), every take and report checked, and everything started stopped again.
#
#   tests/cli/slurm_recipe.sh CAPZ_BINARY REPO_ROOT [SHARED_DATA]
#
# Exits 77 (ctest: skipped) with a message when it cannot run here: not root (slurmd runs jobs as
# root here), or Debian's slurm-wlm / munge not installed (scripts/install-deps.sh installs them).
set -euo pipefail
capz=$(readlink -f "$1")
repo=$(readlink -f "$2")
shared=${3:-}

skip() { echo "SKIPPED: $*"; exit 77; }
[ "$(id -u)" -eq 0 ] || skip "needs root to start slurmd (CI runs as root)"
for b in munged slurmctld slurmd sbatch scontrol sinfo; do
  command -v "$b" >/dev/null || skip "$b not found: install Debian's slurm-wlm and munge"
done

work=$(mktemp -d /tmp/capz_slurm.XXXXXX)
export SLURM_CONF="$work/slurm.conf"
stop() {
  scontrol shutdown >/dev/null 2>&1 || true
  for p in slurmd slurmctld; do
    [ -f "$work/$p.pid" ] && kill "$(cat "$work/$p.pid")" 2>/dev/null || true
  done
  [ -f "$work/munge/munged.pid" ] && kill "$(cat "$work/munge/munged.pid")" 2>/dev/null || true
  sleep 1
  rm -rf "$work"
}
trap stop EXIT
fail() {
  echo "FAILED: $*" >&2
  for f in "$work"/log/*.log "$work"/munge/munged.log; do
    [ -f "$f" ] && { echo "--- $f" >&2; tail -n 20 "$f" >&2; }
  done
  exit 1
}

# munge, with a key and socket of its own (no system service touched).
mkdir -p "$work/munge" "$work/state" "$work/spool" "$work/log" "$work/run"
chmod 700 "$work/munge"
head -c 1024 /dev/urandom >"$work/munge/munge.key"
chmod 400 "$work/munge/munge.key"
munged --key-file="$work/munge/munge.key" --socket="$work/munge/munge.sock" \
  --pid-file="$work/munge/munged.pid" --log-file="$work/munge/munged.log" \
  --seed-file="$work/munge/seed" --force || fail "munged did not start"

# Ports of our own, so a cluster already on this machine is left alone.
port=$((20000 + $$ % 20000))
host=$(hostname -s)
cat >"$SLURM_CONF" <<EOF
ClusterName=capztest
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$work/munge/munge.sock
CredType=cred/munge
SlurmctldPort=$port
SlurmdPort=$((port + 1))
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/log/slurmctld.log
SlurmdLogFile=$work/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
JobAcctGatherType=jobacct_gather/none
ReturnToService=2
NodeName=$host CPUs=$(nproc) State=UNKNOWN
PartitionName=main Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
slurmctld -f "$SLURM_CONF" || fail "slurmctld did not start"
slurmd -f "$SLURM_CONF" || fail "slurmd did not start"
for _ in $(seq 1 30); do
  sinfo -h -o '%T' 2>/dev/null | grep -q idle && break
  sleep 1
done
sinfo -h -o '%T' | grep -q idle || fail "the node never became idle"

# Twelve takes: the bundled samples (C3D, TRC, PCD folders), then shared C3D files if present.
mkdir -p "$work/takes"
n=0
for f in "$repo"/data/*.c3d "$repo"/data/*.trc; do
  cp "$f" "$work/takes/" && n=$((n + 1))
done
for d in "$repo"/data/*/; do
  ls "$d"*.pcd >/dev/null 2>&1 || continue
  cp -r "$d" "$work/takes/" && n=$((n + 1))
done
if [ -n "$shared" ] && [ -d "$shared/c3d/c3dorg" ]; then
  for f in $(find "$shared/c3d/c3dorg" -iname '*.c3d' -size -400k | sort | head -n $((12 - n))); do
    [ "$n" -ge 12 ] && break
    cp "$f" "$work/takes/shared_$n.c3d" && n=$((n + 1))
  done
fi
echo "takes: $n"

# The recipe, as docs/ARCHIVE.md writes it (K = 2 lists, one per array task).
cd "$work"
export CAPZ="$capz"
{ find takes -type f \( -iname '*.c3d' -o -iname '*.trc' \)
  find takes -name '*.pcd' -printf '%h\n' | sort -u; } >takes.txt
[ "$(wc -l <takes.txt)" -eq "$n" ] || fail "takes.txt lists $(wc -l <takes.txt) takes, made $n"
"$repo/tools/slurm/capz-array.sh" --split takes.txt 2 lists
sbatch --wait --array=0-1 --cpus-per-task=1 -o "$work/log/capz-%A_%a.out" \
  "$repo/tools/slurm/capz-array.sh" lists --lossless --output-dir-mirror archive ||
  fail "sbatch --wait returned non-zero"

# Every take once in one report, ok, with its archive, and every archive tests clean.
cat lists/report.0.jsonl lists/report.1.jsonl >all.jsonl
[ "$(wc -l <all.jsonl)" -eq "$n" ] || fail "reports hold $(wc -l <all.jsonl) lines for $n takes"
while read -r t; do
  [ "$(grep -c "\"input\": *\"$t\"" all.jsonl)" -eq 1 ] || fail "$t is not reported exactly once"
  [ -f "archive/$t.capz" ] || fail "no archive/$t.capz"
done <takes.txt
grep -q '"ok": *false' all.jsonl && fail "a take failed: $(grep '"ok": *false' all.jsonl)"
"$capz" test -q -r archive || fail "capz test -r archive"
echo "Slurm recipe: $n takes compressed by a 2-task array, every report ok, every archive tested"
