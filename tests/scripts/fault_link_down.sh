#!/usr/bin/env bash
# Fault: link down on the veth and back (issue 8 item 3). The segment is in
# Op; the master's end of the veth goes down (`ip link set m0 down`) while a
# master is exchanging process data, stays down for a second and comes back.
# The master must end (bounded) reporting lost frames, not hang; ecat-slave
# must survive (no crash, its socket still serves); with no frames the SM
# watchdog takes it to SafeOp (001Bh); a new master run reaches Op again
# with no lost frame and the right WKC every cycle.
# Under load (lib/netns.sh "Live timing under load"): a master run that must
# succeed may, when the host stalled master or slave, lose the frames the
# slave dropped as stale or see the slave leave Op with 001Bh; such a run is
# run again (up to E2E_LIVE_ATTEMPTS) and passes with a NOTE when every
# attempt was late. A wrong WKC, another AL code or a loss the slave did not
# drop fail at once.
# Usage: fault_link_down.sh SRCDIR BUILDDIR   (exit 77 = skipped)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
# shellcheck source-path=SCRIPTDIR source=lib/netns.sh
. "$src/tests/scripts/lib/netns.sh"
e2e_require_bins ecat-slave ecat-master
e2e_require_netns
e2e_setup l
# SCHED_FIFO where allowed, as every live script (lib/netns.sh): the slave
# must take its frames within --max-frame-age on a loaded host.
e2e_use_realtime

e2e_start_slave slave "${E2E_SLAVE_RT[@]}" || exit 1
pid=$(e2e_slave_program_pid "$E2E_SLAVE_PID")

# A master in Op for 3000 cycles; the link drops under it after ~1 s.
timeout -s KILL 60 ip netns exec "$E2E_NS_M" "$build/bin/ecat-master" --iface m0 --cycles 3000 -q \
  > "$E2E_TMP/during.log" 2>&1 &
mpid=$!
sleep 1.5
ip -n "$E2E_NS_M" link set m0 down || e2e_fail "ip link set down"
sleep 1
ip -n "$E2E_NS_M" link set m0 up || e2e_fail "ip link set up"
wait "$mpid"; rc=$?
sed 's/^/  [during] /' "$E2E_TMP/during.log"
[ "$rc" -ne 137 ] || e2e_fail "the master hung while the link was down (killed by timeout)"
grep -Eq '^cycles 3000 lost [1-9]' "$E2E_TMP/during.log" || echo "note: the master lost no frame or failed earlier (exit $rc)"

kill -0 "$pid" 2> /dev/null || e2e_fail "ecat-slave died when the link went down"
sleep 0.5
kill -USR1 "$pid"
sleep 0.3
line=$(grep -E '^ +slave +1 ' "$E2E_TMP/slave.log" | tail -1)
echo "after the link came back: $line"
echo "$line" | grep -Eq 'SAFEOP +\+ERR AL code 0x001B' || e2e_fail "expected SafeOp+ERR 0x001B after the outage"

# Link is back: a new master scans, configures and runs in Op cleanly.
e2e_live_phase "new master after link up, 1000 cycles" e2e_master_on_running_slave after 60 slave "$pid" \
  --cycles 1000 --expect-slaves 1 --move -q
kill -0 "$pid" 2> /dev/null || e2e_fail "ecat-slave died"
[ "$e2e_status" -eq 0 ] && echo "fault_link_down: OK"
exit "$e2e_status"
