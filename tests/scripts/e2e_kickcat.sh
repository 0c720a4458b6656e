#!/usr/bin/env bash
# Interoperability with a second independent open-source master (issue 19):
# KickCAT's (leducp/KickCAT) example programs against ecat-slave over a veth
# pair between two network namespaces (docs/e2e.md "Independent master:
# KickCAT").
#  (a) easycat_example on every device file of xml/devices, one at a time:
#      scan, SII, PreOp, the PDO layout read over CoE (SDO uploads of 1C12h/
#      1C13h and the mapping objects, KickCAT's emulated complete access),
#      SafeOp, Op, then its 1 ms loop of LRD + LWR + error counters + mailbox
#      polling for E2E_KICKCAT_SECONDS (default 5) seconds;
#  (b) the same on a mixed chain of every device file;
#  (c) ds402_sinus on yaskawa-sigma5-sd (its PDOs are configurable; the
#      generic servo's are fixed and rightly refuse 1600h:00 = 0 with
#      06010002h): SDO downloads (6060h, PDO mapping and assignment), CSP at
#      1 ms, enable, a sinus, disable.
# KickCAT gives every frame 2 ms and gives up its whole start-up on the first
# late one (Bus::areEepromReady catches it as "Timeout"); a user-space slave
# on a loaded 2-core machine is sometimes woken later than that even at
# SCHED_FIFO, so a start-up that ends in that timeout before "Init done" is
# tried again, at most four times, and said so. Nothing after "Init done" is.
# Checks: the slave count, SafeOp and Op reached, no error in the cyclic loop
# (KickCAT throws on a wrong working counter or a lost frame: "Error in loop
# iteration"), the loop ran, and no SM watchdog in the slave while it ran.
# KickCAT is not a Debian package: the binaries are taken from
# $ECAT_KICKCAT_BIN (a directory) or PATH; without them the test is skipped
# (exit 77). Build recipe: docs/e2e.md.
# Usage: e2e_kickcat.sh SRCDIR BUILDDIR
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
# shellcheck source-path=SCRIPTDIR source=lib/netns.sh
. "$src/tests/scripts/lib/netns.sh"

kickcat_find() {
  local name=$1
  if [ -n "${ECAT_KICKCAT_BIN:-}" ] && [ -x "$ECAT_KICKCAT_BIN/$name" ]; then
    echo "$ECAT_KICKCAT_BIN/$name"
  else
    command -v "$name" 2> /dev/null
  fi
}
easycat=$(kickcat_find easycat_example) || { echo "skip: KickCAT easycat_example not found (set ECAT_KICKCAT_BIN=dir)"; exit 77; }
sinus=$(kickcat_find ds402_sinus) || sinus=""
e2e_require_bins ecat-slave
e2e_require_netns
e2e_setup kc
e2e_use_realtime
seconds=${E2E_KICKCAT_SECONDS:-5}

# Runs a KickCAT program in the master namespace on m0 for at most LIMIT
# seconds; output (terminal escapes removed) to $E2E_TMP/NAME.log. Returns
# its exit code (124/137: stopped by the limit, which easycat needs: it
# loops for ever).
kickcat_run() {
  local name=$1 limit=$2 prog=$3; shift 3
  timeout -s INT -k 2 "$limit" ip netns exec "$E2E_NS_M" "${E2E_MASTER_RT[@]}" "$prog" -i m0 "$@" 2>&1 \
    | sed -u 's/\x1b\[[0-9;]*[A-Za-z]//g' > "$E2E_TMP/$name.log"
  return "${PIPESTATUS[0]}"
}
expect_line() {  # NAME REGEX WHAT
  grep -qE "$2" "$E2E_TMP/$1.log" || e2e_fail "$1: $3 (no line matching '$2')"
}

# easycat_example: N slaves to Op, then the cyclic loop without an error.
check_easycat() {
  local name=$1 count=$2 try
  for try in 1 2 3 4 5; do
    kickcat_run "$name" "$((seconds + 15))" "$easycat"
    grep -q '^Init done$' "$E2E_TMP/$name.log" && break
    echo "$name: start-up attempt $try ended before 'Init done': $(grep -m1 -E 'Timeout|Error|error' "$E2E_TMP/$name.log")"
  done
  expect_line "$name" "^Detected slaves: $count\$" "slave count"
  [ "$(grep -ciE '^Slave [0-9]+ state is safe[-_]op' "$E2E_TMP/$name.log")" -ge "$count" ] || e2e_fail "$name: not every slave in SAFE_OP"
  expect_line "$name" '^Running loop\.\.\.$' "Op not reached"
  [ "$(grep -cE '^ - Slave [0-9]+ input: [0-9]+ output: [0-9]+$' "$E2E_TMP/$name.log")" -eq "$count" ] \
    || e2e_fail "$name: process data sizes missing"
  local loops errors
  loops=$(grep -c '^input_slave_0: ' "$E2E_TMP/$name.log")
  errors=$(grep -c 'Error in loop iteration' "$E2E_TMP/$name.log")
  [ "$loops" -ge 100 ] || e2e_fail "$name: only $loops cycles"
  # A cycle whose frame is not back within KickCAT's 10 ms is an error there;
  # on a loaded 2-core machine a user-space slave is now and then that late:
  # up to one per 1000 cycles is reported, more fails.
  [ "$errors" -le $((loops / 1000)) ] || e2e_fail "$name: $errors cycles with an error: $(grep -m1 -A1 'Error in loop iteration' "$E2E_TMP/$name.log" | tr '\n' ' ')"
  echo "$name: $count slave(s) in Op, $loops cycles, $errors errors; sizes: $(grep -E '^ - Slave [0-9]+ input' "$E2E_TMP/$name.log" | tr '\n' ';')"
}

d="$src/xml/devices"
all=()
for f in "$d"/*.xml; do
  all+=("$f")
  base=$(basename "$f" .xml)
  if e2e_start_slave "s_$base" "${E2E_SLAVE_RT[@]}" --device "$f"; then
    check_easycat "kc_$base" 1
    e2e_stop "$E2E_SLAVE_PID"
    e2e_check_no_watchdog_during_run "s_$base"
  else
    e2e_fail "$base: slave did not start"
  fi
done

chain=$(IFS=,; echo "${all[*]}")
if e2e_start_slave s_chain "${E2E_SLAVE_RT[@]}" --chain "$chain"; then
  check_easycat kc_chain "${#all[@]}"
  e2e_stop "$E2E_SLAVE_PID"
  e2e_check_no_watchdog_during_run s_chain
else
  e2e_fail "chain: slave did not start"
fi

if [ -n "$sinus" ]; then
  if e2e_start_slave s_sinus "${E2E_SLAVE_RT[@]}" --device "$d/yaskawa-sigma5-sd.xml"; then
    for try in 1 2 3; do
      kickcat_run kc_sinus "$((seconds + 30))" "$sinus" --duration "$seconds" --amplitude 20 --frequency 1
      rc=$?
      grep -q 'Bus.cc:[0-9]*: Timeout' "$E2E_TMP/kc_sinus.log" || break
      echo "kc_sinus: start-up attempt $try ended in KickCAT's EEPROM timeout"
    done
    [ "$rc" -eq 0 ] || e2e_fail "ds402_sinus exit $rc"
    expect_line kc_sinus '^Motor enabled at ' "drive not enabled"
    expect_line kc_sinus '^Disabling motor' "run did not end"
    # ds402_sinus gives a frame 500 us, less than the loaded VM's round-trip
    # tail (0.3 % and 3 % of cycles missed it in two runs, docs/e2e.md): up to
    # 5 % late cycles are reported, more fail.
    bus_errors=$(grep -cE '^\[[0-9]+\] ' "$E2E_TMP/kc_sinus.log")
    [ "$bus_errors" -le $((seconds * 50)) ] || e2e_fail "ds402_sinus: $bus_errors cycles with a bus error: $(grep -m3 -E '^\[[0-9]+\] ' "$E2E_TMP/kc_sinus.log" | tr '\n' ' ')"
    echo "kc_sinus: $bus_errors of $((seconds * 1000)) cycles with a bus error (frame not back within 500 us)"
    echo "kc_sinus: $(grep -m1 '^Motor enabled' "$E2E_TMP/kc_sinus.log")"
    e2e_stop "$E2E_SLAVE_PID"
    e2e_check_no_watchdog_during_run s_sinus
  else
    e2e_fail "sinus: slave did not start"
  fi
else
  echo "note: KickCAT ds402_sinus not found: (c) not run"
fi

for f in "$E2E_TMP"/kc_*.log; do
  [ -n "${ECAT_E2E_KEEP:-}" ] || break
  mkdir -p "$ECAT_E2E_KEEP" && cp "$E2E_TMP"/*.log "$ECAT_E2E_KEEP"/ && echo "logs kept in $ECAT_E2E_KEEP"
  break
done
[ "$e2e_status" -eq 0 ] && echo "e2e_kickcat: OK"
exit "$e2e_status"
