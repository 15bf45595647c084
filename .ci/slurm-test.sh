#!/usr/bin/env bash
# A real one-node SLURM cluster on this machine, and a campaign run on it as a job array.
#
# Installs Debian's slurm-wlm and munge when missing (as root or through sudo), writes a
# minimal slurm.conf for this host into a temporary folder, starts munged, slurmctld and slurmd
# there, then:
#   1. `usar campaign slurm --preset smoke --tasks 4 --submit`: 4 array tasks and the merge;
#      the merged results must equal an unsharded run's (`usar campaign export` CSVs);
#   2. resume: a fresh submission of which task 2 is cancelled with `scancel` while it runs;
#      `usar campaign status` shows it unfinished; submitting again completes it, and the
#      merged results again equal the unsharded run's.
# Every daemon it started is stopped when it ends, passed or failed.
#
# Usage: .ci/slurm-test.sh [path/to/usar]   (default: target/release/usar, built if missing)
set -euo pipefail

cd "$(dirname "$0")/.."
USAR=$(realpath "${1:-target/release/usar}")
if [ ! -x "$USAR" ]; then
    cargo build --release --quiet
fi

as_root() {
    if [ "$(id -u)" -eq 0 ]; then "$@"; else sudo "$@"; fi
}

if ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
    as_root apt-get update -qq
    as_root env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
        slurm-wlm munge >/dev/null
fi
if [ "$(id -u)" -ne 0 ]; then
    echo "slurm-test: the daemons run as root here (SlurmUser=root); run as root" >&2
    exit 2
fi

WORK=$(mktemp -d /tmp/usar-slurm.XXXXXX)
export SLURM_CONF="$WORK/slurm.conf"
PIDS=()
cleanup() {
    status=$?
    for pid in "${PIDS[@]}"; do
        kill "$pid" 2>/dev/null || true
    done
    for f in "$WORK/slurmd.pid" "$WORK/slurmctld.pid" "$WORK/munge/munged.pid"; do
        if [ -s "$f" ]; then kill "$(cat "$f")" 2>/dev/null || true; fi
    done
    sleep 1
    if [ "$status" -ne 0 ]; then
        echo "slurm-test: failed; daemon logs:" >&2
        tail -n 20 "$WORK"/*.log "$WORK"/munge/*.log 2>/dev/null >&2 || true
    fi
    rm -rf "$WORK"
    exit "$status"
}
trap cleanup EXIT

# munge: a key of its own, its socket in the work folder.
mkdir -p "$WORK/munge" "$WORK/state" "$WORK/spool"
chmod 700 "$WORK/munge"
dd if=/dev/urandom of="$WORK/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$WORK/munge/munge.key"
SOCKET="$WORK/munge/munge.socket"
munged --force --key-file="$WORK/munge/munge.key" --socket="$SOCKET" \
    --pid-file="$WORK/munge/munged.pid" --log-file="$WORK/munge/munged.log" \
    --seed-file="$WORK/munge/munged.seed"

free_port() {
    python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])'
}
HOST=$(hostname -s)
NODE=$(slurmd -C | head -n 1)
cat >"$SLURM_CONF" <<EOF
ClusterName=usar-ci
SlurmctldHost=$HOST
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$SOCKET
CredType=cred/munge
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
StateSaveLocation=$WORK/state
SlurmdSpoolDir=$WORK/spool
SlurmctldPidFile=$WORK/slurmctld.pid
SlurmdPidFile=$WORK/slurmd.pid
SlurmctldLogFile=$WORK/slurmctld.log
SlurmdLogFile=$WORK/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SchedulerType=sched/backfill
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
MpiDefault=none
ReturnToService=2
$NODE State=UNKNOWN
PartitionName=ci Nodes=$HOST Default=YES MaxTime=INFINITE State=UP
EOF
slurmctld -i
slurmd
for _ in $(seq 60); do
    if sinfo -h -o %T 2>/dev/null | grep -qE '^(idle|mixed|allocated)'; then break; fi
    sleep 1
done
sinfo -h -o '%P %D %T' | grep -qE 'idle|mixed' || { echo "slurm-test: the node did not come up" >&2; exit 1; }

# Waits until no job of this user is queued or running.
wait_jobs() {
    for _ in $(seq 600); do
        if [ -z "$(squeue -h -o %i)" ]; then return 0; fi
        sleep 1
    done
    echo "slurm-test: jobs still queued after 10 minutes" >&2
    squeue >&2
    return 1
}

# The unsharded reference.
"$USAR" campaign run --preset smoke --out "$WORK/whole" --json >/dev/null
"$USAR" campaign export "$WORK/whole" --csv "$WORK/whole.csv" >/dev/null

# 1. Four tasks and the merge.
"$USAR" campaign slurm --preset smoke --out "$WORK/array" --tasks 4 --submit
wait_jobs
"$USAR" campaign status "$WORK/array"
"$USAR" campaign export "$WORK/array/merged" --csv "$WORK/array.csv" >/dev/null
cmp "$WORK/whole.csv" "$WORK/array.csv"
echo "slurm-test: 4 array tasks merged into the unsharded run's results"

# 2. Resume after cancelling task 2 while it runs.
ids=$("$USAR" campaign slurm --preset smoke --out "$WORK/resume" --tasks 4 --submit --json |
    python3 -c 'import json, sys; print(json.load(sys.stdin)["submitted"])')
array=$(echo "$ids" | awk '{print $2}')
merge=$(echo "$ids" | awk '{print $4}')
for _ in $(seq 300); do
    state=$(squeue -h -j "${array}_2" -o %T 2>/dev/null || true)
    if [ "$state" = "RUNNING" ]; then break; fi
    sleep 0.2
done
scancel "${array}_2"
# The merge never runs now (its dependency cannot be met): cancel it too.
scancel "$merge"
wait_jobs
"$USAR" campaign status "$WORK/resume" --json | python3 -c '
import json, sys
s = json.load(sys.stdin)
states = [x["state"] for x in s["shards"]]
assert states[1] != "done", states
assert not s["merged"], s
print("slurm-test: after scancel, shard 2 is", states[1])'
"$USAR" campaign slurm --preset smoke --out "$WORK/resume" --tasks 4 --submit
wait_jobs
"$USAR" campaign status "$WORK/resume" --json | python3 -c '
import json, sys
s = json.load(sys.stdin)
assert all(x["state"] == "done" for x in s["shards"]), s
assert s["merged"], s'
"$USAR" campaign export "$WORK/resume/merged" --csv "$WORK/resume.csv" >/dev/null
cmp "$WORK/whole.csv" "$WORK/resume.csv"
echo "slurm-test: resumed after scancel; merged results equal the unsharded run's"
