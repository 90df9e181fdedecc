#!/bin/sh
# A HIL scenario for scripts/hil-vm.sh that checks the plumbing, not the firmware: it names the
# kernel and the network interfaces (the vcan buses must be up), writes a file for the host to
# bring back and exits with the code given ($1), which the host must report as the scenario's.
set -u
echo "guest_check: kernel $(uname -r); interfaces: $(ls /sys/class/net | tr '\n' ' ')"
for bus in /sys/class/net/vcan*; do
  flags=$(cat "$bus/flags")
  if [ $((flags & 1)) -eq 1 ]; then state=up; else state=down; fi  # IFF_UP
  echo "guest_check: $(basename "$bus") is $state"
done
echo "written in the guest" >"$PA_OUT/guest_check.txt"
exit "${1:-0}"
