#!/bin/sh
# A HIL scenario for scripts/hil-vm.sh (POSIX sh: busybox sh in the QEMU guest): the real
# fw_vehicle on SocketCAN bus vcan1, driven and checked by hil_can_probe (clean, flooded with
# malformed frames, clean again), the bus recorded by candump in its log format (replayable with
# canplayer). Then fw_vehicle must still be running, stop cleanly on SIGTERM and report the
# malformed frames it rejected. Beside the probe, cansend puts frames outside the protocol on the
# bus (extended identifiers, remote requests), which only a real SocketCAN bus carries and the
# port must skip. Needs in $PA_FILES: fw_vehicle, hil_can_probe, test_link.key, candump, cansend.
# Writes to $PA_OUT: candump.log, fw_vehicle.txt, probe.txt.
set -u
bus=vcan1
files=$PA_FILES
out=$PA_OUT

"$files/candump" -L "$bus" >"$out/candump.log" &
dump=$!
"$files/fw_vehicle" --can "$bus" --node 1 --key "$files/test_link.key" >"$out/fw_vehicle.txt" 2>&1 &
vehicle=$!
# Wait until the vehicle listens (it prints once its socket is bound).
n=0
until grep -q "waiting for HIL_IMU" "$out/fw_vehicle.txt" 2>/dev/null; do
  n=$((n + 1))
  if [ $n -gt 100 ] || ! kill -0 $vehicle 2>/dev/null; then
    echo "scenario: FAIL: fw_vehicle did not start:"
    cat "$out/fw_vehicle.txt"
    kill $dump $vehicle 2>/dev/null  # on a laptop's buses, leave nothing running
    exit 1
  fi
  sleep 0.1
done

others=200
(
  i=0
  while [ $i -lt $others ]; do
    "$files/cansend" "$bus" "$(printf '1%07X' $i)#DEADBEEF"   # 29-bit identifier
    "$files/cansend" "$bus" "$(printf '%03X' $((i * 11 % 2048)))#R"  # remote request
    i=$((i + 1))
  done
) &
sender=$!
"$files/hil_can_probe" --can "$bus" --node 1 "$@" >"$out/probe.txt" 2>&1
probe=$?
cat "$out/probe.txt"
if wait $sender; then
  echo "scenario: cansend put $others extended-identifier and $others remote-request frames on $bus"
else
  echo "scenario: FAIL: cansend failed"
  probe=1
fi

rc=0
[ $probe -eq 0 ] || rc=1
if kill -0 $vehicle 2>/dev/null; then
  kill -TERM $vehicle
  wait $vehicle
  vehicle_rc=$?
else
  wait $vehicle
  vehicle_rc=$?
  echo "scenario: FAIL: fw_vehicle died during the run (exit code $vehicle_rc)"
  rc=1
fi
cat "$out/fw_vehicle.txt"
if [ $vehicle_rc -ne 0 ]; then
  echo "scenario: FAIL: fw_vehicle exit code $vehicle_rc"
  rc=1
fi
rejected=$(sed -n 's/.*, \([0-9]*\) frames rejected.*/\1/p' "$out/fw_vehicle.txt")
if [ -z "$rejected" ] || [ "$rejected" -eq 0 ]; then
  echo "scenario: FAIL: fw_vehicle counted no rejected frames after the flood"
  rc=1
fi

kill -TERM $dump
wait $dump
echo "scenario: candump.log has $(wc -l <"$out/candump.log") frames; its first lines:"
head -n 8 "$out/candump.log"
if [ $rc -eq 0 ]; then echo "scenario: pass"; else echo "scenario: FAIL"; fi
exit $rc
