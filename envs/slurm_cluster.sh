#!/usr/bin/env bash
# A single-node SLURM cluster on this machine, from Debian's packages, for the SLURM tests
# (tests/workflow/test_slurm.py) and CI. Needs root. Both subcommands are idempotent.
#
#   eval "$(bash envs/slurm_cluster.sh up)"   # install if missing, start, print the two exports
#   bash envs/slurm_cluster.sh down           # cancel jobs, stop every daemon it started
#
# Daemons: munged (authentication), MariaDB + slurmdbd (the accounting database: sacct and
# sacctmgr, which the Snakemake SLURM executor uses for job states and account checks, only
# answer through slurmdbd), slurmctld, slurmd. The node gets the machine's cores (nproc) and
# memory (/proc/meminfo). Jobs must name the account and the partition (neither is a default),
# as on a real cluster; `up` prints them as SBATCH_ACCOUNT / SBATCH_PARTITION, the variables
# the SLURM profile (profiles/slurm) reads. Logs: /var/log/slurm/.
set -euo pipefail

CLUSTER=sfcluster
ACCOUNT=suspension_fabric
PARTITION="batch"
NODE=$(hostname -s)
LOGS=/var/log/slurm
STATE=/var/lib/slurm
MUNGE_PID=/run/munge/munged.pid
MARIADB_PID=/run/mysqld/mysqld.pid
SLURMDBD_PID=/run/slurmdbd.pid
SLURMCTLD_PID=/run/slurmctld.pid
SLURMD_PID=/run/slurmd.pid
PACKAGES=(munge mariadb-server slurmdbd slurmctld slurmd slurm-client)

say() { echo "slurm_cluster: $*" >&2; }
# alive PIDFILE NAME: the pid file names a running NAME (a stale file may name another process).
alive() { [ -s "$1" ] && [ "$(cat "/proc/$(cat "$1")/comm" 2>/dev/null)" = "$2" ]; }

# wait_for SECONDS WHAT LOG COMMAND...: poll until COMMAND succeeds, else show LOG and fail.
wait_for() {
    local seconds=$1 what=$2 log=$3
    shift 3
    for _ in $(seq $((seconds * 2))); do
        if "$@" >/dev/null 2>&1; then return 0; fi
        sleep 0.5
    done
    say "$what not ready after ${seconds} s; end of $log:"
    tail -n 30 "$log" >&2 || true
    exit 1
}

install_packages() {
    local missing=()
    for package in "${PACKAGES[@]}"; do
        dpkg-query -W -f='${Status}' "$package" 2>/dev/null | grep -q "ok installed" || missing+=("$package")
    done
    [ ${#missing[@]} -eq 0 ] && return 0
    say "installing ${missing[*]}"
    export DEBIAN_FRONTEND=noninteractive
    local log
    log=$(mktemp)
    # A fresh machine may have no package lists yet.
    if ! { apt-get install -y --no-install-recommends "${missing[@]}" >"$log" 2>&1 \
            || { apt-get update >>"$log" 2>&1 && apt-get install -y --no-install-recommends "${missing[@]}" >>"$log" 2>&1; }; }; then
        tail -n 30 "$log" >&2
        exit 1
    fi
    rm -f "$log"
}

# Writes $1 from stdin; returns 0 if its content changed.
write_config() {
    local target=$1 new
    new=$(cat)
    if [ -f "$target" ] && [ "$(cat "$target")" = "$new" ]; then return 1; fi
    printf '%s\n' "$new" >"$target"
}

write_configs() {
    local cpus memory changed=1
    cpus=$(nproc)
    memory=$(awk '/^MemTotal:/ {print int($2 / 1024)}' /proc/meminfo)  # what `free -m` shows
    mkdir -p /etc/slurm "$LOGS" "$STATE/slurmctld" "$STATE/slurmd"
    # The database password only guards a database bound to localhost that holds test jobs.
    write_config /etc/slurm/slurmdbd.conf <<EOF && changed=0
# Written by envs/slurm_cluster.sh.
AuthType=auth/munge
DbdHost=localhost
SlurmUser=root
PidFile=$SLURMDBD_PID
LogFile=$LOGS/slurmdbd.log
StorageType=accounting_storage/mysql
StorageHost=localhost
StorageUser=slurm
StoragePass=slurm
StorageLoc=slurm_acct_db
EOF
    chmod 600 /etc/slurm/slurmdbd.conf
    # CR_Core_Memory: cores and memory are both consumed, so --mem is enforced at scheduling
    # (DefMemPerCPU: a job without --mem takes its cores' share, not the whole node);
    # proctrack/linuxproc and task/affinity need no cgroup set-up (containers, CI machines);
    # job_comment: sacct shows the rule and wildcards the executor puts in --comment;
    # JobAcctGatherFrequency=task=1: jobs of a few seconds get a MaxRSS too (default 30 s).
    write_config /etc/slurm/slurm.conf <<EOF && changed=0
# Written by envs/slurm_cluster.sh for this machine ($cpus cores, $memory MB).
ClusterName=$CLUSTER
SlurmctldHost=$NODE(127.0.0.1)
SlurmUser=root
AuthType=auth/munge
StateSaveLocation=$STATE/slurmctld
SlurmdSpoolDir=$STATE/slurmd
SlurmctldPidFile=$SLURMCTLD_PID
SlurmdPidFile=$SLURMD_PID
SlurmctldLogFile=$LOGS/slurmctld.log
SlurmdLogFile=$LOGS/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/affinity
MpiDefault=none
ReturnToService=2
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core_Memory
DefMemPerCPU=$((memory / cpus))
JobAcctGatherType=jobacct_gather/linux
JobAcctGatherFrequency=task=1
AccountingStorageType=accounting_storage/slurmdbd
AccountingStorageHost=localhost
AccountingStorageEnforce=associations
AccountingStoreFlags=job_comment
NodeName=$NODE NodeAddr=127.0.0.1 CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=$PARTITION Nodes=$NODE MaxTime=INFINITE State=UP
EOF
    return $changed
}

start_munge() {
    alive "$MUNGE_PID" munged && return 0
    mkdir -p /run/munge && chown munge:munge /run/munge
    if [ ! -s /etc/munge/munge.key ]; then
        runuser -u munge -- mungekey --create --keyfile /etc/munge/munge.key
    fi
    runuser -u munge -- /usr/sbin/munged </dev/null >/dev/null 2>&1
    wait_for 30 munged /var/log/munge/munged.log sh -c "munge -n | unmunge"
}

start_mariadb() {
    if ! alive "$MARIADB_PID" mariadbd; then
        mkdir -p /run/mysqld && chown mysql:mysql /run/mysqld
        [ -d /var/lib/mysql/mysql ] || mariadb-install-db --user=mysql >&2
        setsid /usr/sbin/mariadbd --user=mysql --pid-file="$MARIADB_PID" \
            --log-error="$LOGS/mariadb.log" </dev/null >/dev/null 2>&1 &
    fi
    wait_for 60 MariaDB "$LOGS/mariadb.log" mariadb-admin ping
    mariadb <<EOF
CREATE USER IF NOT EXISTS 'slurm'@'localhost' IDENTIFIED BY 'slurm';
GRANT ALL ON slurm_acct_db.* TO 'slurm'@'localhost';
EOF
}

start_slurmdbd() {
    alive "$SLURMDBD_PID" slurmdbd || slurmdbd </dev/null >/dev/null 2>&1
    wait_for 60 slurmdbd "$LOGS/slurmdbd.log" sacctmgr -n show cluster
}

ensure_accounts() {
    if [ -z "$(sacctmgr -n -P show cluster "$CLUSTER" format=cluster)" ]; then
        sacctmgr -i add cluster "$CLUSTER" >/dev/null
    fi
    if [ -z "$(sacctmgr -n -P show account "$ACCOUNT" format=account)" ]; then
        sacctmgr -i add account "$ACCOUNT" cluster="$CLUSTER" description="suspension_fabric tests" >/dev/null
    fi
    local user
    user=$(id -un)
    if ! sacctmgr -n -P show assoc where user="$user" account="$ACCOUNT" format=account | grep -qx "$ACCOUNT"; then
        sacctmgr -i add user "$user" account="$ACCOUNT" cluster="$CLUSTER" >/dev/null
    fi
}

node_idle() { [ "$(sinfo -h -n "$NODE" -o %T)" = idle ]; }

start_slurm() {
    alive "$SLURMCTLD_PID" slurmctld || slurmctld </dev/null >/dev/null 2>&1
    wait_for 60 slurmctld "$LOGS/slurmctld.log" scontrol ping
    alive "$SLURMD_PID" slurmd || slurmd </dev/null >/dev/null 2>&1
    wait_for 90 "node $NODE (idle)" "$LOGS/slurmd.log" node_idle
}

# stop NAME PIDFILE: TERM, up to 30 s, then KILL; only the process named in its pid file.
stop() {
    local name=$1 pidfile=$2 pid
    alive "$pidfile" "$name" || return 0
    pid=$(cat "$pidfile")
    say "stopping $name ($pid)"
    kill "$pid" 2>/dev/null || return 0
    for _ in $(seq 60); do
        kill -0 "$pid" 2>/dev/null || return 0
        sleep 0.5
    done
    kill -9 "$pid" 2>/dev/null || true
}

up() {
    [ "$(id -u)" -eq 0 ] || { say "needs root"; exit 1; }
    local start=$SECONDS
    install_packages
    if write_configs && { alive "$SLURMCTLD_PID" slurmctld || alive "$SLURMD_PID" slurmd \
            || alive "$SLURMDBD_PID" slurmdbd; }; then
        say "configuration changed: restarting the SLURM daemons"
        stop_slurm
    fi
    start_munge
    start_mariadb
    start_slurmdbd
    ensure_accounts
    start_slurm
    say "up in $((SECONDS - start)) s: node $NODE $(nproc) cores, partition $PARTITION, account $ACCOUNT"
    echo "export SBATCH_ACCOUNT=$ACCOUNT SBATCH_PARTITION=$PARTITION"
}

stop_slurm() {
    if alive "$SLURMCTLD_PID" slurmctld; then
        scancel --partition="$PARTITION" 2>/dev/null || true
        for _ in $(seq 60); do
            [ -z "$(squeue -h -p "$PARTITION" 2>/dev/null)" ] && break
            sleep 0.5
        done
    fi
    stop slurmd "$SLURMD_PID"
    stop slurmctld "$SLURMCTLD_PID"
    stop slurmdbd "$SLURMDBD_PID"
}

down() {
    stop_slurm
    stop mariadbd "$MARIADB_PID"
    stop munged "$MUNGE_PID"
    # Without slurm.conf, SLURM's clients fail at once instead of trying the stopped controller
    # for 9 s; the Snakemake SLURM plugin runs `scontrol show config` whenever Snakemake starts.
    rm -f /etc/slurm/slurm.conf
    say "down"
}

case "${1:-}" in
    up) up ;;
    down) down ;;
    *) echo "usage: $0 up|down" >&2; exit 2 ;;
esac
