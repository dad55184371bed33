#!/usr/bin/env bash
# SPDX-License-Identifier: BSD-2-Clause
# A one-node Slurm cluster on this machine (slurmctld, slurmd and munged from Debian's
# slurm-wlm and munge packages), for trying scripts/encode-slurm.sh and for its test.
#
#   scripts/slurm-localhost.sh start   # prints the line to export SLURM_CONF
#   scripts/slurm-localhost.sh stop
#
# Everything lives in $SVC_SLURM_DIR (default /tmp/svc-slurm): configuration, munge key
# and socket, state, logs. Runs as root (slurmd starts jobs as their users). Ports:
# $SVC_SLURM_PORT (default 6817) and the next one. Exit status 1 when a daemon does not
# come up, with its log's tail.
set -euo pipefail

dir=${SVC_SLURM_DIR:-/tmp/svc-slurm}
port=${SVC_SLURM_PORT:-6817}
conf=$dir/slurm.conf

stop() {
  for pidfile in "$dir"/slurmd.pid "$dir"/slurmctld.pid "$dir"/munged.pid; do
    if [[ -s $pidfile ]]; then
      local pid
      pid=$(cat "$pidfile")
      kill "$pid" 2>/dev/null || true
      for _ in $(seq 1 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    fi
    rm -f "$pidfile"
  done
}

die() {
  echo "slurm-localhost: $*" >&2
  for log in "$dir"/*.log; do [[ -s $log ]] && { echo "--- $log" >&2; tail -5 "$log" >&2; }; done
  stop
  exit 1
}

start() {
  [[ $(id -u) == 0 ]] || die "must run as root"
  for program in munged slurmctld slurmd sinfo; do
    command -v "$program" >/dev/null || die "$program is not installed (Debian: slurm-wlm munge)"
  done
  stop
  mkdir -p "$dir/state" "$dir/spool" "$dir/munge"
  chmod 0700 "$dir/munge"
  [[ -s $dir/munge/munge.key ]] || dd if=/dev/urandom of="$dir/munge/munge.key" bs=1024 count=1 status=none
  chmod 0400 "$dir/munge/munge.key"
  munged --force --key-file="$dir/munge/munge.key" --socket="$dir/munge/munge.socket" \
    --pid-file="$dir/munged.pid" --log-file="$dir/munged.log" --seed-file="$dir/munge/munge.seed" ||
    die "munged did not start"
  local host cpus memory
  host=$(hostname -s)
  cpus=$(nproc)
  memory=$(($(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 / 2))
  cat >"$conf" <<CONF
ClusterName=svc-localhost
SlurmctldHost=$host(127.0.0.1)
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$dir/munge/munge.socket
StateSaveLocation=$dir/state
SlurmdSpoolDir=$dir/spool
SlurmctldPidFile=$dir/slurmctld.pid
SlurmdPidFile=$dir/slurmd.pid
SlurmctldLogFile=$dir/slurmctld.log
SlurmdLogFile=$dir/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SchedulerType=sched/builtin
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
MpiDefault=none
ReturnToService=2
SlurmdTimeout=30
InactiveLimit=0
KillWait=5
NodeName=$host NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=local Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
  export SLURM_CONF=$conf
  slurmctld -f "$conf" || die "slurmctld did not start"
  slurmd -f "$conf" || die "slurmd did not start"
  for _ in $(seq 1 30); do
    if sinfo -h -N -o %T 2>/dev/null | grep -qE '^(idle|mixed|allocated)'; then
      echo "export SLURM_CONF=$conf"
      return 0
    fi
    sleep 1
  done
  die "the node did not become idle in 30 s ($(sinfo -h -N -o %T 2>&1 | head -1))"
}

case "${1:-}" in
  start) start ;;
  stop) stop ;;
  *) echo "usage: $0 start|stop" >&2; exit 2 ;;
esac
