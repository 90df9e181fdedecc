#!/usr/bin/env bash
# Processor in the loop (hil/sil/emulated_firmware.hpp): the host's `hil fly` flies both vehicles
# on the mps2-an386 PIL image (fw_mps2_an386_pil), each in its own qemu-system-arm, in lockstep
# with the plant: the take-off, one throw caught by vehicle 2 (no trial throw), then the pole
# taken down and both vehicles landed. Checks from what hil fly writes and prints: throws.csv's
# one attempt caught, no vehicle crashed, both landed, and every tick's guest instructions
# reported (HIL_TICK_COST) for both vehicles, no phase's worst tick over the budget hil prints.
# Usage: pil_flies_one_attempt.sh QEMU IMAGE ICOUNT_SHIFT HIL WORKDIR
set -euo pipefail
if [ $# -ne 5 ]; then
  echo "usage: pil_flies_one_attempt.sh QEMU IMAGE ICOUNT_SHIFT HIL WORKDIR" >&2
  exit 2
fi
qemu=$1 image=$2 shift_n=$3 hil=$4 work=$5
if ! command -v "$qemu" > /dev/null; then
  echo "FAIL: no QEMU ($qemu): make deps installs qemu-system-arm"
  exit 1
fi
if [ ! -x "$hil" ]; then
  echo "FAIL: no hil at $hil: build the host preset first (cmake --build --preset host)"
  exit 1
fi
rm -rf "$work" && mkdir -p "$work"

start=$EPOCHREALTIME
status=0
"$hil" fly --throws 1 --no-trial --land --seed 1 --firmware qemu --pil-image "$image" --qemu "$qemu" \
  --icount-shift "$shift_n" --out "$work" --no-report --verbose > "$work/fly.txt" 2>&1 || status=$?
end=$EPOCHREALTIME
cat "$work/fly.txt"
awk -v a="$start" -v b="$end" 'BEGIN { printf "hil fly took %.1f s of wall time\n", b - a }'

problems=()
[ "$status" -eq 0 ] || problems+=("hil fly ended with status $status")
if [ -f "$work/throws.csv" ]; then
  outcome=$(awk -F, 'NR == 2 { print $2 }' "$work/throws.csv")
  rows=$(($(wc -l < "$work/throws.csv") - 1))
  [ "$rows" -eq 1 ] || problems+=("throws.csv has $rows attempts, not 1")
  [ "$outcome" = "caught" ] || problems+=("the throw was not caught (outcome '$outcome' in throws.csv)")
else
  problems+=("no throws.csv written")
fi
grep -q "no vehicle crashed: yes" "$work/fly.txt" || problems+=("a vehicle crashed")
grep -q "both vehicles landed after the last attempt: yes" "$work/fly.txt" || problems+=("the vehicles did not both land")
if grep -q "over budget" "$work/fly.txt"; then
  problems+=("a phase's worst tick went over the budget ($(grep -m1 -o 'budget [0-9]*' "$work/fly.txt"))")
fi
for v in 1 2; do
  grep -Eq "pil vehicle $v: [1-9][0-9]* ticks, guest instructions per tick mean [1-9]" "$work/fly.txt" ||
    problems+=("no guest instruction counts for vehicle $v")
done

if [ ${#problems[@]} -ne 0 ]; then
  printf 'FAIL: %s\n' "${problems[@]}"
  exit 1
fi
echo "PASS: the PIL image in QEMU took off, threw, caught and landed"
