#!/usr/bin/env bash
# The example scenarios (examples/scenarios/, docs/scenarios.md "SOEM") run
# by ecat-slave --scenario against SOEM's sample programs, an independent
# open-source master, over a veth pair between two network namespaces (the
# mechanism of e2e_soem.sh: SOEM is built outside the repository and found in
# $ECAT_SOEM_BIN or on PATH; docs/e2e.md).
# A scenario file says which SOEM program meets its expectations on a line
# "# soem: PROGRAM..." (each named program is run against it in turn; a
# missing one is reported and skipped). Where SOEM's samples do something
# else than ecat-master - they never write a controlword, so they reset no
# drive fault; they read the AL status only when a cycle's WKC is short;
# they fall back to the SII's PDO map when the CoE answer never comes - the
# expectations for SOEM are in a file of their own under
# examples/scenarios/soem/, and the ecat-master file points to it with
# "# soem-variant: FILE"; a scenario SOEM cannot be judged on says why with
# "# soem-skip: REASON". Every example must have one of the three lines.
# What it proves: each scenario run passes (ecat-slave exits 0, its JUnit
# report has failures="0"), and every example states what SOEM does with it.
# Usage: e2e_soem_scenarios.sh SRCDIR BUILDDIR   (exit 77 = skipped)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
# shellcheck source-path=SCRIPTDIR source=lib/netns.sh
. "$src/tests/scripts/lib/netns.sh"

soem_find() {
  if [ -n "${ECAT_SOEM_BIN:-}" ] && [ -x "$ECAT_SOEM_BIN/$1" ]; then
    echo "$ECAT_SOEM_BIN/$1"
  else
    command -v "$1" 2> /dev/null
  fi
}

# Each example names what SOEM does with it (checked without SOEM too, so
# a new example cannot forget it; but the run needs root and SOEM).
failures=0
files=("$src"/examples/scenarios/*.yaml "$src"/examples/scenarios/soem/*.yaml)
for file in "${files[@]}"; do
  rel=${file#"$src"/examples/scenarios/}
  if ! grep -qE '^# soem(-variant|-skip)?: ' "$file"; then
    echo "FAIL: $rel: no '# soem:', '# soem-variant:' or '# soem-skip:' line"
    failures=$((failures + 1))
  fi
  variant=$(sed -n 's/^# soem-variant: //p' "$file" | head -1)
  if [ -n "$variant" ] && [ ! -f "$src/examples/scenarios/$variant" ]; then
    echo "FAIL: $rel: its SOEM variant $variant does not exist"
    failures=$((failures + 1))
  fi
done
[ "$failures" -eq 0 ] || exit 1

any=""
for p in ec_sample simple_ng; do soem_find "$p" > /dev/null && any=1; done
[ -n "$any" ] || { echo "skip: neither SOEM ec_sample nor simple_ng found (set ECAT_SOEM_BIN=dir)"; exit 77; }
e2e_require_bins ecat-slave
e2e_require_netns
e2e_setup sc
# As in e2e_soem.sh: SOEM gives a frame 2 ms and a mailbox reply 700 ms;
# where SCHED_FIFO is allowed the slave runs at 40 and SOEM at 30.
slave_rt=()
master_rt=()
if [ -z "${E2E_SOEM_NO_RT:-}" ] && chrt -f 40 true 2> /dev/null; then
  slave_rt=(--rt-priority 40)
  master_rt=(chrt -f 30)
fi

# run_one NAME FILE PROGRAM SLAVE_ARGS...: the scenario on the slave, the
# SOEM program on m0 until the scenario is over (then stopped: ec_sample
# runs 100 s, simple_ng 10000 x 5 ms); the slave's exit status in $rc.
run_one() {
  local name=$1 file=$2 prog=$3
  shift 3
  if ! e2e_start_slave "$name" "${slave_rt[@]}" "$@" --scenario "$file" --junit "$E2E_TMP/$name.xml"; then
    rc=1
    return
  fi
  local spid=$E2E_SLAVE_PID
  # stdbuf: SOEM's samples print to a pipe; line-buffered, the lines before
  # the stop are kept.
  timeout -s KILL 150 ip netns exec "$E2E_NS_M" "${master_rt[@]}" stdbuf -oL "$prog" m0 2>&1 |
    tr '\r' '\n' > "$E2E_TMP/$name.soem.log" &
  local mpid=$!
  wait "$spid"
  rc=$?
  # The namespace holds only the SOEM program: stop it there (TERM, it
  # prints nothing more), then the pipe ends.
  ip netns pids "$E2E_NS_M" | xargs -r kill -TERM 2> /dev/null
  timeout 10 tail --pid="$mpid" -f /dev/null 2> /dev/null
  ip netns pids "$E2E_NS_M" | xargs -r kill -KILL 2> /dev/null
  wait "$mpid" 2> /dev/null
}

ran=0
for file in "${files[@]}"; do
  rel=${file#"$src"/examples/scenarios/}
  name=$(basename "$file" .yaml)
  progs=$(sed -n 's/^# soem: //p' "$file" | head -1)
  if [ -z "$progs" ]; then
    variant=$(sed -n 's/^# soem-variant: //p' "$file" | head -1)
    if [ -n "$variant" ]; then
      echo "$rel: SOEM runs $variant instead"
    else
      echo "$rel: not for SOEM: $(sed -n 's/^# soem-skip: //p' "$file" | head -1)"
    fi
    continue
  fi
  read -r -a slave_args <<< "$(sed -n 's/^# slave: //p' "$file" | head -1)"
  for p in $progs; do
    prog=$(soem_find "$p") || { echo "$rel: SOEM $p not found, not run"; continue; }
    run_one "${name}_$p" "$file" "$prog" "${slave_args[@]}"
    ran=$((ran + 1))
    echo "$rel with SOEM $p:"
    sed -n '/^  \(PASS\|FAIL\|SKIP\)/p;/^scenario /p' "$E2E_TMP/${name}_$p.log" | cut -c1-240
    grep -E '^(ERROR|WARNING|MESSAGE|OK) : |^\* Slave|^\* All|All slaves resumed' "$E2E_TMP/${name}_$p.soem.log" | sed "s/^/  [$p] /" | head -20
    if [ "$rc" -ne 0 ] || ! grep -q 'failures="0"' "$E2E_TMP/${name}_$p.xml" 2> /dev/null; then
      e2e_fail "$rel with SOEM $p: ecat-slave exit $rc (0 expected); its log and SOEM's:"
      cat "$E2E_TMP/${name}_$p.log"
      grep -vE '^(Processdata cycle|Iteration)' "$E2E_TMP/${name}_$p.soem.log" | tail -n 40
    fi
  done
done
[ "$ran" -gt 0 ] || { echo "skip: no scenario's SOEM program was found"; exit 77; }
[ "$e2e_status" -eq 0 ] && echo "e2e_soem_scenarios: all $ran runs passed"
exit "$e2e_status"
