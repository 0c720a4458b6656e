#!/usr/bin/env bash
# The project's master against the emulated tree over a veth pair (issue 16):
# ecat-slave --topology xml/topologies/tree.txt (coupler -> junction port 3 ->
# a1 -> a2, junction port 2 -> b1; every cable the segment's default 1000 ns),
# ecat-master --scan --dc on the master side. From DL status and the latched
# port receive times the master must find each slave's parent, the parent's
# port, its active and entry ports, and the propagation delays of the tree
# (docs/topology.md "The project's master on the tree over veth"):
#   slave 1 coupler   parent master port 0  ports 0,1    delay 0
#   slave 2 junction  parent 1 port 1       ports 0,2,3  delay 1000  (C-J)
#   slave 3 a1        parent 2 port 3       ports 0,1    delay 2000  (+ J-a1)
#   slave 4 a2        parent 3 port 1       ports 0      delay 3000  (+ a1-a2)
#   slave 5 b1        parent 2 port 2       ports 0      delay 6000  (C-J + round trip a1-a2 4000 + J-b1)
# The delays are the cable sums (the ESCs forward without internal delay by
# default, docs/esc.md "Forwarding delays inside an ESC"), the same SOEM
# computes (e2e_soem_tree.sh). No AL state changes (--scan).
# (b) tests/data/topologies/tree-delays.txt, the same tree with a delay per
# cable and processing/forwarding times inside each ESC: the delays the
# master prints must be the ones derived from those numbers below.
# Under load: no live timing is involved. The delays come from the
# emulated ESCs' receive-time latches at each frame's kernel arrival stamp,
# not from when the slave process ran; a scan frame the slave drops as stale
# is retried by the master. Any difference in a line fails.
# Usage: e2e_master_tree.sh SRCDIR BUILDDIR   (exit 77 = skipped: not root / no netns)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
# shellcheck source-path=SCRIPTDIR source=lib/netns.sh
. "$src/tests/scripts/lib/netns.sh"
e2e_require_bins ecat-slave ecat-master
e2e_require_netns
e2e_setup mt
# SCHED_FIFO where allowed, as every live script (lib/netns.sh): the slave
# must take its frames within --max-frame-age on a loaded host.
e2e_use_realtime

if ! e2e_start_slave tree "${E2E_SLAVE_RT[@]}" --topology "$src/xml/topologies/tree.txt"; then
  e2e_fail "slave did not start"
  exit $e2e_status
fi
e2e_master scan 60 --scan --dc --expect-slaves 5 || e2e_fail "ecat-master --scan --dc exit $?"
e2e_stop "$E2E_SLAVE_PID"

got=$(grep '^slave [0-9]' "$E2E_TMP/scan.log")
want="slave 1 station 0x1001 parent master port 0 ports 0,1 entry 0 delay 0 ns
slave 2 station 0x1002 parent 1 port 1 ports 0,2,3 entry 0 delay 1000 ns
slave 3 station 0x1003 parent 2 port 3 ports 0,1 entry 0 delay 2000 ns
slave 4 station 0x1004 parent 3 port 1 ports 0 entry 0 delay 3000 ns
slave 5 station 0x1005 parent 2 port 2 ports 0 entry 0 delay 6000 ns"
[ "$got" = "$want" ] || e2e_fail "the master's topology differs from the tree; expected:
$want"

# (b) The same tree with a delay per cable and time inside each ESC
# (tests/data/topologies/tree-delays.txt: `cable NS`, `inner P F`). The master
# halves each round trip (it assumes a frame takes as long both ways,
# docs/esc.md "Forwarding delays inside an ESC"): a slave's delay is its
# parent's, plus the parent's earlier branches, plus the cable, plus half of
# the parent's inner time toward it (P out of the entry port, else F) and of
# its own back out of port 0 (F, or P at a branch end).
CJ=150 JA1=710 A1A2=520 JB1=930
PC=260 FC=140 PJ=220 FJ=100 PS=340 FS=300
d_j=$((CJ + (PC + FJ) / 2))
d_a1=$((d_j + JA1 + (PJ + FS) / 2))
d_a2=$((d_a1 + A1A2 + (PS + PS) / 2))
round_a=$((2 * JA1 + PS + 2 * A1A2 + PS + FS))   # junction port 3 out .. back in
d_b1=$((d_j + PJ + round_a + JB1 + (FJ + PS) / 2))
: "$FC"  # the coupler's forwarding time lies behind the last slave: in no delay
if e2e_start_slave delays "${E2E_SLAVE_RT[@]}" --topology "$src/tests/data/topologies/tree-delays.txt"; then
  e2e_master delaysm 60 --scan --dc --expect-slaves 5 || e2e_fail "(b) ecat-master --scan --dc exit $?"
  e2e_stop "$E2E_SLAVE_PID"
  got=$(grep '^slave [0-9]' "$E2E_TMP/delaysm.log" | sed 's/.* delay \([0-9]*\) ns$/\1/' | tr '\n' ' ')
  want="0 $d_j $d_a1 $d_a2 $d_b1 "
  [ "$got" = "$want" ] || e2e_fail "(b) delays $got, expected $want"
  echo "(b) delays from cables and inner times: $got"
else
  e2e_fail "(b) slave did not start"
fi
exit $e2e_status
