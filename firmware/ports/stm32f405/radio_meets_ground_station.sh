#!/usr/bin/env bash
# The flight image meets the ground station over its radio's serial line (docs/arena.md, "On the
# bench, in emulation"): fw_stm32f405_flight in qemu-system-arm -M netduinoplus2 with its
# USART1 on a pseudo-terminal, and `groundstation run --radio 1=<that terminal>` on the other end
# for some seconds. Checks what the emulator lets through: the link budget printed, vehicle 1
# heard (its heartbeats, link quality), frames both ways in the shared framing with no CRC or
# header error, the image counting the ground's frames. (QEMU's STM32F405 has no RNG, so the
# image drops any key it has and the link stays unsigned: docs/arena.md says what that leaves.)
# Usage: radio_meets_ground_station.sh QEMU IMAGE GROUNDSTATION KEYFILE WORKDIR
set -euo pipefail
if [ $# -ne 5 ]; then
  echo "usage: radio_meets_ground_station.sh QEMU IMAGE GROUNDSTATION KEYFILE WORKDIR" >&2
  exit 2
fi
qemu=$1 image=$2 ground_station=$3 key=$4 work=$5
if ! command -v "$qemu" > /dev/null; then
  echo "FAIL: no QEMU ($qemu): make deps installs qemu-system-arm"
  exit 1
fi
if [ ! -x "$ground_station" ]; then
  echo "FAIL: no ground station at $ground_station: build the host preset first (make host)"
  exit 1
fi
rm -rf "$work" && mkdir -p "$work" && cd "$work"
printf '%s\n' 0f1e2d3c4b5a69788796a5b4c3d2e1f0 > vehicle2.key  # vehicle 2 has no radio here

"$qemu" -M netduinoplus2 -nographic -monitor none -serial pty -serial null -serial file:console.txt \
  -kernel "$image" > qemu.out 2>&1 &
qemu_pid=$!
trap 'kill "$qemu_pid" 2>/dev/null || true' EXIT
terminal=""
for _ in $(seq 100); do
  terminal=$(grep -o '/dev/pts/[0-9]*' qemu.out | head -n 1 || true)
  [ -n "$terminal" ] && break
  sleep 0.1
done
if [ -z "$terminal" ]; then
  echo "FAIL: QEMU named no pseudo-terminal for USART1:"
  cat qemu.out
  exit 1
fi
echo "USART1 on $terminal"

status=0
timeout -s INT 10 "$ground_station" run --radio 1="$terminal" --domain 201 --key1 "$key" \
  --key2 vehicle2.key > ground_station.log 2>&1 || status=$?
cat ground_station.log
echo "console, last line:"
tail -n 1 console.txt || true
# timeout reports 124 when it sent the signal; the ground station itself ends 0 on SIGINT.
problems=()
[ "$status" -eq 0 ] || [ "$status" -eq 124 ] || problems+=("groundstation run ended with status $status")
grep -q "groundstation run: stopped" ground_station.log || problems+=("the ground station did not stop cleanly")
grep -q "radio at 115200 baud (11520 bytes/s): to the vehicle 520 frames/s" ground_station.log ||
  problems+=("no link budget printed")
grep -Eq "^vehicle 1: link quality (0\.[5-9][0-9]|1\.00)" ground_station.log ||
  problems+=("vehicle 1 not heard at half its heartbeats or more")
radios=$(grep "^radios: " ground_station.log || true)
frames_in=$(sed -n 's/^radios: frames in \([0-9]*\),.*/\1/p' <<< "$radios")
frames_out=$(sed -n 's/^radios: frames in [0-9]*, out \([0-9]*\);.*/\1/p' <<< "$radios")
[ "${frames_in:-0}" -ge 1000 ] || problems+=("${frames_in:-no} frames from the image (1000 or more expected)")
[ "${frames_out:-0}" -ge 100 ] || problems+=("${frames_out:-no} frames to the image (100 or more expected)")
grep -q "dropped: 0 bad CRC, 0 bad headers, 0 from another node" <<< "$radios" ||
  problems+=("frames were lost on the line: $radios")
grep -Eq "link_in=[1-9]" console.txt || problems+=("the image counted no frame from the ground")
if [ ${#problems[@]} -gt 0 ]; then
  printf 'FAIL: %s\n' "${problems[@]}"
  exit 1
fi
echo "PASS: the flight image and the ground station spoke over the serial radio's framing"
