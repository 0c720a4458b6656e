#!/usr/bin/env bash
# The long DC run of issue 19 (docs/e2e.md "DC Sync0 for 10 minutes"): four DC
# drives in one chain (generic servo, simtach-rse, yaskawa-sigma5-sd,
# welcon-servo) in DC Sync0 at 1 ms over the veth pair of lib/netns.sh, under
# one master for DC_RUN_SECONDS (default 600), and the slave's own statistics
# (sync errors = 1C32h:0Bh per slave, SM watchdog, AL state) every 60 s and at
# exit. A measurement, not a ctest test: it takes minutes and its figures
# depend on the machine. Logs are kept in DC_RUN_OUT (default a new /tmp dir).
#   DC_RUN_MASTER=ecat (default): build/bin/ecat-master --dc, SCHED_FIFO 50
#     (--rt-priority), frames at the DC phase lock's lead before SYNC0, slaves
#     that leave Op acknowledged and brought back (--recover), as ec_sample does;
#     DC_RUN_MASTER_ARGS adds options (e.g. "--dc-lead-us 300").
#   DC_RUN_MASTER=soem: the program in ECAT_SOEM_DC (SOEM 2.x ec_sample with
#     DC Sync0 and a run time argument, built outside this repository; the
#     changes are listed in docs/e2e.md), called as PROG m0 1000 SECONDS.
# Usage: dc_long_run.sh SRCDIR BUILDDIR
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
# shellcheck source-path=SCRIPTDIR source=../scripts/lib/netns.sh
. "$src/tests/scripts/lib/netns.sh"

seconds=${DC_RUN_SECONDS:-600}
which=${DC_RUN_MASTER:-ecat}
out=${DC_RUN_OUT:-$(mktemp -d /tmp/dc_long_run.XXXXXX)}
mkdir -p "$out"
e2e_require_bins ecat-slave ecat-master
e2e_require_netns
e2e_setup dl
e2e_use_realtime
d="$src/xml/devices"
chain="$d/generic-servo.xml,$d/simtach-rse.xml,$d/yaskawa-sigma5-sd.xml,$d/welcon-servo.xml"
[ -f "$d/generic-servo.xml" ] || chain="${chain#"$d/generic-servo.xml,"}"
E2E_SLAVE_TIMEOUT=$((seconds + 300))  # read by e2e_start_slave (lib/netns.sh)
export E2E_SLAVE_TIMEOUT
e2e_start_slave slave "${E2E_SLAVE_RT[@]}" --stats 60 --chain "$chain" || exit 1
slave_pid=$(e2e_slave_program_pid "$E2E_SLAVE_PID")
cycles=$((seconds * 1000))
echo "dc_long_run: $which, $seconds s, start $(date -u +%H:%M:%S) UTC, load $(cut -d' ' -f1-3 /proc/loadavg)"
steal0=$(awk '/^cpu /{print $9}' /proc/stat)
rc=0
case "$which" in
  ecat)
    # shellcheck disable=SC2086  # DC_RUN_MASTER_ARGS is a list of options
    timeout -s KILL $((seconds + 240)) ip netns exec "$E2E_NS_M" "$build/bin/ecat-master" --iface m0 --dc \
      --cycles "$cycles" --period-us 1000 --expect-slaves 4 -q --rt-priority 50 --recover ${DC_RUN_MASTER_ARGS:-} \
      > "$out/master.log" 2>&1 || rc=$?
    ;;
  soem)
    prog=${ECAT_SOEM_DC:?set ECAT_SOEM_DC to the DC variant of ec_sample}
    timeout -s KILL $((seconds + 240)) ip netns exec "$E2E_NS_M" "$prog" m0 1000 "$seconds" 2>&1 \
      | tr '\r' '\n' | grep -v '^Processdata cycle' > "$out/master.log" || rc=$?
    ;;
  *) echo "DC_RUN_MASTER: ecat or soem"; exit 2 ;;
esac
steal1=$(awk '/^cpu /{print $9}' /proc/stat)
echo "dc_long_run: end $(date -u +%H:%M:%S) UTC, master exit $rc, load $(cut -d' ' -f1-3 /proc/loadavg)," \
  "steal $(((steal1 - steal0) * 10)) ms over the run (all CPUs)"
# The slave's statistics now, while the master has just stopped.
kill -USR1 "$slave_pid" 2> /dev/null
sleep 1
e2e_stop "$E2E_SLAVE_PID"
cp "$E2E_TMP/slave.log" "$out/slave.log"
sed 's/^/  [master] /' "$out/master.log" | tail -40
grep -vE '^(slave [0-9]+:|.*slave\(s\) on)' "$out/slave.log" | tail -30 | sed 's/^/  [slave] /'
echo "dc_long_run: logs in $out"
exit $rc
