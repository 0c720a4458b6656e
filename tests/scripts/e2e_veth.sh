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
dc_chain="$chain,$d/generic-servo.xml"
if e2e_start_slave dcslave "${E2E_SLAVE_RT[@]}" --chain "$dc_chain"; then
  e2e_master dc 90 --cycles "$cycles" --period-us 1000 --expect-slaves 5 --dc --move \
    || e2e_fail "(c) DC chain: ecat-master exit $?"
  echo "(c) 4 seed drives + generic servo, $cycles cycles at 1 ms, --dc --move: $(e2e_cycle_line dc)"
  e2e_stop "$E2E_SLAVE_PID"
  e2e_check_no_watchdog_during_run dcslave
else
  e2e_fail "(c) DC chain did not start"
fi

[ "$e2e_status" -eq 0 ] && echo "e2e_veth: OK"
exit "$e2e_status"
