#!/usr/bin/env bash
# Where one tick's instructions go (docs/hil.md, "Processor in the loop"): boots an mps2-an386
# image in QEMU (the self-test flight, fw_mps2_an386.elf), single-steps its call of
# fw::Vehicle::tick numbered TICK (from 0, as the self-test's tick_instructions_max_at_tick
# counts) under gdb, and prints its instructions by the step of the tick they belong to: the
# function just below Vehicle::tick in the chain of inlined calls at each instruction, or the
# out-of-line function they are in. Each instruction is counted once, so the parts add up to the
# total; QEMU's -icount counter and this count agree to the probe's few instructions.
#
#   scripts/tick-profile.sh IMAGE TICK [ICOUNT_SHIFT]
#
# ICOUNT_SHIFT is the -icount shift the image was compiled for (default 10, as
# firmware/ports/mps2_an386/CMakeLists.txt builds it). Needs qemu-system-arm, gdb-multiarch and
# arm-none-eabi-addr2line (scripts/install-deps.sh installs them); takes some seconds a thousand
# ticks before TICK.
set -euo pipefail
if [ $# -lt 2 ] || [ $# -gt 3 ]; then
  echo "usage: scripts/tick-profile.sh IMAGE TICK [ICOUNT_SHIFT]" >&2
  exit 2
fi
image=$1 tick=$2 shift_n=${3:-10}
[ -f "$image" ] || { echo "tick-profile: $image is missing (make cortex-m4 builds it)" >&2; exit 2; }
[[ $tick =~ ^[0-9]+$ ]] || { echo "tick-profile: TICK '$tick' is not a tick number (0, 1, ...)" >&2; exit 2; }
[[ $shift_n =~ ^[0-9]+$ ]] || { echo "tick-profile: ICOUNT_SHIFT '$shift_n' is not a whole number" >&2; exit 2; }
for tool in qemu-system-arm gdb-multiarch arm-none-eabi-addr2line; do
  command -v "$tool" >/dev/null || { echo "tick-profile: $tool is missing (scripts/install-deps.sh)" >&2; exit 2; }
done

work=$(mktemp -d)
qemu_pid=
cleanup() {
  [ -n "$qemu_pid" ] && kill "$qemu_pid" 2>/dev/null || true
  rm -rf "$work"
}
trap cleanup EXIT

# A free port for QEMU's gdb server, -gdb (the kernel picks it; tests run side by side).
port=$(python3 -c 'import socket; s = socket.socket(); s.bind(("127.0.0.1", 0)); print(s.getsockname()[1])')
qemu-system-arm -M mps2-an386 -cpu cortex-m4 -nographic -monitor none -serial none -kernel "$image" \
  -semihosting-config enable=on,target=native -icount shift="$shift_n" \
  -gdb tcp:127.0.0.1:"$port" -S > "$work/qemu.out" 2>&1 &
qemu_pid=$!

here=$(cd "$(dirname "$0")" && pwd)
# (gdb -batch exits with 0 even when the script raised: the script's output file says whether it
# stepped the whole tick.)
PA_TICK=$tick PA_PORT=$port PA_PCS="$work/pcs" \
  gdb-multiarch -q -batch -x "$here/tick_profile.py" "$image" > "$work/gdb.out" 2>&1 || true
if [ ! -s "$work/pcs" ]; then
  echo "tick-profile: gdb could not step tick $tick of $image; its last words:" >&2
  tail -n 4 "$work/gdb.out" >&2
  exit 1
fi

python3 - "$image" "$tick" "$work/pcs" <<'EOF'
import collections, subprocess, sys

image, tick, pcs_file = sys.argv[1], sys.argv[2], sys.argv[3]
pcs = [line.strip() for line in open(pcs_file) if line.strip()]  # not empty: checked above
# addr2line -a -f -i: for each address its own line, then a function and a place per inlined
# level, innermost first.
unique = sorted(set(pcs), key=lambda p: int(p, 16))
lines = subprocess.run(["arm-none-eabi-addr2line", "-a", "-f", "-C", "-i", "-e", image] +
                       ["0x" + p for p in unique], capture_output=True, text=True, check=True).stdout.splitlines()
chains, current = {}, None
i = 0
while i < len(lines):
    if lines[i].startswith("0x"):
        current = "%x" % int(lines[i], 16)
        chains[current] = []
        i += 1
        continue
    chains[current].append(lines[i].split("(")[0])  # the function, without its parameters
    i += 2                                          # its place
def part(pc):
    outermost_first = list(reversed(chains.get(pc) or ["??"]))
    if outermost_first[0] == "fw::Vehicle::tick" and len(outermost_first) > 1:
        return outermost_first[1]
    return outermost_first[0]
counts = collections.Counter(part(pc) for pc in pcs)
print("tick-profile: tick %s of %s: %d instructions" % (tick, image.rsplit("/", 1)[-1], len(pcs)))
for name, n in sorted(counts.items(), key=lambda kv: (-kv[1], kv[0])):
    print("%8d  %s" % (n, name))
EOF
