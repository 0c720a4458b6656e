#!/usr/bin/env bash
# The example scenarios (examples/scenarios/*.yaml, docs/scenarios.md) run by
# ecat-slave --scenario against ecat-master over UDP on loopback (no root):
# each file names the master's arguments on a line "# master: ARGS", and may
# name more of the slave's ("# slave: ARGS"), the master's exit status when it
# is not 0 ("# master-exit: N") and a line the master must print ("#
# master-output: TEXT"); a file with "# transport: redundant" needs a ring
# over raw interfaces and is run by e2e_redundancy instead. What it proves: each scenario passes (ecat-slave
# exits 0) and writes a JUnit report with failures="0", and the master ended
# as the file says; and a scenario whose expectation the master cannot meet
# (a request for Bootstrap) fails: exit 3, its step FAIL with the reason, the
# next SKIP, JUnit failures="1". The windows in the examples leave room for a
# loaded host; exact timing is proven in simulated time (test_scenario).
# Usage: e2e_scenarios.sh SRCDIR BUILDDIR   (exit 77 = skipped)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
slave=$build/bin/ecat-slave
master=$build/bin/ecat-master
[ -x "$slave" ] && [ -x "$master" ] || { echo "skip: ecat-slave/ecat-master not built"; exit 77; }
# SCHED_FIFO where the kernel allows it, as every live script (lib/netns.sh,
# docs/e2e.md): without it, on a host busy with builds, the slave took a
# scan's four frames each later than --max-frame-age, dropped them as lost on
# the wire, and the master gave up ("scan: no reply") before the first step.
# shellcheck source-path=SCRIPTDIR source=lib/netns.sh
. "$src/tests/scripts/lib/netns.sh"
e2e_use_realtime
work=$(mktemp -d /tmp/e2e_scenarios.XXXXXX)
trap 'kill $(jobs -p) 2>/dev/null; rm -rf "$work"' EXIT
E2E_TMP=$work  # the lib's log helpers take names in this folder
port=$((40000 + $$ % 20000))
failures=0

# run NAME FILE MASTER_ARGS...: the slave's exit status in $rc, the master's
# in $mrc (when it still ran at the end, it is stopped with SIGTERM, prints
# its statistics and exits 0, or 1 after a lost frame, WKC or state error), their output in
# $work/NAME.log and $work/NAME.master.log; the slave's own arguments in the
# array slave_args.
slave_args=()
run() {
  local name=$1 file=$2
  shift 2
  port=$((port + 1))
  "$slave" --udp "$port" "${E2E_SLAVE_RT[@]}" "${slave_args[@]}" --scenario "$file" --junit "$work/$name.xml" > "$work/$name.log" 2>&1 &
  local spid=$!
  sleep 0.3
  timeout 120 "${E2E_MASTER_RT[@]}" "$master" --udp "127.0.0.1:$port" -q "$@" > "$work/$name.master.log" 2>&1 &
  local mpid=$!
  wait "$spid"
  rc=$?
  kill "$mpid" 2> /dev/null
  wait "$mpid" 2> /dev/null
  mrc=$?
}

# check NAME: whether the run just made passed; the reason in $why when not.
check() {
  local name=$1
  why=""
  if [ "$rc" -ne 0 ] || ! grep -q 'failures="0"' "$work/$name.xml" 2> /dev/null; then
    why="ecat-slave exit $rc (0 expected): $(grep -m1 '^  FAIL' "$work/$name.log")"
  elif [ -n "$master_exit" ] && [ "$mrc" != "$master_exit" ]; then
    why="ecat-master exit $mrc ($master_exit expected)"
  elif [ -n "$master_output" ] && ! grep -qF -- "$master_output" "$work/$name.master.log"; then
    why="ecat-master did not print '$master_output'"
  elif [ -z "$master_exit" ] && ! { grep -q '^ecat-master: stopped by a signal after ' "$work/$name.master.log" &&
    grep -q '^cycles ' "$work/$name.master.log"; }; then
    # Still cycling when the scenario ended: SIGTERM ends its run with the statistics.
    why="ecat-master, stopped by SIGTERM, did not print its statistics"
  fi
  [ -z "$why" ]
}

# late NAME: the evidence that master or slave was held up in the run just
# made (lib/netns.sh "Live timing under load"), in $evidence; false if none.
late() {
  local name=$1 stale
  stale=$(e2e_slave_stale "$name")
  evidence=""
  if e2e_master_was_late "$name.master" "$period_us"; then
    evidence="master: $(grep -m1 -oE '(cycle-jitter-max-us|start-up-cycle-gap-max-us) [0-9.]+' "$work/$name.master.log")"
  fi
  [ "$stale" -gt 0 ] && evidence="${evidence:+$evidence, }slave stale-dropped $stale"
  [ -n "$evidence" ]
}

# Each scenario is run up to E2E_LIVE_ATTEMPTS times: a failed run is run
# again only when master or slave was late in it (a busy host, as in every
# live script); a failure without that evidence fails at once. Unlike the
# other live scripts, a scenario that failed in every attempt fails even when
# each was late: that evidence is weak here (on the 2-vCPU VM an idle run
# shows cycle-jitter-max-us of 1-4 ms and a few stale frames at start-up),
# and a scenario's failure is not judged by kind (an allowed AL code, a WKC),
# so only a pass shows nothing was wrong.
for file in "$src"/examples/scenarios/*.yaml; do
  name=$(basename "$file" .yaml)
  if grep -q '^# transport: redundant' "$file"; then
    echo "$name: needs two raw master ports (run by e2e_redundancy)"
    continue
  fi
  args=$(sed -n 's/^# master: //p' "$file" | head -1)
  [ -n "$args" ] || { echo "FAIL: $name: no '# master: ARGS' line"; failures=$((failures + 1)); continue; }
  read -r -a argv <<< "$args"
  period_us=$(sed -n 's/.*--period-us \([0-9]*\).*/\1/p' <<< "$args")
  period_us=${period_us:-1000}
  master_exit=$(sed -n 's/^# master-exit: //p' "$file" | head -1)
  master_output=$(sed -n 's/^# master-output: //p' "$file" | head -1)
  for try in $(seq 1 "$E2E_LIVE_ATTEMPTS"); do
    read -r -a slave_args <<< "$(sed -n 's/^# slave: //p' "$file" | head -1)"
    run "$name" "$file" "${argv[@]}"
    slave_args=()
    sed -n '/^  \(PASS\|FAIL\|SKIP\)/p;/^scenario /p' "$work/$name.log"
    check "$name" && break
    if [ "$try" -lt "$E2E_LIVE_ATTEMPTS" ] && late "$name"; then
      echo "$name (attempt $try): $why - the host was late ($evidence), trying again"
      continue
    fi
    echo "FAIL: $name (attempt $try): $why; its log and the master's:"
    cat "$work/$name.log" "$work/$name.master.log"
    failures=$((failures + 1))
    break
  done
done

# A scenario the master cannot pass: it never asks for Bootstrap.
cat > "$work/never.yaml" << 'YAML'
name: never boot
steps:
  - name: in Op
    expect: {type: al_state, slave: 0, to: OP}
    within: 30s
  - name: the master asks for Bootstrap
    expect: {type: al_control, slave: 0, requested: BOOT}
    within: 300ms
  - do: {cmd: hello}
YAML
run never "$work/never.yaml" --cycles 100000
sed -n '/^  \(PASS\|FAIL\|SKIP\)/p;/^scenario /p' "$work/never.log"
if [ "$rc" -ne 3 ] || ! grep -q '^  FAIL the master asks for Bootstrap (.*) at .*: not seen within 300 ms$' "$work/never.log" ||
  ! grep -q '^  SKIP step 3 ' "$work/never.log" || ! grep -q 'failures="1"' "$work/never.xml"; then
  echo "FAIL: never: ecat-slave exit $rc (3 expected), or not the FAIL/SKIP lines and JUnit failures=\"1\""
  cat "$work/never.log"
  failures=$((failures + 1))
fi
[ "$failures" -eq 0 ] && echo "e2e_scenarios: all passed"
exit $((failures > 0))
