#!/usr/bin/env bash
# End to end over a veth pair (issue 14 item 6): a chain of five digital twins
# of different vendors, each made by ecat-slave --esi from a file of the vendor
# ESI corpus (tests/data/esi-vendor, docs/twins.md): NI 9144 coupler, Ingenia
# and Synapticon servo drives, a Microchip evaluation slave, a MetalMusings
# stepper/IO card. ecat-master on the other end brings all five to Op and runs
# >= 2000 cycles at 1 ms with no lost frame and the expected WKC on every cycle
# (ecat-master exits 1 otherwise). SOEM is run against the same chain by
# e2e_soem.sh's mechanism where its binaries are present (not here).
# Usage: e2e_twins.sh SRCDIR BUILDDIR   (exit 77 = skipped: not root / no netns)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
# shellcheck source-path=SCRIPTDIR source=lib/netns.sh
. "$src/tests/scripts/lib/netns.sh"
e2e_require_bins ecat-slave ecat-master
e2e_require_netns
cycles=${E2E_CYCLES:-2000}
e2e_setup t
e2e_use_realtime

c="$src/tests/data/esi-vendor"
twins=(ni-9144 ingenia-drive synapticon-somanet-cia402 microchip-samd51-lan9252 metalmusings-easercat-3000)
args=()
for t in "${twins[@]}"; do args+=(--esi "$c/$t.xml"); done
if e2e_start_slave twins "${E2E_SLAVE_RT[@]}" "${args[@]}"; then
  e2e_master twinsm 90 --cycles "$cycles" --period-us 1000 --expect-slaves "${#twins[@]}" \
    || e2e_fail "chain of ${#twins[@]} vendor twins: ecat-master exit $?"
  # Each slave's identity as the master read it from the SII.
  for v in 0x000001F9 0x0000029C 0x000022D2 0x000004D8 0xD0BED1D0; do
    grep -q "vendor $v" "$E2E_TMP/twinsm.log" || e2e_fail "no slave with vendor $v in the scan"
  done
  grep -q "all ${#twins[@]} slave(s) in Op" "$E2E_TMP/twinsm.log" || e2e_fail "not all twins reached Op"
  echo "chain of ${#twins[@]} vendor twins, $cycles cycles at 1 ms: $(e2e_cycle_line twinsm)"
  e2e_stop "$E2E_SLAVE_PID"
  e2e_check_no_watchdog_during_run twins
else
  e2e_fail "twin chain did not start"
fi

[ "$e2e_status" -eq 0 ] && echo "e2e_twins: OK"
exit "$e2e_status"
