#!/usr/bin/env bash
# A single-node Slurm cluster on this machine, for the slurm tests and for trying fscil-bench slurm:
#   bash tools/slurm_local.sh start    # munged + slurmctld + slurmd on localhost; prints the SLURM_CONF to export
#   bash tools/slurm_local.sh stop     # cancels every job, stops the daemons
# Everything lives in $FSCIL_SLURM_DIR (default /tmp/fscil-slurm): a munge key of its own, slurm.conf,
# spool folders and logs; nothing under /etc is touched. Packages: slurm-wlm and munge (tools/bootstrap.sh
# installs them). No cgroups and no accounting: ProctrackType=proctrack/linuxproc, task/none.
set -euo pipefail
dir="${FSCIL_SLURM_DIR:-/tmp/fscil-slurm}"
port="${FSCIL_SLURM_PORT:-6817}"
conf="$dir/slurm.conf"

fail() {
  echo "slurm_local.sh: $*" >&2
  exit 1
}

stop_pid_file() {
  local file="$1" pid
  [ -f "$file" ] || return 0
  pid="$(cat "$file" 2>/dev/null || true)"
  if [ -n "$pid" ] && kill -0 "$pid" 2>/dev/null; then
    kill "$pid" 2>/dev/null || true
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null || true
  fi
  rm -f "$file"
}

stop() {
  if [ -f "$conf" ] && [ -f "$dir/slurmctld.pid" ]; then
    SLURM_CONF="$conf" timeout 10 scancel --full --signal=KILL --user="$(id -un)" 2>/dev/null || true
    SLURM_CONF="$conf" timeout 10 scancel --user="$(id -un)" 2>/dev/null || true
  fi
  stop_pid_file "$dir/slurmd.pid"
  stop_pid_file "$dir/slurmctld.pid"
  stop_pid_file "$dir/munge/munged.pid"
}

show_logs() {
  local log
  for log in "$dir/munge/munged.log" "$dir/log/slurmctld.log" "$dir/log/slurmd.log"; do
    [ -f "$log" ] && { echo "--- $log (last lines)" >&2; tail -n 15 "$log" >&2; }
  done
  return 0
}

start() {
  local command
  for command in munged slurmctld slurmd sbatch sinfo scancel; do
    command -v "$command" >/dev/null 2>&1 || PATH="$PATH:/usr/sbin" command -v "$command" >/dev/null 2>&1 ||
      fail "$command not found: install slurm-wlm and munge (bash tools/bootstrap.sh does)"
  done
  export PATH="$PATH:/usr/sbin"
  stop
  rm -rf "$dir"
  mkdir -p "$dir/munge" "$dir/spool/ctld" "$dir/spool/d" "$dir/log"
  chmod 700 "$dir/munge"
  head -c 1024 /dev/urandom >"$dir/munge/munge.key"
  chmod 400 "$dir/munge/munge.key"
  munged --force --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.socket" \
    --pid-file="$dir/munge/munged.pid" --log-file="$dir/munge/munged.log" --seed-file="$dir/munge/munged.seed" ||
    { show_logs; fail "munged did not start"; }

  local host user cpus memory
  host="$(hostname -s)"
  user="$(id -un)"
  cpus="$(nproc)"
  memory="$(awk '/MemTotal/ { print int($2 / 1024 * 0.9) }' /proc/meminfo)"
  cat >"$conf" <<CONF
ClusterName=fscil-local
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
AuthInfo=socket=$dir/munge/munge.socket
CredType=cred/munge
StateSaveLocation=$dir/spool/ctld
SlurmdSpoolDir=$dir/spool/d
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/log/slurmctld.log
SlurmdLogFile=$dir/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
MinJobAge=600
KillWait=30
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=local Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
  export SLURM_CONF="$conf"
  slurmctld -f "$conf" || { show_logs; fail "slurmctld did not start"; }
  slurmd -f "$conf" || { show_logs; fail "slurmd did not start"; }
  local state=""
  for _ in $(seq 150); do
    state="$(sinfo -h -N -o '%T' 2>/dev/null | head -n 1 || true)"
    [ "$state" = "idle" ] && break
    sleep 0.2
  done
  if [ "$state" != "idle" ]; then
    show_logs
    fail "the node did not become idle in 30 s (state: ${state:-no answer from slurmctld})"
  fi
  echo "slurm_local.sh: single-node cluster up ($host, $cpus CPUs); use it with: export SLURM_CONF=$conf"
}

case "${1:-}" in
  start) start ;;
  stop) stop; echo "slurm_local.sh: stopped" ;;
  *) fail "usage: slurm_local.sh start|stop" ;;
esac
