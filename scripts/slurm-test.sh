#!/usr/bin/env bash
# slurm-test.sh: runs a sharded sweep on a real, one-node Slurm started on this host.
#
# Installs Debian's Slurm and munge (apt-get), writes a one-node slurm.conf for this host
# (no cgroups, no accounting), starts munged, slurmctld and slurmd, submits the script
# that `rollstack slurm` writes for a 4-task frequency sweep, waits for its merge job,
# checks that the merged CSV equals a single-machine run of the same sweep, and stops
# the daemons it started by their PIDs. Needs root (apt and the daemons). Prints the
# round-trip time from submission to the merged output.
#
# Usage: scripts/slurm-test.sh [ROLLSTACK-BINARY]   (default: builds the release binary)
set -euo pipefail
cd "$(dirname "$0")/.."
ROOT=$PWD

if ! command -v sbatch >/dev/null || ! command -v slurmctld >/dev/null || ! command -v munged >/dev/null; then
    if ! command -v apt-get >/dev/null; then
        echo "slurm-test: SKIPPED: Slurm is not installed and apt-get is not available to install it" >&2
        exit 0
    fi
    echo "== installing slurm-wlm and munge"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq
    apt-get install -y -qq --no-install-recommends slurm-wlm munge >/dev/null
fi

if [ $# -ge 1 ]; then
    BIN=$(realpath "$1")
else
    echo "== cargo build --release -p rollstack"
    cargo build --release -q -p rollstack
    BIN=$(realpath "${CARGO_TARGET_DIR:-target}/release/rollstack")
fi

WORK=$(mktemp -d /tmp/rollstack-slurm.XXXXXX)
chmod 755 "$WORK"
PIDS=()
stop_daemons() {
    for pid in "${PIDS[@]}"; do
        kill "$pid" 2>/dev/null || true
    done
    for pid in "${PIDS[@]}"; do
        for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    done
}
trap 'stop_daemons; echo "slurm-test: the daemons are stopped; their state and logs are in $WORK" >&2' EXIT

echo "== starting munged, slurmctld and slurmd (state in $WORK)"
mkdir -p "$WORK/munge" "$WORK/spool/ctld" "$WORK/spool/d" "$WORK/log" "$WORK/run"
chown munge:munge "$WORK/munge"
chmod 755 "$WORK/munge"
if [ ! -s /etc/munge/munge.key ]; then
    dd if=/dev/urandom bs=1 count=1024 of=/etc/munge/munge.key 2>/dev/null
    chown munge:munge /etc/munge/munge.key
    chmod 400 /etc/munge/munge.key
fi
SOCKET=$WORK/munge/munge.socket
runuser -u munge -- munged --socket="$SOCKET" --pid-file="$WORK/munge/munged.pid" \
    --log-file="$WORK/munge/munged.log" --seed-file="$WORK/munge/seed"
for _ in $(seq 50); do [ -s "$WORK/munge/munged.pid" ] && break; sleep 0.1; done
PIDS+=("$(cat "$WORK/munge/munged.pid")")

NODE=$(slurmd -C | head -1 | sed -e 's/^NodeName=[^ ]*/NodeName=localhost/')
PORT_BASE=$((20000 + RANDOM % 20000))
cat > "$WORK/slurm.conf" <<CONF
ClusterName=rollstack-test
SlurmctldHost=localhost(127.0.0.1)
SlurmctldPort=$PORT_BASE
SlurmdPort=$((PORT_BASE + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$SOCKET
CredType=cred/munge
StateSaveLocation=$WORK/spool/ctld
SlurmdSpoolDir=$WORK/spool/d
SlurmctldPidFile=$WORK/run/slurmctld.pid
SlurmdPidFile=$WORK/run/slurmd.pid
SlurmctldLogFile=$WORK/log/slurmctld.log
SlurmdLogFile=$WORK/log/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
DependencyParameters=kill_invalid_depend
SchedulerParameters=batch_sched_delay=0
MailProg=/bin/true
ReturnToService=2
$NODE NodeAddr=127.0.0.1 State=UNKNOWN
PartitionName=debug Nodes=localhost Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$WORK/slurm.conf
slurmctld -f "$SLURM_CONF"
for _ in $(seq 50); do [ -s "$WORK/run/slurmctld.pid" ] && break; sleep 0.1; done
PIDS+=("$(cat "$WORK/run/slurmctld.pid")")
slurmd -f "$SLURM_CONF" -N localhost
for _ in $(seq 50); do [ -s "$WORK/run/slurmd.pid" ] && break; sleep 0.1; done
PIDS+=("$(cat "$WORK/run/slurmd.pid")")
for _ in $(seq 100); do
    sinfo -h -o %T 2>/dev/null | grep -q -E '^(idle|mixed)' && break
    sleep 0.2
done
sinfo

SWEEP=(blocks sweep frequency --omega 2:9:1 --periods 2 --blocks 2)
cd "$WORK"
echo "== rollstack slurm --tasks 4 ${SWEEP[*]} --out $WORK/freq"
T0=$(date +%s.%N)
"$BIN" slurm --tasks 4 "${SWEEP[@]}" --out "$WORK/freq"
SUBMITTED=$(bash "$WORK/freq/slurm/submit.sh")
echo "$SUBMITTED"
MERGE=$(echo "$SUBMITTED" | sed -n 's/.*merge job \([0-9]*\).*/\1/p' | head -1)
ARRAY=$(echo "$SUBMITTED" | sed -n 's/.*job array \([0-9]*\).*/\1/p' | head -1)
for _ in $(seq 1500); do
    squeue -h -j "$ARRAY,$MERGE" 2>/dev/null | grep -q . || break
    sleep 0.2
done
T1=$(date +%s.%N)
STATE=$(scontrol show job "$MERGE" 2>/dev/null | sed -n 's/.*JobState=\([A-Z_]*\).*/\1/p')
if [ "$STATE" != COMPLETED ]; then
    echo "slurm-test: FAILED: the merge job $MERGE ended in state '${STATE:-unknown}'" >&2
    scontrol show job "$ARRAY" >&2 || true
    tail -n 20 "$WORK"/freq/slurm/logs/*.out "$WORK/log/slurmctld.log" >&2 || true
    exit 1
fi

echo "== the same sweep on one machine"
"$BIN" "${SWEEP[@]}" --out "$WORK/single" >/dev/null
# The merged CSV must equal the single run's, apart from the timing column wall_time_s.
python3 - "$WORK/single/sweep_frequency.csv" "$WORK/freq/sweep_frequency.csv" <<'PY'
import csv, sys
def rows(path):
    with open(path, newline="") as f:
        table = list(csv.reader(f))
    keep = [i for i, name in enumerate(table[0]) if name != "wall_time_s"]
    return [[r[i] for i in keep] for r in table]
a, b = rows(sys.argv[1]), rows(sys.argv[2])
if a != b or len(a) != 9:
    sys.exit(f"slurm-test: FAILED: the merged CSV differs from the single run's:\n{a}\n{b}")
PY
cmp "$WORK/single/sweep_frequency.png" "$WORK/freq/sweep_frequency.png"
echo "slurm-test: OK: 4 array tasks and a merge job, 8 rows; the merged CSV and plot equal a single run's"
awk -v a="$T0" -v b="$T1" 'BEGIN { printf "slurm-test: round trip (rollstack slurm, calibration, submission, 4 tasks, merge) %.1f s\n", b - a }'
stop_daemons
trap - EXIT
rm -rf "$WORK"
