#!/usr/bin/env bash
# Ethernet over EtherCAT through an independent master (issue 31 item 1):
# SOEM's eoe_test sample (SOEM 2.x) brings a twin of the Elmo Gold drive (its
# vendor ESI announces EoE) to Op over a veth pair and bridges its own TAP
# tap0 to the slave's EoE port; ecat-slave's built-in responder answers ARP
# and ICMP echo for --eoe-ip. From the master's namespace, ping through tap0
# must be answered: 3 echoes of 56 bytes (one mailbox fragment each way) and
# 2 of 1400 bytes (a frame of 1442 bytes: several fragments each way at the
# drive's mailbox size), every one answered. What it proves: SOEM's EoE
# fragmentation and reassembly and ecat-slave's agree byte for byte (a wrong
# offset, fragment number or checksum loses the echo), with CoE and process
# data on the same mailbox and cycle.
# SOEM is not a Debian package: eoe_test is taken from $ECAT_SOEM_BIN (a
# directory) or PATH; without it, or without ping, the test is skipped (77).
# Usage: e2e_soem_eoe.sh SRCDIR BUILDDIR
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
# shellcheck source-path=SCRIPTDIR source=lib/netns.sh
. "$src/tests/scripts/lib/netns.sh"
if [ -n "${ECAT_SOEM_BIN:-}" ] && [ -x "$ECAT_SOEM_BIN/eoe_test" ]; then
  eoe_test=$ECAT_SOEM_BIN/eoe_test
else
  eoe_test=$(command -v eoe_test 2> /dev/null) || { echo "skip: SOEM eoe_test not found (set ECAT_SOEM_BIN=dir)"; exit 77; }
fi
command -v ping > /dev/null || { echo "skip: ping not installed (iputils-ping)"; exit 77; }
[ -c /dev/net/tun ] || { echo "skip: no /dev/net/tun for SOEM's TAP"; exit 77; }
e2e_require_bins ecat-slave
e2e_require_netns
e2e_setup eoe
e2e_use_realtime

slave_ip=192.168.99.2
e2e_start_slave eoe_slave "${E2E_SLAVE_RT[@]}" --esi "$src/tests/data/esi-vendor/elmo-gold-ecat.xml" \
  --eoe-ip "$slave_ip" || exit 1
ip netns exec "$E2E_NS_M" "${E2E_MASTER_RT[@]}" "$eoe_test" m0 1 > "$E2E_TMP/eoe_master.log" 2>&1 &
mpid=$!
E2E_PIDS+=("$mpid")
for _ in $(seq 1 200); do
  grep -q "Operational state reached" "$E2E_TMP/eoe_master.log" && break
  kill -0 "$mpid" 2> /dev/null || break
  sleep 0.1
done
tr '\r' '\n' < "$E2E_TMP/eoe_master.log" | grep -v '^Processdata' | sed 's/^/  [eoe_test] /'
if ! grep -q "Operational state reached" "$E2E_TMP/eoe_master.log"; then
  e2e_fail "eoe_test did not reach Op"
  exit 1
fi
ip -n "$E2E_NS_M" addr add 192.168.99.1/24 dev tap0 && ip -n "$E2E_NS_M" link set tap0 up \
  || { e2e_fail "tap0 of eoe_test not found"; exit 1; }
# 56 bytes: one fragment each way; 1400: several (the drive's mailbox is smaller).
for size in 56 1400; do
  count=$([ "$size" = 56 ] && echo 3 || echo 2)
  out=$(ip netns exec "$E2E_NS_M" ping -c "$count" -s "$size" -W 3 -i 0.3 "$slave_ip" 2>&1)
  echo "$out" | sed 's/^/  [ping] /'
  grep -q "$count packets transmitted, $count received" <<< "$out" \
    || e2e_fail "ping -s $size: not every echo answered through EoE"
done
kill "$mpid" 2> /dev/null
e2e_stop "$E2E_SLAVE_PID"
grep -q "^frames " "$E2E_TMP/eoe_slave.log" && sed -n '/^frames /,$p' "$E2E_TMP/eoe_slave.log" | sed 's/^/  [slave] /'
[ "$e2e_status" -eq 0 ] && echo "e2e_soem_eoe: ok"
exit "$e2e_status"
