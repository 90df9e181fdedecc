#!/usr/bin/env bash
# Installs the Debian 12 packages the project needs, saying which were missing.
# Idempotent: packages already present are left alone and nothing is fetched.
set -euo pipefail

packages=(
  build-essential cmake ninja-build pkg-config
  # the compiler cache: a second clone's build reuses the first one's objects (CMakeLists.txt)
  ccache
  catch2 libbenchmark-dev libeigen3-dev
  cyclonedds-dev cyclonedds-tools coinor-libipopt-dev libsqlite3-dev libsodium-dev
  libcli11-dev libyaml-cpp-dev clang-format
  # Fast DDS, ROS 2's default middleware, the second DDS implementation the tests talk to
  # (tests/fastdds): the library and its code generator, which runs on Java
  libfastrtps-dev fastddsgen default-jre-headless
  # the fuzz preset: clang and libFuzzer's runtime (only recommended by clang, so named here)
  clang libclang-rt-14-dev
  gcc-arm-none-eabi binutils-arm-none-eabi libnewlib-arm-none-eabi libstdc++-arm-none-eabi-newlib
  qemu-system-arm
  # scripts/tick-profile.sh: gdb for the Arm image, single-stepping one tick in QEMU
  gdb-multiarch
  # HIL on virtual CAN in a QEMU guest when this kernel has no CAN sockets (scripts/hil-vm.sh):
  # Debian's kernel and its CAN modules, a static busybox for the initramfs, candump
  qemu-system-x86 linux-image-amd64 busybox-static can-utils
  python3 python3-matplotlib
  # ROS 2's .msg parser: the project's messages (groundstation/dds/pa_msgs) become IDL at build time
  python3-rosidl
  # the report's check in a browser (tests/report/check_report.py --chromium)
  chromium
  # campaigns on a Slurm cluster: the test starts a one-node Slurm with munge (scripts/slurm-campaign.sh)
  slurm-wlm munge
)

# Every preset of make test writes about 5 GB under build/ (measured 4.6 GB; docs/architecture.md):
# say so before a build runs out of space half-way.
free_kb=$(df -Pk "$(dirname "$0")/.." | awk 'NR == 2 {print $4}')
if [ "${free_kb:-0}" -lt $((6 * 1024 * 1024)) ]; then
  echo "deps: warning: $((free_kb / 1024)) MB free for build/; every preset (make test) needs about 5 GB" >&2
fi

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done

if [ ${#missing[@]} -eq 0 ]; then
  echo "deps: all ${#packages[@]} packages present"
  exit 0
fi

echo "deps: installing missing packages: ${missing[*]}"
if [ "$(id -u)" -ne 0 ]; then
  echo "deps: error: installing needs root (run as root, or: sudo apt-get install ${missing[*]})" >&2
  exit 1
fi
export DEBIAN_FRONTEND=noninteractive
apt-get update -qq
apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "deps: installed ${missing[*]}"
