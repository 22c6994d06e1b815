#!/usr/bin/env bash
# Proves cluster/slurm on a real Slurm, on this one machine: installs slurmctld,
# slurmd and munge from the distribution's packages (if missing), writes a
# minimal one-node configuration (only if the machine has none), starts the
# daemons, and then
#   1. traces the PANTER Al Kα scene in one run (the reference);
#   2. submits the same run with cluster/slurm/submit.sh as an array job of 4
#      shards and a dependent merge job;
#   3. sends shard 1 a SIGTERM once it has a checkpoint (what Slurm does before
#      a time limit with --signal): it must write its checkpoint, be requeued
#      and resume;
#   4. waits for the merge and checks that every image, table and plot is
#      bit-identical to the reference.
# Needs root (packages, daemons). Stops the daemons it started. Exit codes: 0
# bit-identical, 1 a failure of traxer or of the cluster scripts, 2 not root,
# 77 Slurm cannot be installed or started here (skipped).
case "${1:-}" in -h | --help) awk 'NR > 1 && /^#/ { sub(/^# ?/, ""); print; next } NR > 1 { exit }' "$0"; exit 0 ;; esac
set -euo pipefail
cd "$(dirname "$0")/.."
repo=$(pwd)
if [ "$(id -u)" -ne 0 ]; then
  echo "$0: needs root (installs and starts Slurm)" >&2
  exit 2
fi
say() { echo "slurm_check: $*"; }

if ! command -v slurmctld >/dev/null || ! command -v slurmd >/dev/null || ! command -v munged >/dev/null; then
  say "installing slurmctld, slurmd, munge"
  export DEBIAN_FRONTEND=noninteractive
  if ! { apt-get update -q >/dev/null && apt-get install -y -q --no-install-recommends slurmctld slurmd slurm-client munge >/dev/null; }; then
    say "cannot install Slurm from the distribution's packages: skipped"
    exit 77
  fi
fi

conf=/etc/slurm/slurm.conf
marker="# written by traxer scripts/slurm_check.sh"
node=$(hostname -s)
if [ -f "$conf" ] && ! grep -qF "$marker" "$conf"; then
  say "using the existing $conf (not written by this script)"
else
  cpus=$(nproc)
  memory=$(slurmd -C | grep -o 'RealMemory=[0-9]*' | cut -d= -f2)
  mkdir -p /etc/slurm /var/spool/slurmctld /var/spool/slurmd /var/log/slurm
  chown slurm:slurm /var/spool/slurmctld /var/log/slurm
  cat > "$conf" <<EOF
$marker: one node, no accounting, no cgroups
ClusterName=traxercheck
SlurmctldHost=$node
SlurmUser=slurm
AuthType=auth/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SwitchType=switch/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
StateSaveLocation=/var/spool/slurmctld
SlurmdSpoolDir=/var/spool/slurmd
SlurmctldPidFile=/run/slurmctld.pid
SlurmdPidFile=/run/slurmd.pid
SlurmctldLogFile=/var/log/slurm/slurmctld.log
SlurmdLogFile=/var/log/slurm/slurmd.log
ReturnToService=2
NodeName=$node CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=check Nodes=ALL Default=YES MaxTime=INFINITE State=UP
EOF
fi

started=()
cleanup() {
  for p in "${started[@]}"; do pkill -x "$p" 2>/dev/null || true; done
}
trap cleanup EXIT
if ! munge -n 2>/dev/null | unmunge >/dev/null 2>&1; then
  mkdir -p /run/munge /var/log/munge /var/lib/munge
  chown munge:munge /run/munge /var/log/munge /var/lib/munge
  [ -f /etc/munge/munge.key ] || { dd if=/dev/urandom of=/etc/munge/munge.key bs=1024 count=1 2>/dev/null; chown munge:munge /etc/munge/munge.key; chmod 400 /etc/munge/munge.key; }
  runuser -u munge -- /usr/sbin/munged
  started+=(munged)
fi
if ! scontrol ping 2>/dev/null | grep -q UP; then slurmctld; started+=(slurmctld); fi
if ! pgrep -x slurmd >/dev/null; then slurmd; started+=(slurmd); fi
for _ in $(seq 60); do
  sinfo -h -o %T 2>/dev/null | grep -q idle && break
  scontrol update nodename="$node" state=resume >/dev/null 2>&1 || true
  sleep 1
done
if ! sinfo -h -o %T 2>/dev/null | grep -q idle; then
  say "Slurm did not come up on this machine (see /var/log/slurm): skipped"
  sinfo || true
  exit 77
fi
say "Slurm $(sinfo -V | cut -d' ' -f2) is up: $(sinfo -h -o '%P %D node(s) %c CPUs %T')"

cargo build --release --quiet
traxer=$repo/target/release/traxer
work=$(mktemp -d /tmp/traxer-slurm.XXXXXX)
chmod 755 "$work"
scene=scenes/panter_al_ka.toml
photons=12000000
options=(-s 11)

say "reference: one run of $photons photons"
"$traxer" trace "$scene" -n "$photons" "${options[@]}" -o "$work/single" -q

say "submitting 4 shards and the merge"
start=$(date +%s)
TRAXER=$traxer TRAXER_CHECKPOINT_EVERY=0 cluster/slurm/submit.sh "$scene" "$photons" 4 "$work/run" "${options[@]}"
read -r array merge < "$work/run/jobs"

# Shard 1, once it has a checkpoint: SIGTERM to its batch shell, as Slurm
# sends it before a time limit.
for _ in $(seq 600); do
  [ -f "$work/run/shard-1-of-4/checkpoint.bin" ] && break
  sleep 0.1
done
if [ -f "$work/run/shard-1-of-4/checkpoint.bin" ]; then
  say "shard 1 has a checkpoint: sending it SIGTERM"
  # scancel retries while the task is being requeued ("try again later"):
  # the signal is delivered by then, so do not wait for it.
  timeout 5 scancel --batch --signal=TERM "${array}_1" 2>/dev/null || true
else
  say "shard 1 never had a checkpoint"; exit 1
fi

state() { scontrol show job "$1" 2>/dev/null | grep -o 'JobState=[A-Z_]*' | head -1 | cut -d= -f2; }
for _ in $(seq 900); do
  s=$(state "$merge")
  case "$s" in
    COMPLETED) break ;;
    FAILED|CANCELLED|TIMEOUT|NODE_FAIL|OUT_OF_MEMORY)
      say "merge job $merge: $s"; cat "$work/run/logs/"*.log; exit 1 ;;
  esac
  # Slurm holds a requeued task for 2 minutes (until old credentials expire);
  # on a one-node test cluster it may start at once.
  for task in $(squeue -h -j "$array" -t PD -o '%i %r' 2>/dev/null | awk '$2 == "BeginTime" {print $1}'); do
    scontrol update JobId="$task" StartTime=now >/dev/null 2>&1 || true
  done
  if squeue -h -j "$merge" -o %r 2>/dev/null | grep -q DependencyNeverSatisfied; then
    say "merge job $merge can never run: a shard failed"; cat "$work/run/logs/"*.log; exit 1
  fi
  sleep 1
done
[ "$(state "$merge")" = COMPLETED ] || { say "timed out waiting for the merge"; squeue; exit 1; }
say "array and merge done in $(( $(date +%s) - start )) s"

grep -q "requeueing" "$work/run/logs/shard-1.log" || { say "shard 1 was not requeued"; cat "$work/run/logs/shard-1.log"; exit 1; }
grep -q -- "--resume" "$work/run/logs/shard-1.log" || { say "shard 1 did not resume"; cat "$work/run/logs/shard-1.log"; exit 1; }
say "shard 1 was stopped with a checkpoint, requeued and resumed"

status=0
for f in "$work/single"/*; do
  name=$(basename "$f")
  case "$name" in
    *.json) continue ;;  # provenance and timing differ
    run_state.bin)
      cmp -s <(tail -n +3 "$f") <(tail -n +3 "$work/run/merged/$name") || { say "DIFFERENT: $name (tally)"; status=1; } ;;
    *) cmp -s "$f" "$work/run/merged/$name" || { say "DIFFERENT: $name"; status=1; } ;;
  esac
done
if [ "$status" -eq 0 ]; then
  say "merged result is bit-identical to the single run ($(ls "$work/single" | wc -l) files)"
  rm -rf "$work"
fi
exit "$status"
