#!/usr/bin/env bash
# Fault: ecat-slave killed (SIGKILL) during a parameter store (issue 8 item
# 3). CiA 301 §7.5.2.13: writing "save" (0x65766173) to 1010h:01 stores the
# parameters; coe/parameter_store.hpp writes a temporary file, fsyncs and
# renames it, so a crash at any point leaves the previous set or the new one,
# never a mixture. Parameters: 6081h (profile velocity) and 6083h (profile
# acceleration), always written as a pair (v, v + 1000).
#  1. write a pair, save, stop (SIGTERM), restart: the pair is back (store works);
#  2. ROUNDS times: write a new pair, send "save" and SIGKILL the slave after a
#     random 0-20 ms (before, during or after the store), restart with the
#     same --state-dir: the slave starts and serves a consistent pair, the
#     one saved last or the new one (the new one whenever "save" was
#     acknowledged before the kill).
# Under load: nothing here is timed but the kill (any moment is a valid
# test); ecat-sdo retries a frame the slave drops as stale, as it retries
# any lost frame, so a slow host only slows it down.
# Tool: build/bin/ecat-sdo (tests/tools/ecat-sdo.cpp).
# Usage: fault_store_kill.sh SRCDIR BUILDDIR   (exit 77 = skipped)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
# shellcheck source-path=SCRIPTDIR source=lib/netns.sh
. "$src/tests/scripts/lib/netns.sh"
e2e_require_bins ecat-slave ecat-sdo
e2e_require_netns
rounds=${STORE_ROUNDS:-10}
e2e_setup k
# SCHED_FIFO where allowed, as every live script (lib/netns.sh): the slave
# must take its frames within --max-frame-age on a loaded host.
e2e_use_realtime
# ecat-slave drops root after opening its socket: the state directory (and
# the way to it) must be open to the unprivileged user.
chmod 0711 "$E2E_TMP"
state="$E2E_TMP/state"
mkdir -p "$state"
chmod 0777 "$state"
save=0x65766173

sdo() { timeout -s KILL 20 ip netns exec "$E2E_NS_M" "$build/bin/ecat-sdo" --iface m0 "$@"; }
# Reads the pair; prints "v a".
read_pair() {
  local out
  out=$(sdo r:6081:0 r:6083:0) || return 1
  echo "$out" | tr -d '()' | awk '/^6081:00/ {v=$4} /^6083:00/ {a=$4} END {print v+0, a+0}'
}

e2e_start_slave s0 "${E2E_SLAVE_RT[@]}" --state-dir "$state" || exit 1
sdo w:6081:0:4:111 w:6083:0:4:1111 w:1010:1:4:$save > /dev/null \
  || { e2e_fail "first store failed"; cat "$E2E_TMP/s0.log"; }
e2e_stop "$E2E_SLAVE_PID"
e2e_start_slave s1 "${E2E_SLAVE_RT[@]}" --state-dir "$state" || exit 1
pair=$(read_pair) || e2e_fail "cannot read the pair after a restart"
echo "after store + clean restart: 6081h/6083h = $pair"
[ "$pair" = "111 1111" ] || e2e_fail "stored parameters not restored: $pair (expected 111 1111)"
saved="111 1111"

for r in $(seq 1 "$rounds"); do
  pid=$(e2e_slave_program_pid "$E2E_SLAVE_PID")
  v=$(( 200 + r )); a=$(( v + 1000 ))
  sdo w:6081:0:4:$v w:6083:0:4:$a > /dev/null || { e2e_fail "round $r: write failed"; break; }
  sdo w:1010:1:4:$save > "$E2E_TMP/save.$r" 2>&1 &
  spid=$!
  sleep "0.0$(( RANDOM % 20 ))"
  kill -KILL "$pid"
  wait "$spid" 2> /dev/null; src_rc=$?
  wait "$E2E_SLAVE_PID" 2> /dev/null
  acked=no; grep -q '^1010:01 :=' "$E2E_TMP/save.$r" && acked=yes
  e2e_start_slave "r$r" "${E2E_SLAVE_RT[@]}" --state-dir "$state" || { e2e_fail "round $r: slave did not restart"; break; }
  pair=$(read_pair) || { e2e_fail "round $r: cannot read the pair after restart"; continue; }
  echo "round $r: save acknowledged=$acked (ecat-sdo exit $src_rc) -> restored $pair"
  if [ "$pair" = "$v $a" ]; then
    saved="$v $a"
  elif [ "$pair" = "$saved" ]; then
    [ "$acked" = no ] || e2e_fail "round $r: save acknowledged but the old set came back"
  else
    e2e_fail "round $r: restored $pair, neither the last saved ($saved) nor the new set ($v $a)"
  fi
  grep -i "warn\|ignored" "$E2E_TMP/r$r.log" && e2e_fail "round $r: the slave warned about its parameter file"
done
ls -la "$state" | sed 's/^/  [state dir] /'
[ "$e2e_status" -eq 0 ] && echo "fault_store_kill: OK"
exit "$e2e_status"
