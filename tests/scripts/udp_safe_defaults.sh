#!/usr/bin/env bash
# Issue 20: EtherCAT-in-UDP (ETG.1000.4 §5.3) has no authentication, so
# ecat-slave is safe by default on a network. In two network namespaces
# joined by a veth pair (slave side 192.0.2.1 / 2001:db8::1, master side
# 192.0.2.2 / 2001:db8::2):
#  1. `--udp PORT` binds 127.0.0.1 and ::1 only: a master on the same host
#     reaches Op over both, a master on the other end of the link gets no
#     answer, and the kernel lists no other address for the port;
#  2. an explicit wildcard address prints the one-line warning, and
#     `--udp-allow` serves the allowed peer only: the master on the link
#     (allowed) reaches Op, the local one (127.0.0.1, not allowed) gets no
#     answer; the drops are counted in the statistics (refused-source);
#     the same for IPv6 ([::]:PORT, allow 2001:db8::2/128);
#  3. a datagram whose EtherCAT length disagrees with its UDP length is
#     dropped and counted (length-mismatch), the slave still serves after it.
# Usage: udp_safe_defaults.sh SRCDIR BUILDDIR   (exit 77 = skipped)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
# shellcheck source-path=SCRIPTDIR source=lib/netns.sh
. "$src/tests/scripts/lib/netns.sh"
e2e_require_bins ecat-slave ecat-master
e2e_require_netns
e2e_setup u
port=34980
ip -n "$E2E_NS_S" addr add 192.0.2.1/24 dev s0
ip -n "$E2E_NS_M" addr add 192.0.2.2/24 dev m0
ip -n "$E2E_NS_S" addr add 2001:db8::1/64 dev s0 nodad
ip -n "$E2E_NS_M" addr add 2001:db8::2/64 dev m0 nodad

# Starts ecat-slave in the slave namespace with the given arguments; log NAME.
start_udp_slave() {
  local name=$1; shift
  timeout -s TERM 120 ip netns exec "$E2E_NS_S" "$build/bin/ecat-slave" "$@" > "$E2E_TMP/$name.log" 2>&1 &
  E2E_SLAVE_PID=$!
  E2E_PIDS+=("$E2E_SLAVE_PID")
  local _
  for _ in $(seq 1 100); do
    grep -q "slave(s) on" "$E2E_TMP/$name.log" 2> /dev/null && return 0
    kill -0 "$E2E_SLAVE_PID" 2> /dev/null || break
    sleep 0.05
  done
  echo "FAIL: ecat-slave did not start:"; cat "$E2E_TMP/$name.log"
  exit 1
}
# master NS NAME ENDPOINT: a short cyclic run; its exit code.
master() {
  local ns=$1 name=$2 ep=$3
  timeout -s KILL 30 ip netns exec "$ns" "$build/bin/ecat-master" --udp "$ep" --cycles 50 --expect-slaves 1 \
    > "$E2E_TMP/$name.log" 2>&1
  local rc=$?
  sed "s/^/  [$name] /" "$E2E_TMP/$name.log"
  return $rc
}
# The UDP statistics line ecat-slave printed at exit (log NAME), field FIELD.
udp_counter() { grep -m1 '^udp accepted' "$E2E_TMP/$1.log" | awk -v f="$2" '{for (i = 1; i < NF; i++) if ($i == f) print $(i + 1)}'; }

echo "== 1. --udp $port: loopback only"
start_udp_slave lo --udp "$port"
bound=$(ip netns exec "$E2E_NS_S" ss -Hunl "sport = :$port" | awk '{print $4}' | sort | tr '\n' ' ')
echo "bound: $bound"
[ "$bound" = "127.0.0.1:$port [::1]:$port " ] || e2e_fail "--udp $port bound '$bound', expected 127.0.0.1 and [::1] only"
master "$E2E_NS_S" lo-v4 "127.0.0.1:$port" || e2e_fail "local master over 127.0.0.1 did not run"
master "$E2E_NS_S" lo-v6 "[::1]:$port" || e2e_fail "local master over ::1 did not run"
master "$E2E_NS_M" link-v4 "192.0.2.1:$port" && e2e_fail "a master on the link reached the loopback-only slave"
master "$E2E_NS_M" link-v6 "[2001:db8::1]:$port" && e2e_fail "a master on the link reached the loopback-only slave (IPv6)"
grep -q "reachable unauthenticated" "$E2E_TMP/lo.log" && e2e_fail "warning printed for a loopback-only slave"
e2e_stop "$E2E_SLAVE_PID"

echo "== 2. --udp 0.0.0.0:$port --udp-allow 192.0.2.2/32"
start_udp_slave allow4 --udp "0.0.0.0:$port" --udp-allow 192.0.2.2/32
warn=$(grep -c "reachable unauthenticated" "$E2E_TMP/allow4.log")
[ "$warn" = 1 ] || e2e_fail "expected one warning line for 0.0.0.0, got $warn"
grep "reachable unauthenticated" "$E2E_TMP/allow4.log" | sed 's/^/  [allow4] /'
master "$E2E_NS_M" allowed-v4 "192.0.2.1:$port" || e2e_fail "the allowed master (192.0.2.2) did not run"
master "$E2E_NS_S" refused-v4 "127.0.0.1:$port" && e2e_fail "a source outside --udp-allow was served"
e2e_stop "$E2E_SLAVE_PID"
grep '^udp accepted' "$E2E_TMP/allow4.log" | sed 's/^/  [allow4 at exit] /'
refused=$(udp_counter allow4 refused-source)
[ "${refused:-0}" -gt 0 ] || e2e_fail "refused datagrams not counted (refused-source '$refused')"

echo "== 2b. --udp [::]:$port --udp-allow 2001:db8::2/128"
start_udp_slave allow6 --udp "[::]:$port" --udp-allow 2001:db8::2/128
master "$E2E_NS_M" allowed-v6 "[2001:db8::1]:$port" || e2e_fail "the allowed master (2001:db8::2) did not run"
master "$E2E_NS_S" refused-v6 "[::1]:$port" && e2e_fail "::1 outside --udp-allow was served"
master "$E2E_NS_M" refused-v4-on-v6 "192.0.2.1:$port" && e2e_fail "192.0.2.2 outside an IPv6-only --udp-allow was served"
e2e_stop "$E2E_SLAVE_PID"
refused=$(udp_counter allow6 refused-source)
[ "${refused:-0}" -gt 0 ] || e2e_fail "refused IPv6 datagrams not counted (refused-source '$refused')"

echo "== 3. length mismatch"
start_udp_slave len --udp "$port"
# EtherCAT header 0x100E (14 bytes follow) + BRD 0x0000 len 2 + IRQ + data + WKC, plus one stray byte.
ip netns exec "$E2E_NS_S" bash -c \
  "printf '\x0e\x10\x07\x01\x00\x00\x00\x00\x02\x00\x00\x00\x00\x00\x00\x00\xee' > /dev/udp/127.0.0.1/$port" \
  || e2e_fail "could not send the datagram"
master "$E2E_NS_S" after-mismatch "127.0.0.1:$port" || e2e_fail "slave did not serve after a dropped datagram"
e2e_stop "$E2E_SLAVE_PID"
grep '^udp accepted' "$E2E_TMP/len.log" | sed 's/^/  [len at exit] /'
[ "$(udp_counter len length-mismatch)" = 1 ] || e2e_fail "length mismatch not counted once"

[ "$e2e_status" -eq 0 ] && echo "udp_safe_defaults: OK"
exit "$e2e_status"
