#!/bin/sh
# A HIL scenario for scripts/hil-vm.sh --buses 3 (POSIX sh: busybox sh in the QEMU guest): a whole
# attempt flown by five processes on SocketCAN, all on the plant's time. `hil run --ground-clock`
# steps the truth plant between two fw_vehicle processes (vehicle buses vcan1 and vcan2) and
# `groundstation run --hil-clock` on the ground bus vcan0, which flies them from the motion capture
# hil run publishes on DDS and steps once per HIL_CLOCK. The operator (`groundstation op`) takes
# off, has vehicle 1 throw the pole to vehicle 2 and lands both. Then:
#  - the ground station reported the catch, both vehicles ended on the floor with their motors off
#    (hil run's summary of the truth) and no sample or clock went unanswered;
#  - the catch matches the in-process simulation's (`hil fly --throws 1 --no-trial`, same seed):
#    the same outcome, and the catcher's estimated position at the impact within the tolerance
#    below of the in-process one.
# Needs in $PA_FILES: hil, fw_vehicle, groundstation, test_link.key, arena_scenario.sh. Writes to $PA_OUT: the
# processes' outputs, the watch views, every bus's candump log (logs/vcan*.log), truth.csv and the
# DDS events as `groundstation watch` printed them.
set -u
files=$PA_FILES
out=$PA_OUT
domain=9
seed=1
key=$files/test_link.key
# The catch point's tolerance against the in-process run, per axis. Both fly the same plan from the
# same seed, but the operator's commands reach the ground station at plant times set by the guest's
# wall clock (when `op` ran), so the take-off and the throw start at other plant times than in
# process and the noise each meets differs. Over seeds 1-5 in process (`hil fly --throws 1
# --no-trial --seed S --verbose`) the catcher's position at the impact spreads by 4.5 cm in x,
# 4.8 cm in y and 12.6 cm in z (3.201-3.327 m): this first throw's catch is retimed from the
# nominal height 0.8 m down to its own (42), which each run predicts from its own noisy poses
# (5.4 cm in z when the tolerance was first set at 0.1 m, which the five processes then met at
# 0.147 m once in CI). Twice the spread, rounded up.
tolerance_xy_m=0.1
tolerance_z_m=0.25
pids=
. "$files/arena_scenario.sh"

say "start at $(elapsed) s of guest uptime"
start_plant $seed
start_firmware 1
start_firmware 2
start_ground_station groundstation
record_dds
wait_for "$out/hil_run.txt" "hil run: ground bus" 30 || fail "hil run did not start"
wait_for "$out/groundstation.txt" "groundstation run: on vcan0" 60 || fail "groundstation run did not start"

watch_until links 120 "vehicle 1  link up *task parked .* at " "vehicle 2  link up *task parked .* at " ||
  fail "the ground station did not hear both vehicles: $(cat "$out/watch_links.txt")"
say "both links up at $(elapsed) s"
op take-off || fail "take-off was not accepted"
watch_until hover 300 "vehicle 1  link up *task hover" "vehicle 2  link up *task hover" ||
  fail "the vehicles did not reach hover: $(cat "$out/watch_hover.txt")"
say "both hovering at $(elapsed) s"
op throw --vehicle 1 || fail "throw was not accepted"
watch_until attempt 600 "catch success\|catch miss" ||
  fail "the attempt did not end: $(cat "$out/watch_attempt.txt")"
cat "$out/watch_attempt.txt"
say "the attempt ended at $(elapsed) s"
# Balanced again on vehicle 2: the ground station lands both (the pole comes down with vehicle 2).
op land || fail "land was not accepted"
watch_until parked 300 "vehicle 1  link up *task parked" "vehicle 2  link up *task parked" ||
  fail "the vehicles did not land: $(cat "$out/watch_parked.txt")"
say "both landed and parked at $(elapsed) s"
sleep 1
stop_all
cat "$out/hil_run.txt" "$out/groundstation.txt" "$out/fw_vehicle1.txt" "$out/fw_vehicle2.txt"

rc=0
check() { if ! eval "$1"; then say "FAIL: $2"; rc=1; fi; }
caught=$(grep "catch success" "$out/watch_attempt.txt")
check '[ -n "$caught" ]' "the ground station did not report the catch: $(grep 'catch miss' "$out/watch_attempt.txt")"
for n in 1 2; do
  line=$(grep "hil run: vehicle $n truth:" "$out/hil_run.txt")
  check 'echo "$line" | grep -q "on the floor, motors off"' "vehicle $n did not end on the floor with its motors off: $line"
  samples=$(grep "hil run: vehicle $n on" "$out/hil_run.txt")
  check 'echo "$samples" | grep -q " 0 missed"' "vehicle $n missed samples: $samples"
done
check 'grep -q "HIL clock: 0 steps" "$out/groundstation.txt"' "the ground station waited in vain for motion capture"
check 'grep "hil run: ground clock:" "$out/hil_run.txt" | grep -q "released 0 times"' "the plant stepped on without the ground station"
check '! grep "hil run: vehicle . on" "$out/hil_run.txt" | grep -vq "released 0 times"' "the plant stepped on without a firmware"

# The same attempt in process, from the same seed.
"$files/hil" fly --throws 1 --no-trial --seed $seed --verbose >"$out/in_process.txt" 2>&1
cat "$out/in_process.txt" | grep -v "^  t="
here=$(echo "$caught" | sed -n 's/.*catcher at impact (\([-0-9.]*\), \([-0-9.]*\), \([-0-9.]*\)) m.*/\1 \2 \3/p')
there=$(sed -n 's/.*catcher at impact (\([-0-9.]*\), \([-0-9.]*\), \([-0-9.]*\)).*/\1 \2 \3/p' "$out/in_process.txt")
check 'grep -q "^ *1  caught" "$out/in_process.txt"' "in process the throw was not caught"
say "catcher at impact: five processes ($here) m, in process ($there) m"
check '[ -n "$here" ] && [ -n "$there" ]' "no catch point to compare"
if [ -n "$here" ] && [ -n "$there" ]; then
  check "echo $here $there | awk -v xy=$tolerance_xy_m -v z=$tolerance_z_m '{ for (i = 1; i <= 3; ++i) { d = \$i - \$(i + 3); if (d < 0) d = -d; if (d > (i < 3 ? xy : z)) exit 1 } }'" \
    "the catch points differ by more than $tolerance_xy_m m in x or y or $tolerance_z_m m in z"
fi
cp "$out/logs/truth.csv" "$out/"
for f in "$out"/logs/*; do say "$(basename "$f"): $(wc -l <"$f") lines"; done
if [ $rc -eq 0 ]; then say "pass"; else say "FAIL"; fi
exit $rc
