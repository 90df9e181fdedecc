# Shared by the arena's guest scenarios (hil_run_on_vcan.sh, hil_attempt_on_vcan.sh), sourced
# from $PA_FILES after they set files, out and domain. POSIX sh (busybox sh in the QEMU guest).

say() { echo "scenario: $*"; }
elapsed() { cut -d' ' -f1 /proc/uptime; }
stop_all() {
  for p in $pids; do kill -TERM "$p" 2>/dev/null; done
  for p in $pids; do wait "$p" 2>/dev/null; done
}
# wait_for FILE TEXT SECONDS: until FILE holds TEXT.
wait_for() {
  n=0
  until grep -q -e "$2" "$1" 2>/dev/null; do
    n=$((n + 1))
    [ $n -le $(($3 * 10)) ] || return 1
    sleep 0.1
  done
}
# watch_until NAME SECONDS PATTERN...: `groundstation watch --once` until every PATTERN is in its
# view; the last view is kept in watch_NAME.txt.
watch_until() {
  name=$1
  limit=$2
  shift 2
  t0=$(date +%s)
  while :; do
    "$files/groundstation" watch --domain $domain --once >"$out/watch_$name.txt" 2>&1
    all=1
    for p in "$@"; do grep -q -e "$p" "$out/watch_$name.txt" || all=0; done
    [ $all -eq 1 ] && return 0
    [ $(($(date +%s) - t0)) -lt "$limit" ] || return 1
    sleep 0.5
  done
}

# The arena on the plant's clock (docs/hil.md): hil run --ground-clock on vcan0 (ground), vcan1
# and vcan2 with every bus logged to $out/logs, into $out/hil_run.txt.
start_plant() {
  mkdir -p "$out/logs"
  "$files/hil" run --ground-can vcan0 --vehicle-can vcan1,vcan2 --domain $domain --seed "$1" --ground-clock \
    --log "$out/logs" >"$out/hil_run.txt" 2>&1 &
  plant_pid=$!
  pids="$pids $!"
}
# start_firmware N: vehicle N's fw_vehicle on vcanN, into $out/fw_vehicleN.txt; its pid in fw_pidN.
start_firmware() {
  "$files/fw_vehicle" --can "vcan$1" --node "$1" --key "$key" >"$out/fw_vehicle$1.txt" 2>&1 &
  eval "fw_pid$1=$!"
  pids="$pids $!"
}
# start_ground_station NAME [ARG...]: groundstation run --hil-clock on vcan0, into $out/NAME.txt;
# its pid in gs_pid.
start_ground_station() {
  name=$1
  shift
  "$files/groundstation" run --can vcan0 --domain $domain --key1 "$key" --key2 "$key" --hil-clock "$@" \
    >"$out/$name.txt" 2>&1 &
  gs_pid=$!
  pids="$pids $!"
}
op() { "$files/groundstation" op "$@" --domain $domain --timeout 30; }
# Every view `groundstation watch` draws, twice a second of the guest's clock, into
# $out/dds_watch.txt: the run's DDS telemetry and events, recorded.
record_dds() {
  "$files/groundstation" watch --domain $domain >"$out/dds_watch.txt" 2>&1 &
  pids="$pids $!"
}
# fail WHY: stops the processes and shows the end of each one's output.
fail() {
  say "FAIL: $*"
  stop_all
  for f in "$out"/hil_run.txt "$out"/fw_vehicle*.txt "$out"/groundstation*.txt; do
    echo "--- $(basename "$f")"
    tail -n 20 "$f"
  done
  exit 1
}
