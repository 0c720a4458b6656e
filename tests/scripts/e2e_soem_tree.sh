#!/usr/bin/env bash
# SOEM against the emulated tree (issue 16 item 6): ecat-slave --topology
# xml/topologies/tree.txt (coupler -> junction port 3 -> a1 -> a2, junction
# port 2 -> b1; every cable the segment's default 1000 ns) over a veth pair,
# SOEM 2.x slaveinfo on the master side. Its ecx_config_init and ecx_configdc
# compute each slave's active ports, the parent's port it hangs on and the
# propagation delay from DL status and the port receive times; they must be
# the tree's (docs/topology.md "SOEM on the tree"):
#   slave      Activeports  DCParentport  Delay
#   1 coupler  1.1.0.0      0             0
#   2 junction 1.0.1.1      1             1000
#   3 a1       1.1.0.0      3             2000
#   4 a2       1.0.0.0      1             3000
#   5 b1       1.0.0.0      2             6000 (1000 + round trip of a1-a2 4000 + 1000)
# SOEM is not a Debian package: binaries from $ECAT_SOEM_BIN or PATH; without
# slaveinfo the test is skipped (exit 77).
# Under load: as e2e_master_tree.sh, the delays do not depend on when the
# slave process runs; SOEM resends a frame the slave dropped as stale
# (2 ms each, 3 times for most of the scan). Any difference fails.
# Usage: e2e_soem_tree.sh SRCDIR BUILDDIR
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
# shellcheck source-path=SCRIPTDIR source=lib/netns.sh
. "$src/tests/scripts/lib/netns.sh"

if [ -n "${ECAT_SOEM_BIN:-}" ] && [ -x "$ECAT_SOEM_BIN/slaveinfo" ]; then
  slaveinfo=$ECAT_SOEM_BIN/slaveinfo
else
  slaveinfo=$(command -v slaveinfo 2> /dev/null) || { echo "skip: SOEM slaveinfo not found (set ECAT_SOEM_BIN=dir)"; exit 77; }
fi
e2e_require_bins ecat-slave
e2e_require_netns
e2e_setup st
# SCHED_FIFO where allowed, as every live script (lib/netns.sh): the slave
# must take its frames within --max-frame-age on a loaded host.
e2e_use_realtime

if ! e2e_start_slave tree "${E2E_SLAVE_RT[@]}" --topology "$src/xml/topologies/tree.txt"; then
  e2e_fail "slave did not start"
  exit $e2e_status
fi
timeout -s KILL 60 ip netns exec "$E2E_NS_M" "$slaveinfo" m0 2>&1 | tr '\r' '\n' > "$E2E_TMP/si.log"
sed 's/^/  [slaveinfo] /' "$E2E_TMP/si.log"
e2e_stop "$E2E_SLAVE_PID"

# One line per slave: number, active ports, parent port, delay.
summary=$(awk '/^Slave:/ {n=substr($0,7)} /^ Delay:/ {split($2,a,"["); d[n]=a[1]}
  /^ DCParentport:/ {p[n]=substr($1,14)} /^ Activeports:/ {act[n]=substr($1,13)}
  END {for (i = 1; i in act; i++) printf "%d %s %s %s\n", i, act[i], p[i], d[i]}' "$E2E_TMP/si.log")
echo "SOEM saw (slave activeports parentport delay):"
while IFS= read -r line; do echo "  $line"; done <<< "$summary"
want="1 1.1.0.0 0 0
2 1.0.1.1 1 1000
3 1.1.0.0 3 2000
4 1.0.0.0 1 3000
5 1.0.0.0 2 6000"
[ "$summary" = "$want" ] || e2e_fail "SOEM's topology differs from the tree; expected:
$want"

# (b) The same tree with a delay per cable and time inside each ESC
# (tests/data/topologies/tree-delays.txt; e2e_master_tree.sh (b) derives the
# same delays for the project's master): SOEM halves the round trips alike.
CJ=150 JA1=710 A1A2=520 JB1=930
PC=260 PJ=220 FJ=100 PS=340 FS=300
d_j=$((CJ + (PC + FJ) / 2))
d_a1=$((d_j + JA1 + (PJ + FS) / 2))
d_a2=$((d_a1 + A1A2 + (PS + PS) / 2))
d_b1=$((d_j + PJ + (2 * JA1 + PS + 2 * A1A2 + PS + FS) + JB1 + (FJ + PS) / 2))
if e2e_start_slave delays "${E2E_SLAVE_RT[@]}" --topology "$src/tests/data/topologies/tree-delays.txt"; then
  timeout -s KILL 60 ip netns exec "$E2E_NS_M" "$slaveinfo" m0 2>&1 | tr '\r' '\n' > "$E2E_TMP/si2.log"
  e2e_stop "$E2E_SLAVE_PID"
  delays=$(awk '/^Slave:/ {n=substr($0,7)} /^ Delay:/ {split($2,a,"["); d[n]=a[1]}
    END {for (i = 1; i in d; i++) printf "%s ", d[i]}' "$E2E_TMP/si2.log")
  echo "(b) SOEM's delays with cable and inner times: $delays"
  [ "$delays" = "0 $d_j $d_a1 $d_a2 $d_b1 " ] || e2e_fail "(b) expected 0 $d_j $d_a1 $d_a2 $d_b1"
else
  e2e_fail "(b) slave did not start"
fi
exit $e2e_status
