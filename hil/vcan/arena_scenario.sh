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
  until grep -q "$2" "$1" 2>/dev/null; do
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
    for p in "$@"; do grep -q "$p" "$out/watch_$name.txt" || all=0; done
    [ $all -eq 1 ] && return 0
    [ $(($(date +%s) - t0)) -lt "$limit" ] || return 1
    sleep 0.5
  done
}
