#!/usr/bin/env bash
# A sharded `bench` on real schedulers, as docs/cli.md tells: the sweep split in 2 shards run by GNU
# parallel, and as a Slurm array job on a single-node cluster started here (munged, slurmctld and
# slurmd with a configuration in a temporary folder); each pair of shards merged must give the rows
# of the unsplit sweep: labels, PIP, rays and errors equal.  tests/scheduler_check.sh PENUMBRA_CLI
set -euo pipefail
cli=$(realpath "$1")
tmp=$(mktemp -d)
daemons=()
cleanup() {
  [ -f "$tmp/slurm.conf" ] && SLURM_CONF=$tmp/slurm.conf scontrol shutdown >/dev/null 2>&1 || true
  [ -S "$tmp/munge/sock" ] && munged --stop --socket="$tmp/munge/sock" >/dev/null 2>&1 || true
  rm -rf "$tmp"
}
trap cleanup EXIT
sweep=(bench --scenes builtin:square --methods sm,pcf --pcf-kernel 3x3,5x5 --res 32x32 --repeat 1 --warmup 0
  --temporal-frames 0 --no-report --no-images)
"$cli" "${sweep[@]}" --out "$tmp/one" >/dev/null

# Rows of two merged bench.json files alike (what a shard measures in the same way is equal).
same_rows() {
  /usr/bin/python3 - "$1" "$2" <<'PY'
import json, sys
whole, merged = (json.load(open(p + "/bench.json"))["rows"] for p in sys.argv[1:])
assert len(whole) == len(merged) > 2, (len(whole), len(merged))
for w, m in zip(whole, merged):
    for key in ("label", "pip_fraction", "rays_traced", "error"):
        assert w.get(key) == m.get(key), (key, w.get(key), m.get(key))
print(f"{sys.argv[2]}: {len(merged)} rows, the unsplit sweep's")
PY
}

# GNU parallel: both shards at once on this machine.
parallel --halt now,fail=1 "$cli" "${sweep[@]}" --shard {}/2 --out "$tmp/parallel{}" ">/dev/null" ::: 1 2
"$cli" bench --no-report --merge "$tmp/parallel1,$tmp/parallel2" --out "$tmp/parallel" >/dev/null
same_rows "$tmp/one" "$tmp/parallel"

# Slurm: slurmd starts jobs as their users, so it runs as root.
if [ "$(id -u)" -ne 0 ]; then
  echo "scheduler_check: the Slurm half needs root (slurmd); skipped" >&2
  exit 77
fi
mkdir -p "$tmp/munge" "$tmp/state" "$tmp/spool" "$tmp/log"
chmod 700 "$tmp/munge"
head -c 1024 /dev/urandom >"$tmp/munge/munge.key"
chmod 400 "$tmp/munge/munge.key"
munged --force --key-file="$tmp/munge/munge.key" --socket="$tmp/munge/sock" --pid-file="$tmp/munge/pid" \
  --log-file="$tmp/munge/log" --seed-file="$tmp/munge/seed"
host=$(hostname -s)
port=$((20000 + $$ % 20000))  # two ports of its own, so that parallel test runs do not meet
cat >"$tmp/slurm.conf" <<CONF
ClusterName=penumbra
SlurmctldHost=$host
SlurmUser=root
AuthType=auth/munge
AuthInfo=socket=$tmp/munge/sock
CredType=cred/munge
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SwitchType=switch/none
MpiDefault=none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
ReturnToService=2
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmctldPidFile=$tmp/state/slurmctld.pid
SlurmdPidFile=$tmp/state/slurmd.pid
StateSaveLocation=$tmp/state
SlurmdSpoolDir=$tmp/spool
SlurmctldLogFile=$tmp/log/slurmctld.log
SlurmdLogFile=$tmp/log/slurmd.log
NodeName=$host CPUs=$(nproc) State=UNKNOWN
PartitionName=main Nodes=$host Default=YES MaxTime=INFINITE State=UP
CONF
export SLURM_CONF=$tmp/slurm.conf
slurmctld
slurmd
for _ in $(seq 60); do sinfo -h -o %T 2>/dev/null | grep -q idle && break; sleep 0.5; done
sinfo -h -o %T | grep -q idle || { tail -20 "$tmp/log/"*.log >&2; echo "scheduler_check: the node never came up" >&2; exit 1; }
# The array job as docs/cli.md writes it: each task runs its shard.
cat >"$tmp/job.sh" <<JOB
#!/bin/bash
exec "$cli" ${sweep[*]} --shard \$SLURM_ARRAY_TASK_ID/2 --out "$tmp/slurm\$SLURM_ARRAY_TASK_ID"
JOB
sbatch --wait --quiet --array=1-2 --output="$tmp/log/task-%a.out" "$tmp/job.sh" || { cat "$tmp/log/"task-*.out >&2; exit 1; }
"$cli" bench --no-report --merge "$tmp/slurm1,$tmp/slurm2" --out "$tmp/slurm" >/dev/null
same_rows "$tmp/one" "$tmp/slurm"
echo "scheduler_check: GNU parallel and Slurm shards merge into the unsplit sweep"
