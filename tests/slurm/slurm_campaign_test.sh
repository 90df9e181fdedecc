#!/usr/bin/env bash
# A campaign on a real Slurm (docs/campaigns.md): starts munged, slurmctld and slurmd (one node,
# this machine, as root, no systemd) in a temporary folder, submits a campaign of 8 attempts as a
# 4-shard job array and its merge with scripts/slurm-campaign.sh, waits, and compares the merged
# throws.csv and summary.txt with `hil campaign` in one process, byte for byte; then loses shard 2,
# checks that the merge names its attempts, flies it again alone and merges again. The daemons are
# stopped by their process ids at the end, also on failure.
#
#   tests/slurm/slurm_campaign_test.sh HIL SLURM_CAMPAIGN_SH
#
# Exits 77 (ctest's SKIP_RETURN_CODE) only when Slurm or munge is not installed.
set -euo pipefail

hil=${1:?usage: slurm_campaign_test.sh HIL SLURM_CAMPAIGN_SH}
submit=${2:?usage: slurm_campaign_test.sh HIL SLURM_CAMPAIGN_SH}
attempts=8 shards=4 seed=3

for program in munged slurmctld slurmd sbatch squeue scontrol; do
  if ! command -v "$program" >/dev/null; then
    echo "SKIP: $program is not installed (Debian: slurm-wlm and munge; scripts/install-deps.sh)"
    exit 77
  fi
done

work=$(mktemp -d /tmp/slurm_campaign_test.XXXXXX)
pids=()
stop() {
  local code=$?
  # Jobs still running (a failure) are cancelled first, so that no slurmstepd outlives slurmd.
  if [ -n "${SLURM_CONF:-}" ] && [ -n "$(squeue -h -o %i 2>/dev/null)" ]; then
    timeout 10 scancel --quiet $(squeue -h -o %i) 2>/dev/null || true
    for _ in $(seq 50); do [ -z "$(squeue -h -o %i 2>/dev/null)" ] && break; sleep 0.2; done
  fi
  for pid in "${pids[@]}"; do kill "$pid" 2>/dev/null || true; done
  for pid in "${pids[@]}"; do
    for _ in $(seq 50); do kill -0 "$pid" 2>/dev/null || break; sleep 0.1; done
    kill -9 "$pid" 2>/dev/null || true
  done
  if [ "$code" -ne 0 ]; then
    for log in "$work"/*.log "$work"/*.stderr "$work"/campaign/slurm/*.out; do
      [ -f "$log" ] && { echo "--- $log"; tail -n 30 "$log"; }
    done
  fi
  rm -rf "$work"
  exit "$code"
}
trap stop EXIT
trap 'exit 1' INT TERM
fail() {
  echo "FAIL: $*"
  exit 1
}

# The one-process campaign first: the shards then have the cores to themselves.
"$hil" campaign --attempts $attempts --seed $seed --jobs 2 --no-report --out "$work/whole" \
  >"$work/whole.txt" 2>/dev/null || fail "hil campaign in one process failed"

# A port nobody listens on (parallel runs of this test pick different ones).
free_port() {
  local port
  for _ in $(seq 100); do
    port=$((20000 + RANDOM % 30000))
    if ! (exec 3<>"/dev/tcp/127.0.0.1/$port") 2>/dev/null; then
      echo "$port"
      return
    fi
  done
  fail "no free port"
}

# munge: its own key, socket, pid, seed and log (--force: the folder's permissions are a test's).
mkdir -p "$work/munge" "$work/state" "$work/spool"
chmod 700 "$work/munge"
head -c 1024 /dev/urandom >"$work/munge/munge.key"
chmod 400 "$work/munge/munge.key"
socket="$work/munge/munge.socket"
munged --foreground --force --key-file="$work/munge/munge.key" --socket="$socket" \
  --pid-file="$work/munge/munged.pid" --seed-file="$work/munge/munged.seed" \
  --log-file="$work/munged.log" 2>"$work/munged.stderr" &
pids+=($!)
for _ in $(seq 50); do [ -S "$socket" ] && break; sleep 0.1; done
[ -S "$socket" ] || fail "munged did not open its socket"

host=$(hostname -s)
user=$(id -un)
cpus=$(nproc)
cat >"$work/slurm.conf" <<EOF
ClusterName=pa-test
SlurmctldHost=$host
SlurmctldPort=$(free_port)
SlurmdPort=$(free_port)
SlurmUser=$user
SlurmdUser=$user
AuthType=auth/munge
CredType=cred/munge
AuthInfo=socket=$socket
StateSaveLocation=$work/state
SlurmdSpoolDir=$work/spool
SlurmctldPidFile=$work/slurmctld.pid
SlurmdPidFile=$work/slurmd.pid
ProctrackType=proctrack/linuxproc
TaskPlugin=task/none
SwitchType=switch/none
MpiDefault=none
JobAcctGatherType=jobacct_gather/none
AccountingStorageType=accounting_storage/none
JobCompType=jobcomp/none
SchedulerType=sched/builtin
SelectType=select/cons_tres
SelectTypeParameters=CR_Core
ReturnToService=2
SlurmdParameters=config_overrides
MailProg=/bin/true
PlugStackConfig=$work/plugstack.conf
NodeName=pa_test_node NodeAddr=127.0.0.1 NodeHostname=$host CPUs=$cpus State=UNKNOWN
PartitionName=pa_test Nodes=pa_test_node Default=YES MaxTime=INFINITE State=UP
EOF
: >"$work/plugstack.conf"
export SLURM_CONF="$work/slurm.conf"

# In the foreground (-D) they log to stderr.
slurmctld -D -c -f "$SLURM_CONF" >"$work/slurmctld.log" 2>&1 &
pids+=($!)
slurmd -D -N pa_test_node -f "$SLURM_CONF" >"$work/slurmd.log" 2>&1 &
pids+=($!)
state=""
for _ in $(seq 300); do
  state=$(sinfo -h -n pa_test_node -o %T 2>/dev/null || true)
  [ "$state" = idle ] && break
  sleep 0.1
done
[ "$state" = idle ] || fail "the node did not come up (state '$state')"

started=$(date +%s)
"$submit" --hil "$hil" --attempts $attempts --shards $shards --seed $seed --cpus 1 --no-report \
  --out "$work/campaign" >"$work/submit.txt" || fail "slurm-campaign.sh failed: $(cat "$work/submit.txt")"
cat "$work/submit.txt"
merge_job=$(sed -n 's/^merge: job \([0-9]*\).*/\1/p' "$work/submit.txt")
[ -n "$merge_job" ] || fail "no merge job id in: $(cat "$work/submit.txt")"

# Until no job is left (sbatch --wait polls every few seconds), at most 3 minutes.
wait_for_jobs() {
  for _ in $(seq 900); do
    [ -z "$(squeue -h -o %i 2>/dev/null)" ] && return 0
    sleep 0.2
  done
  fail "the jobs still run after 3 minutes: $(squeue 2>&1)"
}
wait_for_jobs
echo "the jobs ended after $(($(date +%s) - started)) s"

[ -f "$work/campaign/throws.csv" ] || fail "the merge wrote no throws.csv"
cmp "$work/whole/throws.csv" "$work/campaign/throws.csv" || fail "throws.csv differs from the one-process run"
cmp "$work/whole/summary.txt" "$work/campaign/summary.txt" || fail "summary.txt differs from the one-process run"
cat "$work/campaign/slurm/merge.out"

# A shard lost (its manifest gone, as when its task is killed before the end): the merge names its
# attempts; flown again alone on Slurm, the campaign is complete and the same again.
rm "$work/campaign/shards/2/shard.txt"
shard_dirs=()
for k in $(seq 1 $shards); do shard_dirs+=("$work/campaign/shards/$k"); done
if "$hil" campaign merge --no-report --out "$work/remerged" "${shard_dirs[@]}" >/dev/null 2>"$work/missing.txt"; then
  fail "the merge of a lost shard succeeded"
fi
grep -q "2 of 8 attempts missing: 3-4 (shard 2/4)" "$work/missing.txt" || fail "unexpected: $(cat "$work/missing.txt")"
sbatch --array=2 "$work/campaign/slurm/shard.sbatch" >/dev/null || fail "shard 2 could not be submitted again"
wait_for_jobs
"$hil" campaign merge --no-report --out "$work/remerged" "${shard_dirs[@]}" >/dev/null ||
  fail "the merge after shard 2 was flown again failed"
cmp "$work/whole/throws.csv" "$work/remerged/throws.csv" || fail "throws.csv differs after shard 2 was flown again"
echo "PASS: $shards shards on Slurm merged equal the one-process campaign of $attempts attempts;" \
  "a lost shard flown again completes it"
