#!/usr/bin/env bash
# ecat-slave --firmware-threads 2 live (issue 30 item 3): 250 drives served
# over EtherCAT-in-UDP on loopback, the project's master (another process)
# scans them, configures mailboxes and process data and takes them to Op,
# then cycles; SIGUSR1 makes ecat-slave print its statistics, whose
# firmware line shows the runs split over the two threads, and SIGTERM ends
# it (the helpers block signals, so the loop thread takes them). Only what
# a busy host cannot spoil is asserted: every drive in Op, the split, the
# exit - not the cycle's timing (run alone: the e2e_ prefix makes it serial).
# Then the same with --firmware-threads auto, judged again every 0.5 s.
# Usage: e2e_firmware_threads.sh SRCDIR BUILDDIR   (exit 77 = skipped)
set -uo pipefail
build=${2:?builddir}
slave="$build/bin/ecat-slave"
master="$build/bin/ecat-master"
[ -x "$slave" ] && [ -x "$master" ] || { echo "skip: ecat-slave/ecat-master not built"; exit 77; }
out=$(mktemp -d)
slave_pid=""
trap '[ -n "$slave_pid" ] && kill -9 "$slave_pid" 2> /dev/null; rm -rf "$out"' EXIT
status=0
fail() { echo "FAIL: $*"; status=1; }
# stop_slave PREFIX LOG: SIGTERM, then a clean exit within 5 s (the helpers
# block signals, so the loop thread takes it).
stop_slave() {
  kill -TERM "$slave_pid"
  for _ in $(seq 50); do kill -0 "$slave_pid" 2> /dev/null || break; sleep 0.1; done
  if kill -0 "$slave_pid" 2> /dev/null; then
    fail "${1}ecat-slave still running 5 s after SIGTERM"
  else
    wait "$slave_pid"
    local src=$?
    [ "$src" -eq 0 ] || fail "${1}ecat-slave exit $src after SIGTERM: $(tail -3 "$2")"
    slave_pid=""
  fi
}
n=250
port=$((36100 + $$ % 400))

# The loop's spin after each frame is the default --spin-us auto
# (docs/e2e.md "Frames in bursts"); the statistics say it.
"$slave" --udp "127.0.0.1:$port" --count $n --firmware-threads 2 > "$out/slave" 2>&1 &
slave_pid=$!
for _ in $(seq 50); do grep -q "slave(s) on udp" "$out/slave" && break; sleep 0.1; done
timeout 120 "$master" --udp "127.0.0.1:$port" --expect-slaves $n --cycles 1000 > "$out/master" 2>&1
rc=$?
grep -q "all $n slave(s) in Op" "$out/master" || fail "master exit $rc, not all in Op: $(grep -v 'station 0x' "$out/master" | tail -5)"
kill -USR1 "$slave_pid"
for _ in $(seq 50); do grep -q '^firmware-threads' "$out/slave" && break; sleep 0.1; done
line=$(grep '^firmware-threads' "$out/slave" | tail -1)
splits=$(sed -n 's/^firmware-threads 2 split-runs \([0-9]*\) .*/\1/p' <<< "$line")
[ -n "$splits" ] && [ "$splits" -gt 0 ] || fail "no firmware run split over the two threads: '$line'"
grep -Eq '^spin-us auto [0-9]+ ' "$out/slave" || fail "no --spin-us auto line in the statistics: $(grep -v '^  slave' "$out/slave" | tail -4)"
stop_slave "" "$out/slave"
echo "$n drives in Op over UDP; $line"

# --firmware-threads auto judged while running (slave/lane_judge.hpp): a
# trial every 0.5 s; whichever way the host favours, the trials happen, the
# statistics say the way in force and the last verdict, and every drive
# still reaches Op and cycles.
port=$((port + 1))
"$slave" --udp "127.0.0.1:$port" --count $n --firmware-threads auto --firmware-threads-recheck 0.5 > "$out/auto" 2>&1 &
slave_pid=$!
for _ in $(seq 50); do grep -q "slave(s) on udp" "$out/auto" && break; sleep 0.1; done
choice=$(grep -- '--firmware-threads auto:' "$out/auto" | head -1)
timeout 120 "$master" --udp "127.0.0.1:$port" --expect-slaves $n --cycles 3000 > "$out/master-auto" 2>&1
rc=$?
grep -q "all $n slave(s) in Op" "$out/master-auto" || fail "auto: master exit $rc, not all in Op: $(grep -v 'station 0x' "$out/master-auto" | tail -5)"
kill -USR1 "$slave_pid"
for _ in $(seq 50); do grep -q '^firmware-threads' "$out/auto" && break; sleep 0.1; done
if grep -q 'judged again every 0.5 s' <<< "$choice"; then
  line=$(grep '^firmware-threads' "$out/auto" | tail -1)
  trials=$(sed -n 's/^firmware-threads 2 split-runs [0-9]* helper-words [0-9]* auto [12] trials \([0-9]*\) switches [0-9]* last: .*/\1/p' <<< "$line")
  [ -n "$trials" ] && [ "$trials" -ge 1 ] || fail "auto: no trial judged: '$line' (start: $choice)"
  echo "auto: $choice; $line"
else
  # One CPU, or a chain that may not split: chosen once, nothing to judge.
  echo "auto not judged on this host: $choice"
fi
stop_slave "auto: " "$out/auto"
exit $status
