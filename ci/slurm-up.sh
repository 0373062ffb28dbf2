#!/usr/bin/env bash
# A single-node Slurm on this host, for the cluster tests: installs Debian's slurm-wlm and
# munge if missing, writes a minimal slurm.conf for this host, starts munged, slurmctld and
# slurmd without systemd and waits until the node is idle. Everything lives in $DIR
# (default /tmp/texopt-slurm): its slurm.conf (export SLURM_CONF=$DIR/slurm.conf to use it),
# logs, state and the daemons' pid files, which ci/slurm-down.sh stops them by.
#
#     ci/slurm-up.sh [DIR]      (as root)
set -euo pipefail
DIR=${1:-/tmp/texopt-slurm}
if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
    apt-get update -qq
    DEBIAN_FRONTEND=noninteractive apt-get install -y -qq slurm-wlm munge >/dev/null
fi
mkdir -p "$DIR"/{state,spool,log,run,munge}
chmod 755 "$DIR"   # munged runs as munge and keeps its log and pid here
# munge: a key if the package did not make one; its socket and pid in $DIR.
if [ ! -s /etc/munge/munge.key ]; then
    dd if=/dev/urandom of=/etc/munge/munge.key bs=1 count=1024 status=none
fi
chown -R munge:munge /etc/munge "$DIR/munge"
chmod 700 /etc/munge "$DIR/munge"
chmod 400 /etc/munge/munge.key
mkdir -p /run/munge && chown munge:munge /run/munge
if ! pgrep -x munged >/dev/null; then
    sudo_munge() { su -s /bin/sh munge -c "$*"; }
    sudo_munge "munged --pid-file=$DIR/munge/munged.pid --log-file=$DIR/munge/munged.log"
fi
node=$(slurmd -C | head -1)
host=$(hostname -s)
cat > "$DIR/slurm.conf" <<CONF
ClusterName=texopt
SlurmctldHost=$host
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
CredType=cred/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
MpiDefault=none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
StateSaveLocation=$DIR/state
SlurmdSpoolDir=$DIR/spool
SlurmctldPidFile=$DIR/run/slurmctld.pid
SlurmdPidFile=$DIR/run/slurmd.pid
SlurmctldLogFile=$DIR/log/slurmctld.log
SlurmdLogFile=$DIR/log/slurmd.log
$node
PartitionName=debug Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$DIR/slurm.conf
slurmctld -f "$SLURM_CONF"
slurmd -f "$SLURM_CONF"
for _ in $(seq 1 60); do
    if sinfo -h -o '%T' 2>/dev/null | grep -qx idle; then
        echo "slurm up: $(sinfo -h -o '%N %c CPUs %T')"
        exit 0
    fi
    sleep 1
done
echo "slurm did not come up; logs in $DIR/log" >&2
tail -20 "$DIR/log/slurmctld.log" "$DIR/log/slurmd.log" >&2 || true
exit 1
