#!/usr/bin/env bash
# Runs every libFuzzer target of the fuzz build (tests/fuzz) for FUZZ_SECONDS each (default 600)
# on its checked-in corpus, and prints per target: executions per second, coverage (cov: edges,
# ft: features), corpus size and crashes. New inputs go to build/fuzz/fuzz-scratch/<target>
# (never into tests/fuzz/corpus), crashing inputs to build/fuzz/fuzz-artifacts/<target>/, logs
# to build/fuzz/fuzz-logs/<target>.log. Usage: scripts/fuzz.sh [target ...] (default: all).
# Exit status 1 when any target crashed.
set -uo pipefail

cd "$(dirname "$0")/.."
build=build/fuzz/tests/fuzz
seconds=${FUZZ_SECONDS:-600}
targets=("$@")
[ ${#targets[@]} -eq 0 ] && targets=(protocol vehicle mocap yaml_config adaptation_store)

failed=0
printf '%-18s %10s %8s %8s %8s %8s %s\n' target exec/s cov ft corpus crashes log
for t in "${targets[@]}"; do
  exe=$build/${t}_fuzz
  if [ ! -x "$exe" ]; then
    echo "fuzz: $exe is missing (make fuzz builds it)" >&2
    exit 2
  fi
  scratch=build/fuzz/fuzz-scratch/$t
  artifacts=build/fuzz/fuzz-artifacts/$t
  log=build/fuzz/fuzz-logs/$t.log
  mkdir -p "$scratch" "$artifacts" "$(dirname "$log")"
  before=$(find "$artifacts" -type f | wc -l)
  # -fork keeps fuzzing past a crash, so one run reports every distinct crash it meets.
  nice -n 19 "$exe" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=1 \
    -fork=1 -ignore_crashes=1 -ignore_timeouts=1 -ignore_ooms=1 \
    -artifact_prefix="$artifacts/" "$scratch" "tests/fuzz/corpus/$t" >"$log" 2>&1
  crashes=$(($(find "$artifacts" -type f | wc -l) - before))
  # The last status line of the fork mode: "#N: cov: C ft: F corp: K exec/s E oom/timeout/crash: ...".
  last=$(grep -E '^#[0-9]+' "$log" | tail -1)
  field() { sed -nE "s|.* $1:? ([0-9]+).*|\1|p" <<<"$last"; }
  printf '%-18s %10s %8s %8s %8s %8s %s\n' "$t" "$(field exec/s)" "$(field cov)" "$(field ft)" \
    "$(field corp)" "$crashes" "$log"
  [ "$crashes" -gt 0 ] && failed=1
done
exit $failed
