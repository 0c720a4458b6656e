#!/usr/bin/env bash
# End to end over a veth pair between two network namespaces (issue 5 item 4):
# ecat-slave answers raw EtherCAT on one end, ecat-master drives it from the
# other: Init -> PreOp -> SafeOp -> Op and >= 2000 cycles at 1 ms with no
# lost frame and the expected WKC every cycle (ecat-master exits 1 otherwise).
#  (a) the embedded generic servo, moved in CSP (--move);
#  (b) a chain of the 4 seed drives in free run;
#  (c) DC Sync0 mode (--dc) on the 4 seed drives plus the generic servo: the
#      master writes 1C32h:01 only where it is writable and differs, and skips
#      leadshine-isv2-can, which has no DC unit; the CSP drives are moved.
# Master and slave run with real-time priority where the kernel allows it
# (e2e_use_realtime; E2E_NO_RT=1 to compare without).
# The cycle statistics lines are printed (see docs/e2e.md for figures).
# Usage: e2e_veth.sh SRCDIR BUILDDIR   (exit 77 = skipped: not root / no netns)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
# shellcheck source-path=SCRIPTDIR source=lib/netns.sh
. "$src/tests/scripts/lib/netns.sh"
e2e_require_bins ecat-slave ecat-master
e2e_require_netns
cycles=${E2E_CYCLES:-2000}
e2e_setup v
e2e_use_realtime

# (a) one generic servo, moved.
if e2e_start_slave servo "${E2E_SLAVE_RT[@]}"; then
  e2e_master servo 60 --cycles "$cycles" --period-us 1000 --expect-slaves 1 --move \
    || e2e_fail "(a) generic servo: ecat-master exit $?"
  echo "(a) generic servo, $cycles cycles at 1 ms, --move: $(e2e_cycle_line servo)"
  e2e_stop "$E2E_SLAVE_PID"
  e2e_check_no_watchdog_during_run servo
else
  e2e_fail "(a) slave did not start"
fi

# (b) the four seed drives in one chain (free run).
d="$src/xml/devices"
chain="$d/simtach-rse.xml,$d/yaskawa-sigma5-sd.xml,$d/welcon-servo.xml,$d/leadshine-isv2-can.xml"
if e2e_start_slave chain "${E2E_SLAVE_RT[@]}" --chain "$chain"; then
  e2e_master chain 90 --cycles "$cycles" --period-us 1000 --expect-slaves 4 \
    || e2e_fail "(b) chain of 4 seed drives: ecat-master exit $?"
  echo "(b) chain of 4 seed drives, $cycles cycles at 1 ms: $(e2e_cycle_line chain)"
  e2e_stop "$E2E_SLAVE_PID"
  e2e_check_no_watchdog_during_run chain
else
  e2e_fail "(b) slave chain did not start"
fi

# (c) DC Sync0 mode on the drives whose 1C32h:01 is writable.
# A DC slave must count a SYNC0 that comes without new outputs (ETG.1020 sync
# error counter, 1C32h:0Bh) and leave Op with 0x001A when the master misses
# its cycles, so zero sync errors can be asked only of a run whose master kept
# its 1 ms cycle. This VM stalls processes for 7-25 ms now and then even at
# SCHED_FIFO (seen 2026-11-25 on an idle machine; docs/e2e.md), which no DC
# slave survives. So: a run with state errors whose master was late by more
# than one period is a host stall, not a verdict; the slaves must then have
# left Op with 0x001A and nothing else, no frame may be lost and every WKC must
# be right; up to 3 runs are tried for one with the master on time. State
# errors while the master kept its cycle, any other AL code, a lost frame or a
# wrong WKC fail at once.
dc_chain="$chain,$d/generic-servo.xml"
dc_period_us=1000
dc_done=0
for dc_try in 1 2 3; do
  if ! e2e_start_slave dcslave "${E2E_SLAVE_RT[@]}" --chain "$dc_chain"; then
    e2e_fail "(c) DC chain did not start"
    break
  fi
  e2e_master dc 90 --cycles "$cycles" --period-us "$dc_period_us" --expect-slaves 5 --dc --move
  dc_rc=$?
  dc_line=$(e2e_cycle_line dc)
  echo "(c) 4 seed drives + generic servo, $cycles cycles at 1 ms, --dc --move (run $dc_try): $dc_line"
  e2e_stop "$E2E_SLAVE_PID"
  e2e_check_no_watchdog_during_run dcslave
  if [ "$dc_rc" -eq 0 ]; then
    dc_done=1
    break
  fi
  dc_jitter=$(sed -n 's/.*cycle-jitter-max-us \([0-9.]*\).*/\1/p' <<< "$dc_line")
  dc_lost=$(sed -n 's/.* lost \([0-9]*\) .*/\1/p' <<< "$dc_line")
  dc_wkc=$(sed -n 's/.* wkc-errors \([0-9]*\) .*/\1/p' <<< "$dc_line")
  dc_codes=$(grep -E '^ +slave +[0-9]+ ' "$E2E_TMP/dcslave.log" | sed -n 's/.*AL code \(0x[0-9A-Fa-f]*\).*/\1/p' |
    sort -u | grep -Ev '^0x(0000|001A)$' | tr '\n' ' ')
  if [ -z "$dc_jitter" ] || [ "${dc_lost:-1}" != 0 ] || [ "${dc_wkc:-1}" != 0 ] || [ -n "$dc_codes" ]; then
    e2e_fail "(c) DC chain: ecat-master exit $dc_rc (lost ${dc_lost:-?}, wkc-errors ${dc_wkc:-?}, other AL codes: ${dc_codes:-none})"
    break
  fi
  if awk -v j="$dc_jitter" -v p="$dc_period_us" 'BEGIN { exit !(j <= p) }'; then
    e2e_fail "(c) DC chain: state errors while the master kept its cycle (jitter max $dc_jitter us)"
    break
  fi
  echo "(c) run $dc_try: the master was late by up to $dc_jitter us (host stall); the slaves that left Op did so with 0x001A, as they must"
done
if [ "$dc_done" = 0 ] && [ "$e2e_status" = 0 ]; then
  echo "NOTE: (c) zero sync errors not shown here: in each of 3 runs the host stalled the master by more than one period"
fi

[ "$e2e_status" -eq 0 ] && echo "e2e_veth: OK"
exit "$e2e_status"
