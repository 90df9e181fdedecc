#!/bin/sh
# A HIL scenario for scripts/hil-vm.sh --buses 3 (POSIX sh: busybox sh in the QEMU guest): the
# faults an arena meets, survived by the five processes on the plant's clock (hil run
# --ground-clock, two fw_vehicle, groundstation run --hil-clock, the operator's groundstation op):
#  1. the ground station killed (SIGKILL) with both vehicles hovering: each firmware levels and
#     hovers on board (its hold) within 25 ms of the last setpoint it read, which becomes its
#     failsafe hover, then lands with its motors off;
#  2. the ground station started again on the same adaptation store: it re-attaches from the
#     vehicles' heartbeats and takes them off again on command;
#  3. a flood of malformed frames (length 7: no frame type has it) on all three buses while they
#     hover: counted and dropped, the vehicles keep hovering, no process dies;
#  4. the catcher's firmware killed (SIGKILL) once the thrower balances the pole for a throw: the
#     ground station reports vehicle 2 lost and calls the catch off; vehicle 1 lands with the pole.
# Needs in $PA_FILES: hil, fw_vehicle, groundstation, test_link.key, arena_scenario.sh, cangen.
# Writes to $PA_OUT: the processes' outputs, the watch views, dds_watch.txt, every bus's candump log
# and truth.csv.
set -u
files=$PA_FILES
out=$PA_OUT
domain=11
key=$files/test_link.key
store=$out/adaptation.sqlite
pids=
. "$files/arena_scenario.sh"

hovering() { watch_until "$1" 300 "vehicle 1  link up *task hover" "vehicle 2  link up *task hover"; }

say "start at $(elapsed) s of guest uptime"
start_plant 3
start_firmware 1
start_firmware 2
start_ground_station groundstation --store "$store"
record_dds
wait_for "$out/groundstation.txt" "groundstation run: on vcan0" 60 || fail "groundstation run did not start"
watch_until links 120 "vehicle 1  link up *task parked .* at " "vehicle 2  link up *task parked .* at " ||
  fail "the ground station did not hear both vehicles: $(cat "$out/watch_links.txt")"
op take-off || fail "take-off was not accepted"
hovering hover || fail "the vehicles did not reach hover: $(cat "$out/watch_hover.txt")"
say "both hovering at $(elapsed) s"

# 1. The ground station killed.
kill -KILL "$gs_pid"
wait "$gs_pid" 2>/dev/null
say "1. the ground station killed at $(elapsed) s"
for n in 1 2; do
  wait_for "$out/fw_vehicle$n.txt" "-> landed" 300 || fail "vehicle $n did not land on its own"
done
rc=0
check() { if ! eval "$1"; then say "FAIL: $2"; rc=1; fi; }
for n in 1 2; do
  hold=$(grep "flying -> hold" "$out/fw_vehicle$n.txt" | tail -n 1)
  age=$(echo "$hold" | sed -n 's/.*the last setpoint \([0-9.]*\) ms old.*/\1/p')
  say "vehicle $n: $hold"
  check "[ -n \"$age\" ] && awk -v a=$age 'BEGIN { exit !(a <= 25) }'" \
    "vehicle $n was not levelled (its hold) within 25 ms of its last setpoint"
  check "grep -q 'hold -> failsafe_hover' '$out/fw_vehicle$n.txt'" "vehicle $n's hold did not become its failsafe hover"
  grep "fw_vehicle: .* -> " "$out/fw_vehicle$n.txt" | tail -n 4
done
say "both landed on their own at $(elapsed) s"

# 2. The ground station again, on the same store.
start_ground_station groundstation2 --store "$store"
wait_for "$out/groundstation2.txt" "groundstation run: on vcan0" 60 || fail "the second groundstation run did not start"
watch_until reattached 120 "vehicle 1  link up *task parked .* at " "vehicle 2  link up *task parked .* at " ||
  fail "the restarted ground station did not re-attach: $(cat "$out/watch_reattached.txt")"
say "2. re-attached at $(elapsed) s"
op take-off || fail "take-off after the restart was not accepted"
hovering hover_again || fail "the vehicles did not take off again: $(cat "$out/watch_hover_again.txt")"
say "both hovering again at $(elapsed) s"

# 3. Malformed frames on every bus, 2000 each, 1 ms apart, all at once.
for n in 0 1 2; do
  "$files/cangen" "vcan$n" -g 1 -I r -L 7 -D r -n 2000 >/dev/null 2>&1 &
  floods="${floods:-} $!"
done
for p in $floods; do wait "$p"; done
say "3. the floods ended at $(elapsed) s"
hovering after_flood || fail "the vehicles did not keep hovering through the flood: $(cat "$out/watch_after_flood.txt")"
for p in $pids; do kill -0 "$p" 2>/dev/null; done

# 4. The catcher's firmware killed once the thrower balances the pole.
op throw --vehicle 1 || fail "throw was not accepted"
watch_until balance 300 "vehicle 1  link up *task balance" || fail "vehicle 1 did not balance the pole"
kill -KILL "$fw_pid2"
wait "$fw_pid2" 2>/dev/null
say "4. vehicle 2's firmware killed at $(elapsed) s"
watch_until called_off 120 "vehicle lost *vehicle 2" "catch aborted: the catcher is vehicle_lost" ||
  fail "the ground station did not call the catch off: $(cat "$out/watch_called_off.txt")"
cat "$out/watch_called_off.txt"
op land || fail "land was not accepted"
watch_until parked 300 "vehicle 1  link up *task parked" || fail "vehicle 1 did not land: $(cat "$out/watch_parked.txt")"
say "vehicle 1 landed at $(elapsed) s"
sleep 1
stop_all
cat "$out/hil_run.txt" "$out/groundstation2.txt" "$out/fw_vehicle1.txt" "$out/fw_vehicle2.txt"

line=$(grep "hil run: vehicle 1 truth:" "$out/hil_run.txt")
check 'echo "$line" | grep -q "on the floor, motors off"' "vehicle 1 did not end on the floor with its motors off: $line"
line=$(grep "hil run: vehicle 2 truth:" "$out/hil_run.txt")
check 'echo "$line" | grep -q "on the floor, motors off"' "vehicle 2 (its firmware killed) is not on the floor with its motors off: $line"
# The plant lets the killed ground station go where it was killed: its first release is at most
# 0.1 s of plant time before vehicle 1's hold (25 ms after the last setpoint). Under a loaded
# emulator a living ground station can also be silent past the plant's 1 s of the clock (seen once
# at 0.07 of real time, just after the restart): the plant lets it go and awaits it again when it
# answers, so later releases are reported, not failed.
released_at_kill() {
  first=$(sed -n 's/^hil run: \([0-9.]*\) s: the ground station has not answered.*/\1/p' "$out/hil_run.txt" | head -n 1)
  hold1=$(sed -n 's/^fw_vehicle: \([0-9.]*\) s: mode flying -> hold.*/\1/p' "$out/fw_vehicle1.txt" | head -n 1)
  say "the ground station first let go at ${first:-never} s, vehicle 1's hold at ${hold1:-never} s"
  [ -n "$first" ] && [ -n "$hold1" ] && awk -v r="$first" -v h="$hold1" 'BEGIN { exit !(r <= h && h - r < 0.1) }'
}
check released_at_kill "the plant did not let the killed ground station go where it was killed"
grep "hil run: ground clock:" "$out/hil_run.txt"
check 'grep -q "hil run: vehicle 2 on .* released 1 times" "$out/hil_run.txt"' "the plant did not let the killed firmware go once"
check 'grep -q "^fw_vehicle: stopped" "$out/fw_vehicle1.txt"' "vehicle 1's firmware did not stop cleanly"
check 'grep -q "^groundstation run: stopped" "$out/groundstation2.txt"' "the second ground station did not stop cleanly"
grep "frames rejected" "$out/fw_vehicle1.txt"
grep "CAN frames received" "$out/groundstation2.txt"
cp "$out/logs/truth.csv" "$out/"
for f in "$out"/logs/*; do say "$(basename "$f"): $(wc -l <"$f") lines"; done
if [ $rc -eq 0 ]; then say "pass"; else say "FAIL"; fi
exit $rc
