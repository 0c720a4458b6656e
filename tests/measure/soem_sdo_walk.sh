#!/usr/bin/env bash
# SOEM 2.x `slaveinfo -sdo` (the SDO-information walk: object list, every
# object's description, every entry's description and value) on every device
# file of xml/devices, SDO_WALK_RUNS times each (default 10), one ecat-slave
# per device over the veth pair of lib/netns.sh (issue 29 item 4, docs/e2e.md
# "Stale frames"). Run it beside CPU burners (e.g. `stress-ng --cpu 2`) to
# show that a slave the host stalls drops the frames SOEM gave up on
# (--max-frame-age) instead of answering them late, and SOEM's walk keeps
# its way: the only SOEM error allowed is 06090011h (subindex does not
# exist, the gaps of 1C32h/1C33h). A measurement, not a ctest test: it takes
# minutes. SOEM binaries from $ECAT_SOEM_BIN (as e2e_soem.sh); the slave and
# SOEM run at SCHED_FIFO 40/30 as in e2e_soem.sh unless SDO_WALK_NO_RT=1.
# SDO_WALK_SLAVE_ARGS adds ecat-slave options (e.g. "--max-frame-age 0" to
# see the walk without the stale-frame drop); SDO_WALK_DEVICES a file name
# pattern without .xml (default all). Logs kept in SDO_WALK_OUT.
# Prints one line per run and a summary; exit 1 if any run had another error.
# Usage: soem_sdo_walk.sh SRCDIR BUILDDIR
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
# shellcheck source-path=SCRIPTDIR source=../scripts/lib/netns.sh
. "$src/tests/scripts/lib/netns.sh"
slaveinfo=${ECAT_SOEM_BIN:-}/slaveinfo
[ -x "$slaveinfo" ] || { echo "skip: set ECAT_SOEM_BIN to a directory with SOEM's slaveinfo"; exit 77; }
runs=${SDO_WALK_RUNS:-10}
out=${SDO_WALK_OUT:-$(mktemp -d /tmp/soem_sdo_walk.XXXXXX)}
mkdir -p "$out"
read -r -a extra <<< "${SDO_WALK_SLAVE_ARGS:-}"
e2e_require_bins ecat-slave
e2e_require_netns
e2e_setup sw
slave_rt=()
master_rt=()
if [ -z "${SDO_WALK_NO_RT:-}" ] && chrt -f 40 true 2> /dev/null; then slave_rt=(--rt-priority 40); master_rt=(chrt -f 30); fi
echo "soem_sdo_walk: $runs runs per device, start $(date -u +%H:%M:%S) UTC, load $(cut -d' ' -f1-3 /proc/loadavg)," \
  "slave ${slave_rt[*]:-without RT} ${extra[*]}"
total_bad=0
total_runs=0
for dev in "$src"/xml/devices/${SDO_WALK_DEVICES:-*}.xml; do
  base=$(basename "$dev" .xml)
  if ! e2e_start_slave "$base" "${slave_rt[@]}" "${extra[@]}" --device "$dev"; then
    e2e_fail "$base: slave did not start"
    continue
  fi
  for r in $(seq 1 "$runs"); do
    log="$out/$base.$r.log"
    timeout -s KILL 300 ip netns exec "$E2E_NS_M" "${master_rt[@]}" "$slaveinfo" m0 -sdo 2>&1 | tr '\r' '\n' > "$log"
    rc=${PIPESTATUS[0]}
    objects=$(grep -cE '^0x[0-9a-f]{4} +"' "$log")
    entries=$(grep -cE '^    0x[0-9a-f]{2} +"' "$log")
    gaps=$(grep -c ' error:06090011 ' "$log")
    bad=$(grep -E ' (SDO|PACKET|MBX|EMERGENCY) slave:' "$log" | grep -vc ' error:06090011 ')
    found=$(sed -n 's/^ CoE Object Description found, \([0-9]*\) entries\.$/\1/p' "$log" | head -1)
    total_runs=$((total_runs + 1))
    if [ "$rc" -ne 0 ] || [ "$bad" -ne 0 ] || ! grep -q '^1 slaves found and configured\.$' "$log"; then
      total_bad=$((total_bad + 1))
      e2e_fail "$base run $r: slaveinfo exit $rc, $bad errors other than 06090011h: $(grep -E ' (SDO|PACKET|MBX|EMERGENCY) slave:' "$log" | grep -v ' error:06090011 ' | head -2 | tr '\n' ' ')"
    fi
    echo "$base run $r: exit $rc, object list ${found:-none}, $objects objects, $entries entries, $gaps gaps (06090011h), $bad other errors"
  done
  e2e_stop "$E2E_SLAVE_PID"
  cp "$E2E_TMP/$base.log" "$out/$base.slave.log"
  echo "$base slave at exit: $(grep -m1 '^frames ' "$E2E_TMP/$base.log")"
done
echo "soem_sdo_walk: $total_runs runs, $total_bad with an error other than 06090011h; end $(date -u +%H:%M:%S) UTC, load $(cut -d' ' -f1-3 /proc/loadavg); logs in $out"
exit "$e2e_status"
