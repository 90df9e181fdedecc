#!/usr/bin/env bash
# Runs a HIL scenario on virtual CAN buses (vcan0..vcanN-1), in a QEMU guest when the kernel
# here has no CAN sockets (docs/hil.md). The guest is Debian's kernel (linux-image-amd64) booted
# under TCG with a busybox initramfs built here: it loads the CAN modules, creates the buses,
# runs SCENARIO with the FILEs given, sends the scenario's output files back over the serial
# console and powers off. --native runs the same scenario on this kernel's vcan buses instead.
#
# Usage: scripts/hil-vm.sh [--native] [--work DIR] [--buses N] [--timeout S] [--file PATH]...
#                          SCENARIO [ARG...]
# The scenario is a POSIX sh script (busybox sh in the guest). It finds the FILEs and can-utils'
# candump, cansend and cangen in $PA_FILES and writes what it wants kept to $PA_OUT; these land in
# DIR/out. Exit code: the scenario's; 1 when the guest fails; 2 on bad arguments; 77 when QEMU
# or the kernel is missing (ctest counts the test as skipped).
set -euo pipefail

native=0
work=build/hil-vm
buses=2
timeout_s=240
files=()
usage() {
  echo "usage: scripts/hil-vm.sh [--native] [--work DIR] [--buses N] [--timeout S] [--file PATH]... SCENARIO [ARG...]" >&2
  exit 2
}
while [ $# -gt 0 ]; do
  case "$1" in
    --native) native=1; shift ;;
    --work) [ $# -ge 2 ] || usage; work=$2; shift 2 ;;
    --buses) [ $# -ge 2 ] || usage; buses=$2; shift 2 ;;
    --timeout) [ $# -ge 2 ] || usage; timeout_s=$2; shift 2 ;;
    --file) [ $# -ge 2 ] || usage; files+=("$2"); shift 2 ;;
    -h | --help) usage ;;
    -*) echo "hil-vm: error: unknown option '$1'" >&2; usage ;;
    *) break ;;
  esac
done
[ $# -ge 1 ] || { echo "hil-vm: error: no SCENARIO given" >&2; usage; }
scenario=$1
shift
[[ "$buses" =~ ^[1-9]$ ]] || { echo "hil-vm: error: --buses needs 1..9, got '$buses'" >&2; exit 2; }
[[ "$timeout_s" =~ ^[0-9]+$ ]] || { echo "hil-vm: error: --timeout needs seconds, got '$timeout_s'" >&2; exit 2; }
for f in "$scenario" "${files[@]}"; do
  [ -f "$f" ] || { echo "hil-vm: error: '$f' does not exist (build it first)" >&2; exit 2; }
done

mkdir -p "$work"
work=$(cd "$work" && pwd)
rm -rf "$work/out"
mkdir -p "$work/out"

if [ "$native" -eq 1 ]; then
  # This kernel's CAN: the buses must exist (creating them needs root), the FILEs are linked
  # into one folder so that the scenario finds them as it does in the guest.
  for ((n = 0; n < buses; ++n)); do
    if ! ip link show "vcan$n" >/dev/null 2>&1; then
      if [ "$(id -u)" -ne 0 ]; then
        echo "hil-vm: error: no bus vcan$n; create it as root:" >&2
        echo "  sudo modprobe vcan && sudo ip link add dev vcan$n type vcan && sudo ip link set up vcan$n" >&2
        exit 1
      fi
      modprobe vcan 2>/dev/null || true
      ip link add dev "vcan$n" type vcan ||
        { echo "hil-vm: error: cannot create vcan$n: this kernel has no vcan (leave out --native to run in QEMU)" >&2; exit 1; }
    fi
    if [ "$(id -u)" -eq 0 ]; then
      ip link set up "vcan$n"
    elif ! ip -o link show "vcan$n" | grep -q '[<,]UP[,>]'; then
      echo "hil-vm: error: bus vcan$n is down; raise it as root: sudo ip link set up vcan$n" >&2
      exit 1
    fi
  done
  rm -rf "$work/files"
  mkdir -p "$work/files"
  for f in "${files[@]}"; do ln -s "$(realpath "$f")" "$work/files/"; done
  for tool in candump cansend cangen; do
    path=$(command -v "$tool") || { echo "hil-vm: error: $tool not found (Debian: apt-get install can-utils)" >&2; exit 1; }
    ln -s "$path" "$work/files/$tool"
  done
  set +e
  PA_FILES=$work/files PA_OUT=$work/out sh "$scenario" "$@"
  rc=$?
  set -e
  echo "hil-vm: scenario exit code $rc; output in $work/out"
  exit "$rc"
fi

skip() {
  echo "hil-vm: skipped: $1 (scripts/install-deps.sh installs it)"
  exit 77
}
qemu=$(command -v qemu-system-x86_64) || skip "qemu-system-x86_64 not found (Debian: qemu-system-x86)"
kernel=
for k in /boot/vmlinuz-*; do
  [ -r "$k" ] && [ -f "/lib/modules/${k#/boot/vmlinuz-}/modules.dep" ] && kernel=$k
done
[ -n "$kernel" ] || skip "no readable /boot/vmlinuz-* with its modules in /lib/modules (Debian: linux-image-amd64)"
version=${kernel#/boot/vmlinuz-}
modules=/lib/modules/$version
busybox=$(command -v busybox) || skip "busybox not found (Debian: busybox-static)"
if ldd "$busybox" >/dev/null 2>&1; then skip "$busybox is not statically linked (Debian: busybox-static)"; fi
candump=$(command -v candump) || skip "candump not found (Debian: can-utils)"
cansend=$(command -v cansend) || skip "cansend not found (Debian: can-utils)"
cangen=$(command -v cangen) || skip "cangen not found (Debian: can-utils)"

# --- the initramfs --------------------------------------------------------------------------
root=$work/root
rm -rf "$root"
mkdir -p "$root"/{bin,dev,proc,sys,tmp,out,guest,modules}
cp "$busybox" "$root/bin/busybox"
for applet in $("$busybox" --list); do
  [ "$applet" = busybox ] || ln -sf busybox "$root/bin/$applet"
done

# The CAN modules and what they need, in load order (modules.dep lists a module's dependencies,
# the deepest last). Compressed modules are unpacked here: busybox's insmod reads plain ones.
module_order=()
add_module() {
  local name=$1 line path dep i m
  if ! line=$(grep -E "(^|/)$name\.ko(\.xz|\.zst|\.gz)?:" "$modules/modules.dep"); then
    grep -qE "(^|/)$name\.ko\$" "$modules/modules.builtin" 2>/dev/null && return 0  # built into the kernel
    echo "hil-vm: error: module $name not in $modules/modules.dep" >&2
    exit 1
  fi
  path=${line%%:*}
  local deps
  read -r -a deps <<<"${line#*:}"
  for ((i = ${#deps[@]} - 1; i >= 0; --i)); do
    dep=$(basename "${deps[$i]}")
    add_module "${dep%%.ko*}"
  done
  for m in "${module_order[@]}"; do [ "$m" != "$name" ] || return 0; done
  module_order+=("$name")
  case "$path" in
    *.xz) xz -dc "$modules/$path" >"$root/modules/$name.ko" ;;
    *.zst) zstd -qdc "$modules/$path" >"$root/modules/$name.ko" ;;
    *.gz) gzip -dc "$modules/$path" >"$root/modules/$name.ko" ;;
    *) cp "$modules/$path" "$root/modules/$name.ko" ;;
  esac
}
for m in can can-raw can-dev vcan; do add_module "$m"; done

# The programs and every shared library they load, at the paths the loader looks for them.
copy_libraries() {
  local lib
  for lib in $(ldd "$1" | grep -oE '/[^ ]+' || true); do
    if [ ! -e "$root$lib" ]; then
      mkdir -p "$root$(dirname "$lib")"
      cp -L "$lib" "$root$lib"
    fi
  done
}
cp "$scenario" "$root/guest/scenario.sh"
for f in "${files[@]}" "$candump" "$cansend" "$cangen"; do
  cp -L "$f" "$root/guest/"
  # Debug information is most of a RelWithDebInfo program (hil and groundstation: about 200 MB
  # each, 2 to 3 MB without), and the guest unpacks its initramfs into its 512 MB.
  if ldd "$f" >/dev/null 2>&1; then
    strip --strip-debug "$root/guest/$(basename "$f")"
    copy_libraries "$f"
  fi
done

# The scenario's arguments, quoted for sh.
args=
for a in "$@"; do args="$args '${a//\'/\'\\\'\'}'"; done
cat >"$root/init" <<EOF
#!/bin/sh
# PID 1 of the HIL guest (written by scripts/hil-vm.sh).
export PATH=/bin
mount -t proc proc /proc
mount -t sysfs sys /sys
mount -t devtmpfs dev /dev
echo "hil-vm: guest up after \$(cut -d' ' -f1 /proc/uptime) s"
for m in ${module_order[*]}; do insmod /modules/\$m.ko || echo "hil-vm: insmod \$m failed"; done
ip link set up lo
n=0
while [ \$n -lt $buses ]; do
  ip link add dev vcan\$n type vcan && ip link set up vcan\$n
  n=\$((n + 1))
done
start=\$(cut -d' ' -f1 /proc/uptime)
cd /out
PA_FILES=/guest PA_OUT=/out sh /guest/scenario.sh$args
rc=\$?
echo "hil-vm: scenario ran from \$start s to \$(cut -d' ' -f1 /proc/uptime) s of guest uptime"
# Every output file as gzip and base64 between markers; the host unpacks them.
for f in *; do
  [ -f "\$f" ] || continue
  echo "PA-FILE-BEGIN \$f"
  gzip -c "\$f" | base64
  echo "PA-FILE-END"
done
echo "PA-HIL-RESULT exit=\$rc"
sync
poweroff -f
EOF
chmod +x "$root/init"
(cd "$root" && find . | sort | "$busybox" cpio -o -H newc 2>/dev/null | gzip -1 >"$work/initramfs.cpio.gz")

# --- the guest --------------------------------------------------------------------------------
echo "hil-vm: booting $kernel under TCG ($(du -h "$work/initramfs.cpio.gz" | cut -f1) initramfs, modules: ${module_order[*]})"
console=$work/console.log
started_ms=$(($(date +%s%N) / 1000000))
set +e
timeout --foreground "$timeout_s" "$qemu" -accel tcg -cpu max -smp 2 -m 512 -nographic -no-reboot -nic none \
  -kernel "$kernel" -initrd "$work/initramfs.cpio.gz" \
  -append "console=ttyS0 quiet panic=-1 rdinit=/init" </dev/null >"$console" 2>&1
qemu_rc=$?
set -e
elapsed_ms=$(($(date +%s%N) / 1000000 - started_ms))
elapsed=$((elapsed_ms / 1000)).$(printf '%03d' $((elapsed_ms % 1000)))
# Without carriage returns and the firmware's terminal escapes.
sed -e 's/\r$//' -e $'s/\x1b\\[[0-9;?]*[A-Za-z]//g' -e $'s/\x1bc//g' <"$console" >"$console.txt"
mv "$console.txt" "$console"

# The console without the file blocks, then the files.
awk '/^PA-FILE-BEGIN /{skip=1; next} /^PA-FILE-END/{skip=0; next} !skip' "$console"
awk -v dir="$work/out" '
  /^PA-FILE-BEGIN /{name=$2; file=dir "/" name ".gz.b64"; printf "" > file; next}
  /^PA-FILE-END/{close(file); file=""; next}
  file != ""{print >> file}' "$console"
brought=()
for b in "$work/out"/*.gz.b64; do
  [ -e "$b" ] || continue
  base64 -d "$b" | gunzip >"${b%.gz.b64}" && rm "$b"
  brought+=("$(basename "${b%.gz.b64}")")
done
echo "hil-vm: brought back: ${brought[*]:-nothing}"

result=$(grep -oE '^PA-HIL-RESULT exit=[0-9]+' "$console" | tail -n1 | cut -d= -f2 || true)
if [ -z "$result" ]; then
  if [ "$qemu_rc" -eq 124 ]; then
    echo "hil-vm: error: the guest did not finish within ${timeout_s} s (console: $console)" >&2
  else
    echo "hil-vm: error: the guest stopped without a result (qemu exit code $qemu_rc; console: $console)" >&2
  fi
  exit 1
fi
echo "hil-vm: guest finished in ${elapsed} s (boot, scenario and power-off); scenario exit code $result;" \
  "output in $work/out"
exit "$result"
