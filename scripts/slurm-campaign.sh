#!/usr/bin/env bash
# A `hil campaign` on a Slurm cluster (docs/campaigns.md): a job array of shards
# (`hil campaign --shard K/M`, one array task each) and a merge job that runs when every shard has
# succeeded (`--dependency=afterok`) and joins them into DIR/throws.csv, DIR/summary.txt and
# DIR/report.html, byte for byte what `hil campaign` in one process writes.
#
#   scripts/slurm-campaign.sh --attempts N --shards M --out DIR [--seed S] [--plant FILE]
#                             [--cpus C] [--hil PATH] [--no-report] [--dry-run] [-- SBATCH_OPTION...]
#
#   --cpus C       cores of each shard's task (its hil worker processes; default 1)
#   --hil PATH     the hil executable (default: build/host/hil/hil of this repository)
#   --dry-run      write the batch scripts and print the sbatch commands, submit nothing
#   after --        options for every sbatch call (--partition=..., --time=..., --account=...)
#
# DIR must be on a file system every node sees (a cluster's home or scratch). It gets
# DIR/slurm/{shard,merge}.sbatch and their logs (shard_<K>.out, merge.out) and DIR/shards/<K>.
# Prints the two job ids ("shards: job 12 (array 1-4)", "merge: job 13"). A shard that failed
# keeps the merge from running (Slurm cancels it); fly it again and merge again with
#   sbatch --array=K DIR/slurm/shard.sbatch && sbatch DIR/slurm/merge.sbatch
# (or `hil campaign merge --out DIR DIR/shards/*`, which names the attempts still missing).
# Needs sbatch on PATH; exits 2 on bad arguments, 1 when a submission fails.
set -euo pipefail

usage() {  # the opening comment
  sed -n '2,/^set -euo/p' "$0" | sed '$d' | sed 's/^# \{0,1\}//' >&2
  exit 2
}
die() {
  echo "slurm-campaign: $*" >&2
  exit 2
}
count() {  # count NAME VALUE: a positive decimal
  [[ "$2" =~ ^[1-9][0-9]*$ ]] || die "$1 needs a positive count, got '$2'"
}

repo=$(cd "$(dirname "$0")/.." && pwd)
attempts="" shards="" out="" seed=1 plant="" cpus=1 hil="$repo/build/host/hil/hil" report=1 dry_run=0
sbatch_options=()
while [ $# -gt 0 ]; do
  case "$1" in
    --attempts | --shards | --out | --seed | --plant | --cpus | --hil)
      [ $# -ge 2 ] || die "$1 needs a value"
      case "$1" in
        --attempts) attempts=$2 ;;
        --shards) shards=$2 ;;
        --out) out=$2 ;;
        --seed) seed=$2 ;;
        --plant) plant=$2 ;;
        --cpus) cpus=$2 ;;
        --hil) hil=$2 ;;
      esac
      shift 2
      ;;
    --no-report) report=0 && shift ;;
    --dry-run) dry_run=1 && shift ;;
    --) shift && sbatch_options=("$@") && break ;;
    -h | --help) usage ;;
    *) die "unknown argument '$1' (--help lists them)" ;;
  esac
done
[ -n "$attempts" ] || die "--attempts is required"
[ -n "$shards" ] || die "--shards is required"
[ -n "$out" ] || die "--out is required"
count --attempts "$attempts"
count --shards "$shards"
count --cpus "$cpus"
[[ "$seed" =~ ^[0-9]+$ ]] || die "--seed needs a non-negative integer, got '$seed'"
[ "$shards" -le "$attempts" ] || die "--shards $shards is more than the $attempts attempts"
[ -x "$hil" ] || die "no hil executable at '$hil' (build it: cmake --build --preset host, or give --hil)"
hil=$(cd "$(dirname "$hil")" && pwd)/$(basename "$hil")
plant_option=()
if [ -n "$plant" ]; then
  [ -f "$plant" ] || die "no plant file '$plant'"
  plant_option=(--plant "$(cd "$(dirname "$plant")" && pwd)/$(basename "$plant")")
fi
report_option=()
[ "$report" = 1 ] || report_option=(--no-report)
if [ "$dry_run" = 0 ] && ! command -v sbatch >/dev/null; then
  echo "slurm-campaign: sbatch not found (Slurm's client commands; Debian: slurm-client)" >&2
  exit 1
fi

mkdir -p "$out/slurm" "$out/shards"
out=$(cd "$out" && pwd)
# Slurm reads #SBATCH lines without the shell's quoting.
[[ "$out" != *[[:space:]]* ]] || die "--out '$out' has white space, which #SBATCH --output cannot take"

# The batch scripts, every value quoted as the shell reads it back.
q() { printf '%q' "$1"; }
{
  echo "#!/bin/bash"
  echo "#SBATCH --job-name=hil-campaign-shard"
  echo "#SBATCH --cpus-per-task=$cpus"
  echo "#SBATCH --output=$out/slurm/shard_%a.out"
  echo "# Shard \$SLURM_ARRAY_TASK_ID of $shards of a campaign of $attempts attempts, seed $seed."
  echo "set -euo pipefail"
  echo "k=\$SLURM_ARRAY_TASK_ID"
  printf 'exec %s campaign --attempts %s --seed %s' "$(q "$hil")" "$attempts" "$seed"
  for o in "${plant_option[@]}"; do printf ' %s' "$(q "$o")"; done
  printf ' --shard "$k/%s" --jobs "${SLURM_CPUS_PER_TASK:-1}" --out %s/"$k"\n' "$shards" "$(q "$out/shards")"
} >"$out/slurm/shard.sbatch"
{
  echo "#!/bin/bash"
  echo "#SBATCH --job-name=hil-campaign-merge"
  echo "#SBATCH --output=$out/slurm/merge.out"
  echo "# The $shards shards of the campaign joined into $out."
  echo "set -euo pipefail"
  echo "shards=()"
  echo "for k in \$(seq 1 $shards); do shards+=($(q "$out/shards")/\"\$k\"); done"
  printf 'exec %s campaign merge --out %s' "$(q "$hil")" "$(q "$out")"
  for o in "${report_option[@]}"; do printf ' %s' "$o"; done
  printf ' "${shards[@]}"\n'
} >"$out/slurm/merge.sbatch"

if [ "$dry_run" = 1 ]; then
  echo "sbatch --parsable --array=1-$shards ${sbatch_options[*]} $out/slurm/shard.sbatch"
  echo "sbatch --parsable --dependency=afterok:<shards' job> --kill-on-invalid-dep=yes ${sbatch_options[*]} $out/slurm/merge.sbatch"
  exit 0
fi
submit() {  # prints the job id (sbatch --parsable says "id" or "id;cluster")
  local answer
  if ! answer=$(sbatch --parsable "$@"); then
    echo "slurm-campaign: sbatch $* failed" >&2
    exit 1
  fi
  echo "${answer%%;*}"
}
array_job=$(submit --array=1-"$shards" "${sbatch_options[@]}" "$out/slurm/shard.sbatch")
merge_job=$(submit --dependency=afterok:"$array_job" --kill-on-invalid-dep=yes "${sbatch_options[@]}" \
  "$out/slurm/merge.sbatch")
echo "shards: job $array_job (array 1-$shards), logs $out/slurm/shard_<K>.out"
echo "merge: job $merge_job, after every shard succeeded; log $out/slurm/merge.out, results in $out"
