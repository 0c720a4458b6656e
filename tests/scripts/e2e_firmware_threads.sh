#!/usr/bin/env bash
# ecat-slave --firmware-threads 2 live (issue 30 item 3): 250 drives served
# over EtherCAT-in-UDP on loopback, the project's master (another process)
# scans them, configures mailboxes and process data and takes them to Op,
# then cycles; SIGUSR1 makes ecat-slave print its statistics, whose
# firmware line shows the runs split over the two threads, and SIGTERM ends
# it (the helpers block signals, so the loop thread takes them). Asserted:
# every drive in Op, the split, the exit - not the cycle's timing. A start-up
# that fails only as the spec allows a late master or host (001Bh, a frame
# lost while the slave dropped stale ones) with the evidence beside it is
# run again, as every live script's (lib/netns.sh, docs/e2e.md "Live timing
# under load"): beside two CPU burners the start-up lost SDO replies to
# stale drops. Then the same with --firmware-threads auto, judged again
# every 0.5 s.
# Usage: e2e_firmware_threads.sh SRCDIR BUILDDIR   (exit 77 = skipped)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
slave="$build/bin/ecat-slave"
master="$build/bin/ecat-master"
[ -x "$slave" ] && [ -x "$master" ] || { echo "skip: ecat-slave/ecat-master not built"; exit 77; }
# shellcheck source-path=SCRIPTDIR source=lib/netns.sh
. "$src/tests/scripts/lib/netns.sh"  # the live-timing judgement only (no namespaces here)
E2E_TMP=$(mktemp -d)
out=$E2E_TMP
slave_pid=""
trap '[ -n "$slave_pid" ] && kill -9 "$slave_pid" 2> /dev/null; rm -rf "$out"' EXIT
fail() { e2e_fail "$*"; }
# stop_slave PREFIX LOG: SIGTERM, then a clean exit within 5 s (the helpers
# block signals, so the loop thread takes it).
stop_slave() {
  kill -TERM "$slave_pid"
  for _ in $(seq 50); do kill -0 "$slave_pid" 2> /dev/null || break; sleep 0.1; done
  if kill -0 "$slave_pid" 2> /dev/null; then
    fail "${1}ecat-slave still running 5 s after SIGTERM"
    kill -9 "$slave_pid" 2> /dev/null
  else
    wait "$slave_pid"
    local rc=$?
    [ "$rc" -eq 0 ] || fail "${1}ecat-slave exit $rc after SIGTERM: $(tail -3 "$2")"
  fi
  slave_pid=""
}
n=250
port=$((36100 + $$ % 400))

# start_run NAME CYCLES SLAVE-ARGS...: a new slave on the next port (log
# NAME), the master for CYCLES cycles (log NAME-master), then the slave's
# statistics (SIGUSR1); returns 0 when every drive reached Op (the cycles
# after it are not judged: their timing is the host's), else what
# e2e_judge_master_run says of the start-up (1 failed, 2 late), with the
# slave still running.
start_run() {
  local name=$1 cycles=$2 rc
  shift 2
  port=$((port + 1))
  "$slave" --udp "127.0.0.1:$port" --count $n "$@" > "$out/$name.log" 2>&1 &
  slave_pid=$!
  for _ in $(seq 50); do grep -q "slave(s) on udp" "$out/$name.log" 2> /dev/null && break; sleep 0.1; done
  timeout 120 "$master" --udp "127.0.0.1:$port" --expect-slaves $n --cycles "$cycles" > "$out/$name-master.log" 2>&1
  rc=$?
  kill -USR1 "$slave_pid"
  for _ in $(seq 50); do grep -q '^firmware-threads' "$out/$name.log" && break; sleep 0.1; done
  sleep 0.05
  if grep -q "all $n slave(s) in Op" "$out/$name-master.log"; then
    E2E_VERDICT="all $n in Op (master exit $rc, slave stale-dropped $(e2e_slave_stale "$name"))"
    return 0
  fi
  e2e_judge_master_run "$name-master" "$name" 1000 "$rc" "0x001B" 0 1000000
  local verdict=$?
  # The judgement passes a run that exited 0; without "in Op" it did not.
  [ "$verdict" -ne 0 ] || { E2E_VERDICT="master exit 0 without all $n in Op: $(tail -3 "$out/$name-master.log")"; verdict=1; }
  return "$verdict"
}

# The loop's spin after each frame is the default --spin-us auto
# (docs/e2e.md "Frames in bursts"); the statistics say it.
two_threads() {
  start_run two 1000 --firmware-threads 2
  local verdict=$?
  if [ "$verdict" -ne 0 ]; then stop_slave "" "$out/two.log"; return "$verdict"; fi
  local line splits
  line=$(grep '^firmware-threads' "$out/two.log" | tail -1)
  splits=$(sed -n 's/^firmware-threads 2 split-runs \([0-9]*\) .*/\1/p' <<< "$line")
  [ -n "$splits" ] && [ "$splits" -gt 0 ] || fail "no firmware run split over the two threads: '$line'"
  grep -Eq '^spin-us auto [0-9]+ ' "$out/two.log" || fail "no --spin-us auto line in the statistics: $(grep -v '^  slave' "$out/two.log" | tail -4)"
  stop_slave "" "$out/two.log"
  E2E_VERDICT="$E2E_VERDICT; $n drives in Op over UDP; $line"
  return 0
}

# --firmware-threads auto judged while running (slave/lane_judge.hpp): a
# trial every 0.5 s; whichever way the host favours, the trials happen, the
# statistics say the way in force and the last verdict, and every drive
# still reaches Op and cycles.
auto_threads() {
  start_run auto 3000 --firmware-threads auto --firmware-threads-recheck 0.5
  local verdict=$?
  if [ "$verdict" -ne 0 ]; then stop_slave "auto: " "$out/auto.log"; return "$verdict"; fi
  local choice line trials
  choice=$(grep -- '--firmware-threads auto:' "$out/auto.log" | head -1)
  if grep -q 'judged again every 0.5 s' <<< "$choice"; then
    line=$(grep '^firmware-threads' "$out/auto.log" | tail -1)
    trials=$(sed -n 's/^firmware-threads 2 split-runs [0-9]* helper-words [0-9]* auto [12] trials \([0-9]*\) switches [0-9]* last: .*/\1/p' <<< "$line")
    [ -n "$trials" ] && [ "$trials" -ge 1 ] || fail "auto: no trial judged: '$line' (start: $choice)"
    E2E_VERDICT="$E2E_VERDICT; $choice; $line"
  else
    # One CPU, or a chain that may not split: chosen once, nothing to judge.
    E2E_VERDICT="$E2E_VERDICT; auto not judged on this host: $choice"
  fi
  stop_slave "auto: " "$out/auto.log"
  return 0
}

e2e_live_phase "two threads" two_threads
e2e_live_phase "auto" auto_threads
exit $e2e_status
