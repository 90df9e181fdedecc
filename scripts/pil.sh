#!/usr/bin/env bash
# Processor in the loop against the host (make pil; docs/hil.md "Processor in the loop"): flies
# the paper's series with seed SEED twice, on the firmware core compiled for this host and on the
# Cortex-M4 image in QEMU (hil fly --firmware qemu), and compares them: each throw's outcome, its
# catch point and the pole's energy error at the impact, and how far the two flights drift apart
# (the largest difference of any vehicle, pole or pole-end position in the attempts' time series).
# Passes when throws 8 and 9 are caught on the image, their energy error is within the paper's
# 0.0102 J, every outcome is the host's and every catch point within 1 cm of the host's.
# Usage: scripts/pil.sh HIL IMAGE OUT_DIR [SEED]
set -euo pipefail
if [ $# -lt 3 ] || [ $# -gt 4 ]; then
  echo "usage: scripts/pil.sh HIL IMAGE OUT_DIR [SEED]" >&2
  exit 2
fi
hil=$1 image=$2 out=$3 seed=${4:-1}
for f in "$hil" "$image"; do
  [ -f "$f" ] || { echo "pil: $f is missing (make host cortex-m4 builds it)" >&2; exit 2; }
done
rm -rf "$out/host" "$out/qemu"
mkdir -p "$out"

echo "pil: the paper's series, seed $seed, on the host's core"
"$hil" fly --series paper --seed "$seed" --out "$out/host" --no-report > "$out/host.txt"
echo "pil: the same on the Cortex-M4 image in QEMU (some minutes)"
start=$EPOCHREALTIME
"$hil" fly --series paper --seed "$seed" --firmware qemu --pil-image "$image" --out "$out/qemu" \
  --no-report > "$out/qemu.txt"
awk -v a="$start" -v b="$EPOCHREALTIME" 'BEGIN { printf "pil: %.0f s of wall time in QEMU\n", b - a }'
grep -A 30 "^     pil vehicle 1" "$out/qemu.txt"

# throws.csv: throw,outcome,flight_s,catch_height_m,catch_x_m,catch_y_m,travel_m,energy_error_J,...
status=0
echo "throw  host outcome     image outcome    catch point apart (mm)  energy error host / image (J)"
paste -d, "$out/host/throws.csv" "$out/qemu/throws.csv" | awk -F, -v n="$(head -1 "$out/host/throws.csv" | tr ',' '\n' | wc -l)" '
  NR == 1 { next }
  {
    d = sqrt(($5 - $(n + 5))^2 + ($6 - $(n + 6))^2) * 1000
    printf "%5d  %-15s  %-15s  %22.2f  %+.5f / %+.5f\n", $1, $2, $(n + 2), d, $8, $(n + 8)
    if ($2 != $(n + 2)) { print "pil: FAIL: throw " $1 " is " $(n + 2) " on the image, " $2 " on the host"; bad = 1 }
    if (d > 10) { print "pil: FAIL: throw " $1 "'"'"'s catch points are " d " mm apart"; bad = 1 }
    if (($1 == 8 || $1 == 9) && ($(n + 2) != "caught" || $(n + 8) > 0.0102 || $(n + 8) < -0.0102)) {
      print "pil: FAIL: throw " $1 " on the image: " $(n + 2) ", energy error " $(n + 8) " J"; bad = 1
    }
  }
  END { exit bad }' || status=1

# The attempts' time series, row by row (the same instants): the largest position difference.
worst=0
for h in "$out"/host/attempt_*.csv; do
  q="$out/qemu/$(basename "$h")"
  [ -f "$q" ] || { echo "pil: FAIL: $(basename "$h") is missing on the image"; status=1; continue; }
  d=$(paste -d, "$h" "$q" | awk -F, 'NR == 1 { n = NF / 2; next }
    { for (c = 2; c <= 13; ++c) { x = $c - $(n + c); if (x < 0) x = -x; if (x > m) m = x }
      for (c = 28; c <= 33; ++c) { x = $c - $(n + c); if (x < 0) x = -x; if (x > m) m = x } }
    END { printf "%.6f", m }')
  echo "pil: $(basename "$h"): positions at most $(awk -v d="$d" 'BEGIN { printf "%.3f", d * 1000 }') mm apart"
  worst=$(awk -v a="$worst" -v b="$d" 'BEGIN { print (b > a ? b : a) }')
done
awk -v w="$worst" 'BEGIN { printf "pil: the flights on the host and on the image drift at most %.3f mm apart\n", w * 1000 }'
[ "$status" -eq 0 ] && echo "pil: PASS"
exit "$status"
