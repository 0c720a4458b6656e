#!/usr/bin/env bash
# Fault: an interface other than the named one is never answered (issue 8
# item 3; issue 5: "AF_PACKET on the named interface only"). The slave
# namespace has two veth ends, s0 (named: --iface s0) and s1; the master
# namespace has their peers m0 and m1. A master on m1 must find no slave
# (its scan fails and ecat-slave counts no frame); a master on m0 then finds
# the slave and runs in Op, so the test can tell a dead slave from a deaf
# second port.
# Under load (lib/netns.sh "Live timing under load"): a master run that must
# succeed may, when the host stalled master or slave, lose the frames the
# slave dropped as stale or see the slave leave Op with 001Bh; such a run is
# run again (up to E2E_LIVE_ATTEMPTS) and passes with a NOTE when every
# attempt was late. A wrong WKC, another AL code or a loss the slave did not
# drop fail at once.
# Usage: fault_other_iface.sh SRCDIR BUILDDIR   (exit 77 = skipped)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
# shellcheck source-path=SCRIPTDIR source=lib/netns.sh
. "$src/tests/scripts/lib/netns.sh"
e2e_require_bins ecat-slave ecat-master
e2e_require_netns
e2e_setup i
# SCHED_FIFO where allowed, as every live script (lib/netns.sh): the slave
# must take its frames within --max-frame-age on a loaded host.
e2e_use_realtime
ip link add s1 netns "$E2E_NS_S" type veth peer name m1 netns "$E2E_NS_M" || { echo "FAIL: second veth"; exit 1; }
ip -n "$E2E_NS_S" link set s1 up && ip -n "$E2E_NS_M" link set m1 up || { echo "FAIL: link up"; exit 1; }

e2e_start_slave slave "${E2E_SLAVE_RT[@]}" || exit 1
pid=$(e2e_slave_program_pid "$E2E_SLAVE_PID")

timeout -s KILL 60 ip netns exec "$E2E_NS_M" "$build/bin/ecat-master" --iface m1 --cycles 10 -q \
  > "$E2E_TMP/other.log" 2>&1
rc=$?
sed 's/^/  [other] /' "$E2E_TMP/other.log"
[ "$rc" -eq 1 ] || e2e_fail "a master on the other interface got exit $rc (expected 1: no slave found)"
kill -USR1 "$pid"; sleep 0.3
stats=$(grep '^frames ' "$E2E_TMP/slave.log" | tail -1)
echo "ecat-slave after the master on m1: $stats"
grep -q '^frames 0 returned 0 ' <<< "$stats" || e2e_fail "ecat-slave processed frames from the other interface"

e2e_live_phase "master on the named interface, 200 cycles" e2e_master_on_running_slave named 60 slave "$pid" \
  --cycles 200 --expect-slaves 1 -q
[ "$e2e_status" -eq 0 ] && echo "fault_other_iface: OK"
exit "$e2e_status"
