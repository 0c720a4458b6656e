#!/usr/bin/env bash
# Fault: a cable that corrupts frames (issue 16, error counters). ecat-slave
# --count 3 --corrupt-link 1:1 --corrupt-frames 5: after ~1 s of a master's
# cyclic run a SIGUSR2 makes the cable between slave 1 (port 1) and slave 2
# corrupt its next 5 frames. Those frames are lost to the master (a bad FCS
# is never sent back), exactly 5: ecat-slave's statistics must show "lost 5"
# and its log the armed fault; the master must end (bounded) and see at least
# one lost cycle. The register values the ESCs count are asserted in
# tests/esc/esc_error_counter_test.cpp and tests/slave/error_localisation_test.cpp.
# Under load: nothing here needs the host on time. The 5 corrupted frames
# are counted where the chain passes frames, so frames the slave drops as
# stale (older than --max-frame-age: lost on the wire, counted apart as
# stale-dropped) neither use them up nor add to "lost"; the master only has
# to see at least one lost cycle, and it sees those 5.
# Usage: fault_corrupt_link.sh SRCDIR BUILDDIR   (exit 77 = skipped: not root / no netns)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
# shellcheck source-path=SCRIPTDIR source=lib/netns.sh
. "$src/tests/scripts/lib/netns.sh"
e2e_require_bins ecat-slave ecat-master
e2e_require_netns
e2e_setup cl
# SCHED_FIFO where allowed, as every live script (lib/netns.sh): the slave
# must take its frames within --max-frame-age on a loaded host.
e2e_use_realtime

e2e_start_slave slave "${E2E_SLAVE_RT[@]}" --count 3 --corrupt-link 1:1 --corrupt-frames 5 || exit 1
pid=$(e2e_slave_program_pid "$E2E_SLAVE_PID")
timeout -s KILL 60 ip netns exec "$E2E_NS_M" "$build/bin/ecat-master" --iface m0 --cycles 2000 --period-us 1000 \
  --expect-slaves 3 > "$E2E_TMP/master.log" 2>&1 &
mpid=$!
sleep 1.2
kill -USR2 "$pid" || e2e_fail "SIGUSR2"
wait "$mpid"
sed 's/^/  [master] /' "$E2E_TMP/master.log"
e2e_stop "$E2E_SLAVE_PID"
sed 's/^/  [slave] /' "$E2E_TMP/slave.log"
grep -q 'ecat-slave: 1 link(s) corrupt their next 5 frame(s)' "$E2E_TMP/slave.log" || e2e_fail "fault not armed"
grep -Eq '^frames [0-9]+ returned [0-9]+ malformed 0 lost 5 ' "$E2E_TMP/slave.log" || e2e_fail "expected exactly 5 frames lost"
grep -Eq '^cycles 2000 lost [1-9]' "$E2E_TMP/master.log" || e2e_fail "the master saw no lost cycle"
exit $e2e_status
