#!/usr/bin/env bash
# The master side of cable redundancy and the topology print over raw sockets
# (issue 16 items 4 and 6, master part; docs/master.md "Cable redundancy").
# Two veth pairs: s0/m0 as in every e2e script, and s1/m1 for the ring's
# return to the master's second port.
#  (a) ecat-master --scan --topology: one line per slave of a chain of 3,
#      parents and ports of a line.
#  (b) ecat-master --iface m0 --redundant-iface m1, 500 cycles at 1 ms:
#      when ecat-slave has --redundant-iface (the ring of the emulated segment)
#      the ring must be found intact; without it nothing comes back on m1 and
#      the master must find "secondary link down" and still lose no cycle.
#  (c) with --redundant-iface on the slave side: a ring of 4, 3000 cycles at
#      1 ms; after ~1 s SIGUSR2 makes ecat-slave cut the cable on slave 2's
#      port 1 (--toggle-link 2:1); the master must lose no cycle, see no WKC
#      error, and end with "ring broken between slave 2 and slave 3".
# Usage: e2e_redundancy.sh SRCDIR BUILDDIR   (exit 77 = skipped: not root / no netns)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
# shellcheck source-path=SCRIPTDIR source=lib/netns.sh
. "$src/tests/scripts/lib/netns.sh"
e2e_require_bins ecat-slave ecat-master
e2e_require_netns
e2e_setup r
ip link add s1 netns "$E2E_NS_S" type veth peer name m1 netns "$E2E_NS_M" || { echo "FAIL: veth s1/m1"; exit 1; }
ip -n "$E2E_NS_S" link set s1 up && ip -n "$E2E_NS_M" link set m1 up || { echo "FAIL: link up s1/m1"; exit 1; }

ring_args=()
want_ring="secondary link down"
if "$build/bin/ecat-slave" --help 2> /dev/null | grep -q -- '--redundant-iface'; then
  ring_args=(--redundant-iface s1)
  want_ring="ring intact"
fi

# (a) topology of a line of three.
if e2e_start_slave topo --count 3; then
  e2e_master topo 30 --scan --expect-slaves 3 || e2e_fail "(a) ecat-master --scan exit $?"
  grep -q '^slave 1 station 0x1001 parent master port 0 ports 0,1 entry 0$' "$E2E_TMP/topo.log" \
    || e2e_fail "(a) slave 1 line"
  grep -q '^slave 2 station 0x1002 parent 1 port 1 ports 0,1 entry 0$' "$E2E_TMP/topo.log" \
    || e2e_fail "(a) slave 2 line"
  grep -q '^slave 3 station 0x1003 parent 2 port 1 ports 0 entry 0$' "$E2E_TMP/topo.log" \
    || e2e_fail "(a) slave 3 line"
  e2e_stop "$E2E_SLAVE_PID"
else
  e2e_fail "(a) slave did not start"
fi

# (b) two master ports.
if e2e_start_slave ring --count 3 "${ring_args[@]}"; then
  e2e_master ring 60 --redundant-iface m1 --cycles 500 --period-us 1000 --expect-slaves 3 \
    || e2e_fail "(b) ecat-master --redundant-iface exit $?"
  grep -q "^redundancy: $want_ring" "$E2E_TMP/ring.log" || e2e_fail "(b) expected \"$want_ring\""
  echo "(b) ${ring_args[*]:-no ring on the slave side}: $(grep -m1 '^redundancy:' "$E2E_TMP/ring.log")"
  e2e_stop "$E2E_SLAVE_PID"
else
  e2e_fail "(b) slave did not start"
fi

# (c) a cut in the ring during the cyclic run.
if [ ${#ring_args[@]} -eq 0 ]; then
  echo "(c) skipped: ecat-slave has no --redundant-iface"
elif e2e_start_slave cut --count 4 "${ring_args[@]}" --toggle-link 2:1; then
  pid=$(e2e_slave_program_pid "$E2E_SLAVE_PID")
  timeout -s KILL 60 ip netns exec "$E2E_NS_M" "$build/bin/ecat-master" --iface m0 --redundant-iface m1 \
    --cycles 3000 --period-us 1000 --expect-slaves 4 > "$E2E_TMP/cutm.log" 2>&1 &
  mpid=$!
  sleep 1.5
  kill -USR2 "$pid" || e2e_fail "(c) SIGUSR2"
  wait "$mpid"; rc=$?
  sed 's/^/  [cut] /' "$E2E_TMP/cutm.log"
  [ "$rc" -eq 0 ] || e2e_fail "(c) ecat-master exit $rc"
  grep -q 'link(s) cut' "$E2E_TMP/cut.log" || e2e_fail "(c) ecat-slave did not cut the link"
  grep -Eq '^cycles 3000 lost 0 wkc-errors 0 ' "$E2E_TMP/cutm.log" || e2e_fail "(c) lost cycles or WKC errors"
  grep -Eq '^redundancy: ring broken between slave 2 and slave 3 \(exchanges: intact [1-9][0-9]* broken [1-9]' \
    "$E2E_TMP/cutm.log" || e2e_fail "(c) break not reported between slave 2 and slave 3"
  e2e_stop "$E2E_SLAVE_PID"
else
  e2e_fail "(c) slave did not start"
fi

exit $e2e_status
