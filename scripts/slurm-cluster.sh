#!/bin/sh
# A single-node Slurm cluster on this machine, for tests and trials:
# munged, slurmctld and slurmd with their key, sockets, state, spool and
# logs under one folder; stopped by their process ids only.
#
#   scripts/slurm-cluster.sh start DIR   start it (prints DIR/env.sh to source)
#   scripts/slurm-cluster.sh stop DIR    cancel its jobs, stop its daemons
#
# After start, `. DIR/env.sh` points sbatch, squeue, scancel and srun at
# it (SLURM_CONF). The node has this machine's cores, one partition
# "debug". Exit code 77 when Slurm or munge is not installed or will not
# start (the tests skip on it); the reason goes to stderr.
set -eu

usage() { echo "usage: $0 start|stop DIR" >&2; exit 2; }
[ $# -eq 2 ] || usage
action=$1
base=$(mkdir -p "$2" && cd "$2" && pwd)

skip() { echo "slurm-cluster: $*" >&2; exit 77; }

# Wait (up to $1 tenths of a second) until the command in $2... succeeds.
wait_for() {
  n=$1; shift
  while [ "$n" -gt 0 ]; do
    if "$@" > /dev/null 2>&1; then return 0; fi
    sleep 0.1; n=$((n - 1))
  done
  return 1
}

stop_pid() {
  [ -s "$1" ] || return 0
  pid=$(cat "$1")
  kill "$pid" 2> /dev/null || true
  i=0
  while kill -0 "$pid" 2> /dev/null && [ $i -lt 100 ]; do sleep 0.1; i=$((i + 1)); done
  kill -9 "$pid" 2> /dev/null || true
  rm -f "$1"
}

case $action in
start)
  for p in munged slurmctld slurmd sbatch squeue scancel sinfo; do
    command -v $p > /dev/null 2>&1 || [ -x /usr/sbin/$p ] \
      || skip "$p is not installed (scripts/install-deps.sh installs Slurm and munge)"
  done
  PATH=$PATH:/usr/sbin
  node=$(hostname -s)
  cpus=$(nproc)
  mkdir -p "$base/etc" "$base/munge" "$base/state" "$base/spool/$node" "$base/log" "$base/run"
  chmod 711 "$base/munge"
  socket=$base/munge/munge.socket.2
  if [ ! -s "$base/munge/munge.key" ]; then
    dd if=/dev/urandom of="$base/munge/munge.key" bs=1024 count=1 2> /dev/null
    chmod 400 "$base/munge/munge.key"
  fi
  munged --key-file="$base/munge/munge.key" --socket="$socket" \
    --pid-file="$base/run/munged.pid" --log-file="$base/log/munged.log" \
    --seed-file="$base/munge/munge.seed" --force 2> "$base/log/munged.err" \
    || skip "munged would not start: $(cat "$base/log/munged.err")"
  wait_for 50 sh -c "munge -S '$socket' -n | unmunge -S '$socket'" \
    || skip "munge does not answer on $socket"
  cat > "$base/etc/slurm.conf" <<CONF
ClusterName=nct-test
SlurmctldHost=$node(127.0.0.1)
SlurmUser=$(id -un)
SlurmdUser=$(id -un)
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$socket
StateSaveLocation=$base/state
SlurmdSpoolDir=$base/spool/%n
SlurmctldPidFile=$base/run/slurmctld.pid
SlurmdPidFile=$base/run/slurmd-%n.pid
SlurmctldLogFile=$base/log/slurmctld.log
SlurmdLogFile=$base/log/slurmd-%n.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
SwitchType=switch/none
MpiDefault=none
ReturnToService=2
AccountingStorageType=accounting_storage/none
JobAcctGatherType=jobacct_gather/none
MailProg=/bin/true
JobCompType=jobcomp/filetxt
JobCompLoc=$base/log/jobcomp.txt
MinJobAge=300
SchedulerType=sched/backfill
SchedulerParameters=batch_sched_delay=0
InactiveLimit=0
KillWait=5
NodeName=$node NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=1000 State=UNKNOWN
PartitionName=debug Nodes=$node Default=YES MaxTime=INFINITE State=UP
CONF
  export SLURM_CONF=$base/etc/slurm.conf
  slurmctld -D -i > "$base/log/slurmctld.out" 2>&1 &
  echo $! > "$base/run/slurmctld.daemon"
  slurmd -D > "$base/log/slurmd.out" 2>&1 &
  echo $! > "$base/run/slurmd.daemon"
  if ! wait_for 200 sh -c "sinfo -h -o %T | grep -qx idle"; then
    why=$(tail -3 "$base/log/slurmctld.log" "$base/log/slurmd-$node.log" 2> /dev/null || true)
    "$0" stop "$base"
    skip "the node did not come up idle in 20 s: $why"
  fi
  cat > "$base/env.sh" <<ENV
export SLURM_CONF=$base/etc/slurm.conf
export PATH=\$PATH:/usr/sbin
export OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1
ENV
  echo "$base/env.sh"
  ;;
stop)
  if [ -s "$base/etc/slurm.conf" ]; then
    SLURM_CONF=$base/etc/slurm.conf scancel --full -u "$(id -un)" 2> /dev/null || true
  fi
  stop_pid "$base/run/slurmd.daemon"
  stop_pid "$base/run/slurmctld.daemon"
  stop_pid "$base/run/munged.pid"
  ;;
*) usage ;;
esac
