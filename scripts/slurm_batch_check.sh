#!/usr/bin/env bash
# Runs `sdcb batch` as a Slurm array job on a one-node Slurm that this script
# starts itself (munged, slurmctld, slurmd in the foreground as children of
# this script: no systemd, no files outside WORK_DIR, ports chosen at
# random), then checks the result:
#   - the 2 array tasks together produced every output of the manifest, and
#     each task ran exactly the rows of its shard (row % 2 == task index,
#     from SLURM_ARRAY_TASK_ID / _MIN / _COUNT, no --shard given);
#   - a second submission of the same array converts nothing (all skipped).
# Needs root and Debian's slurmctld, slurmd, slurm-client and munge
# (scripts/setup.sh installs them). Exit 0: checked; 1: a check failed;
# 77: Slurm or munge is not installed (ctest counts that as skipped).
#   bash scripts/slurm_batch_check.sh SDCB_BINARY MESH_DIR WORK_DIR
set -euo pipefail

sdcb=$(readlink -f "${1:?usage: slurm_batch_check.sh SDCB MESH_DIR WORK_DIR}")
mesh_dir=$(readlink -f "${2:?mesh dir}")
work=${3:?work dir}

for tool in munged slurmctld slurmd sbatch squeue; do
  if ! command -v "$tool" >/dev/null && [ ! -x "/usr/sbin/$tool" ]; then
    echo "slurm_batch_check: $tool is missing (scripts/setup.sh installs Slurm and munge)" >&2
    exit 77
  fi
done
if [ "$(id -u)" != 0 ]; then
  echo "slurm_batch_check: needs root (slurmd runs jobs as their user)" >&2
  exit 77
fi
PATH=$PATH:/usr/sbin

rm -rf "$work"
mkdir -p "$work"/{munge,state,spool,logs,out}
work=$(readlink -f "$work")
chmod 700 "$work/munge"
pids=()
cleanup() {
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  wait 2>/dev/null || true
}
trap cleanup EXIT
fail() {
  echo "slurm_batch_check: FAILED: $*" >&2
  for log in "$work"/logs/*.log; do
    echo "--- $log" >&2
    tail -n 20 "$log" >&2
  done
  exit 1
}

# munge with its own key and socket.
dd if=/dev/urandom of="$work/munge/munge.key" bs=1024 count=1 status=none
chmod 400 "$work/munge/munge.key"
munged --foreground --force --key-file="$work/munge/munge.key" \
  --socket="$work/munge/munge.socket" --pid-file="$work/munge/munged.pid" \
  --seed-file="$work/munge/munged.seed" --log-file="$work/logs/munged.log" \
  2>>"$work/logs/munged.log" &
pids+=($!)

host=$(hostname -s)
cpus=$(nproc)
memory=$(( $(awk '/MemTotal/ {print $2}' /proc/meminfo) / 1024 / 2 ))
port=$(( 20000 + RANDOM % 20000 ))
export SLURM_CONF=$work/slurm.conf
cat > "$SLURM_CONF" <<EOF
ClusterName=sdcbcheck
SlurmctldHost=$host
SlurmctldPort=$port
SlurmdPort=$((port + 1))
SlurmUser=root
SlurmdUser=root
AuthType=auth/munge
AuthInfo=socket=$work/munge/munge.socket
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
SlurmctldLogFile=$work/logs/slurmctld.log
SlurmdLogFile=$work/logs/slurmd.log
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
SelectType=select/cons_tres
SelectTypeParameters=CR_CPU
MpiDefault=none
ReturnToService=2
SchedulerType=sched/backfill
NodeName=$host CPUs=$cpus RealMemory=$memory State=UNKNOWN
PartitionName=check Nodes=$host Default=YES MaxTime=INFINITE State=UP
EOF

for i in $(seq 50); do [ -S "$work/munge/munge.socket" ] && break; sleep 0.1; done
[ -S "$work/munge/munge.socket" ] || fail "munged did not start"
slurmctld -D -i -f "$SLURM_CONF" 2>>"$work/logs/slurmctld.log" &
pids+=($!)
slurmd -D -f "$SLURM_CONF" 2>>"$work/logs/slurmd.log" &
pids+=($!)
for i in $(seq 100); do
  state=$(sinfo -h -o %t 2>/dev/null || true)
  [ "$state" = idle ] && break
  sleep 0.2
done
[ "$state" = idle ] || fail "the node did not become idle (state '$state')"

# Six small assets, coarse fits; rows 0..5.
manifest=$work/manifest.txt
for mesh in ellipsoid geosphere blob-closed dragknob icosahedron cube-meshed; do
  echo "$mesh_dir/$mesh.off out/$mesh.sdcb --rmse 1 --max-rounds 1"
done > "$manifest"
cat > "$work/job.sh" <<EOF
#!/bin/bash
#SBATCH --array=0-1
#SBATCH --cpus-per-task=1
#SBATCH --output=$work/logs/job-%A_%a.log
exec "$sdcb" batch "$manifest" \
  --json-lines "$work/results.\${SLURM_ARRAY_TASK_ID}.\${SLURM_ARRAY_JOB_ID}.jsonl"
EOF

# Submits the array and waits for it (polling: `sbatch --wait` backs off to
# tens of seconds); fails unless every task exited 0.
submit() {
  local id
  id=$(sbatch --parsable "$work/job.sh") || fail "sbatch failed"
  for i in $(seq 1200); do
    [ -z "$(squeue -h -j "$id" 2>/dev/null)" ] && break
    sleep 0.25
  done
  [ -z "$(squeue -h -j "$id")" ] || fail "array job $id still running after 5 minutes"
  for task in 0 1; do
    grep -q "shard $task/2 (SLURM_ARRAY_TASK_ID)" "$work/logs/job-${id}_$task.log" ||
      fail "task $task did not report its shard"
    grep -q " 0 failed" "$work/logs/job-${id}_$task.log" || fail "task $task failed"
  done
  echo "$id"
}

start=$(date +%s%N)
job=$(submit)
seconds=$(( ($(date +%s%N) - start) / 1000000 ))
python3 - "$work" "$job" <<'EOF' || fail "first run"
import json, os, sys
work, job = sys.argv[1], sys.argv[2]
seen = {}
for task in (0, 1):
    for line in open(f"{work}/results.{task}.{job}.jsonl"):
        j = json.loads(line)
        assert j["status"] == "ok", j
        assert j["row"] % 2 == task, (task, j["row"])
        assert j["row"] not in seen, j["row"]
        seen[j["row"]] = j["output"]
assert sorted(seen) == list(range(6)), sorted(seen)
for out in seen.values():
    assert os.path.getsize(out) > 0, out
EOF
job2=$(submit)
python3 - "$work" "$job2" <<'EOF' || fail "rerun"
import json, sys
work, job = sys.argv[1], sys.argv[2]
rows = []
for task in (0, 1):
    for line in open(f"{work}/results.{task}.{job}.jsonl"):
        j = json.loads(line)
        assert j["status"] == "skipped", j
        rows.append(j["row"])
assert sorted(rows) == list(range(6)), rows
EOF
echo "slurm_batch_check: ok: array job $job (2 tasks, 6 rows) in ${seconds} ms; rerun $job2 skipped all 6"
