#!/usr/bin/env bash
# Programs an STM32F405 image onto a board (`make flash [BOARD=...]`):
#   (no BOARD)       the HIL image, with openocd through an ST-LINK on SWD
#   BOARD=omnibusf4  the flight image, with dfu-util over USB into the chip's ROM bootloader
#   BOARD=omnibusf4-pwm  the same with standard PWM motor output instead of DShot600
# Neither tool is in scripts/install-deps.sh: flashing needs a board, which nothing here has,
# so a missing tool is reported with the command that installs it.
# KEY=FILE (required): the vehicle's link key, 32 hex digits in a file outside the repository
# (docs/security.md). It is written into the image's .link_key section of a copy of the image;
# images as built carry none, and a vehicle without a key accepts no ground frame.
# Usage: KEY=FILE scripts/flash.sh [BOARD] [BUILD_DIR]   (BUILD_DIR defaults to build/stm32f405)
set -euo pipefail

board="${1:-}"
dir="${2:-build/stm32f405}/firmware/ports/stm32f405"
case "$board" in
  "" | hil) tool=openocd; image="$dir/fw_stm32f405.elf" ;;
  omnibusf4) tool=dfu-util; image="$dir/fw_stm32f405_flight.bin" ;;
  omnibusf4-pwm) tool=dfu-util; image="$dir/fw_stm32f405_flight_pwm.bin" ;;
  *)
    echo "flash: unknown BOARD '$board' (known: omnibusf4, omnibusf4-pwm; none for the HIL image)" >&2
    exit 2
    ;;
esac

if ! command -v "$tool" >/dev/null 2>&1; then
  echo "flash: $tool is not installed (Debian: sudo apt-get install $tool); it is not in scripts/install-deps.sh because flashing needs a board" >&2
  exit 1
fi
if [ ! -f "$image" ]; then
  echo "flash: $image is not built (make stm32f405)" >&2
  exit 1
fi

key="${KEY:-}"
if [ -z "$key" ]; then
  echo "flash: KEY=FILE is required: the vehicle's link key, 32 hex digits (make one: od -An -tx1 -N16 /dev/urandom | tr -d ' \n' > vehicle1.key)" >&2
  exit 2
fi
# The keyed copy of the image, in a private temporary directory removed on exit.
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$(dirname "$0")/key-image.sh" "${image%.bin}.elf" "$key" "$work/keyed.elf"

case "$tool" in
  openocd)
    openocd -f interface/stlink.cfg -f target/stm32f4x.cfg -c "program $work/keyed.elf verify reset exit"
    ;;
  dfu-util)
    arm-none-eabi-objcopy -O binary "$work/keyed.elf" "$work/keyed.bin"
    echo "flash: the board must be in its ROM bootloader: hold the BOOT button while plugging in USB"
    # 0483:df11 is ST's DFU bootloader; :leave starts the new image when done.
    dfu-util -d 0483:df11 -a 0 -s 0x08000000:leave -D "$work/keyed.bin"
    ;;
esac
