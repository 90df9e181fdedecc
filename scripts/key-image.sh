#!/usr/bin/env bash
# Writes a vehicle's link key into a copy of a firmware image (docs/security.md): the image's
# .link_key section, erased as built, gets the key's 16 bytes. scripts/flash.sh uses it.
# Usage: scripts/key-image.sh IMAGE.elf KEYFILE OUT.elf
set -euo pipefail

if [ $# -ne 3 ]; then
  echo "usage: scripts/key-image.sh IMAGE.elf KEYFILE OUT.elf" >&2
  exit 2
fi
image="$1"; key="$2"; out="$3"

if ! hex=$(tr -d ' \t\r\n' < "$key" 2>/dev/null) || ! [[ "$hex" =~ ^[0-9a-fA-F]{32}$ ]]; then
  echo "key-image: $key: a link key is 32 hexadecimal digits (128 bits)" >&2
  exit 2
fi
if [[ "$hex" =~ ^(0{32}|[fF]{32})$ ]]; then
  echo "key-image: $key: all zeros or all ones is not a key" >&2
  exit 2
fi
if ! arm-none-eabi-objdump -h "$image" 2>/dev/null | grep -q ' \.link_key '; then
  echo "key-image: $image has no .link_key section (is it an STM32F405 image?)" >&2
  exit 1
fi

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# The 16 bytes, without xxd (not installed everywhere): each pair of digits as a \x escape.
printf "$(sed 's/../\\x&/g' <<< "$hex")" > "$work/key.bin"
arm-none-eabi-objcopy --update-section .link_key="$work/key.bin" "$image" "$out"
