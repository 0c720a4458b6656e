#!/usr/bin/env bash
# Interoperability with an independent open-source master (issue 5, issue 14):
# SOEM's sample programs (1.x: slaveinfo, simple_test; 2.x: slaveinfo,
# simple_ng, ec_sample, eni_test; whichever exist) against ecat-slave over a veth
# pair between two network namespaces (see docs/e2e.md "Independent master").
#  (a) the embedded generic servo: slaveinfo -map (SII + CoE PDO map), slaveinfo
#      -sdo (SDO information walk), simple_test (SafeOp -> Op, 10000 LRW cycles,
#      DC delay measurement by ec_configdc, FRMW of the system time per cycle);
#  (b) the chain of the 4 seed drives: the same three runs (the Yaskawa SII asks
#      for LRD/LWR instead of LRW, so SOEM exchanges in two datagrams).
#  (b2) 199 I/O slaves with the firmware on two threads (--firmware-threads 2):
#      simple_ng, 10000 cycles, the runs split.
# Checks: slaves found and named as the SII says, SafeOp reached, the CoE PDO
# map printed, every object of the dictionary described without SDO error
# (only "subindex does not exist" for gaps in 1C32h/1C33h), "Operational state
# reached for all slaves", every process-data cycle with exactly the expected
# WKC, and no SM watchdog in the slave while the master ran.
# Under load (lib/netns.sh "Live timing under load"): a cyclic frame that
# takes SOEM's whole EC_TIMEOUTRET (2 ms) is SOEM's timeout against a late
# host, which the spec allows: counted as late, up to E2E_SOEM_LATE_MAX
# (default 10 %); and eni_test's check thread, whose own state reads then go
# unanswered (the slave dropped them as stale), prints "slave N lost" and
# "found"/"recovered" - allowed only when the slave did drop stale frames.
# Every frame that came back must be exact, every SDO answer right (no error
# but 06090011h: the stale-frame drop keeps SOEM's mailbox walk on its way,
# docs/e2e.md "Stale frames"), and a slave in an error state fails.
# SOEM is not a Debian package: the binaries are taken from $ECAT_SOEM_BIN
# (a directory) or PATH; without them the test is skipped (exit 77).
# Usage: e2e_soem.sh SRCDIR BUILDDIR
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
# shellcheck source-path=SCRIPTDIR source=lib/netns.sh
. "$src/tests/scripts/lib/netns.sh"

soem_find() {
  local name=$1
  if [ -n "${ECAT_SOEM_BIN:-}" ] && [ -x "$ECAT_SOEM_BIN/$name" ]; then
    echo "$ECAT_SOEM_BIN/$name"
  else
    command -v "$name" 2> /dev/null
  fi
}
# SOEM 1.x ships simple_test; SOEM 2.x replaced it by simple_ng and added
# ec_sample (DC, cyclic mailbox) and eni_test (built with SOEM's sample ENI).
# Whatever is present is run; slaveinfo exists in both generations.
slaveinfo=$(soem_find slaveinfo) || { echo "skip: SOEM slaveinfo not found (set ECAT_SOEM_BIN=dir)"; exit 77; }
simple_test=$(soem_find simple_test) || simple_test=""
simple_ng=$(soem_find simple_ng) || simple_ng=""
ec_sample=$(soem_find ec_sample) || ec_sample=""
eni_test=$(soem_find eni_test) || eni_test=""
if [ -z "$simple_test" ] && [ -z "$simple_ng" ]; then
  echo "skip: neither SOEM simple_test (1.x) nor simple_ng (2.x) found (set ECAT_SOEM_BIN=dir)"; exit 77
fi
echo "SOEM programs: slaveinfo ${simple_test:+simple_test }${simple_ng:+simple_ng }${ec_sample:+ec_sample }${eni_test:+eni_test}"
e2e_require_bins ecat-slave
e2e_require_netns
e2e_setup so
# SOEM gives a frame 2 ms (EC_TIMEOUTRET) and a mailbox write 3 x 2 ms; a
# user-space slave on a loaded machine can miss that, and SOEM then drops the
# SDO (a PDO entry of 0 bits, AL 001Dh/001Eh at SafeOp; docs/e2e.md). So the
# slave runs SCHED_FIFO where that is allowed (E2E_SOEM_NO_RT=1: never).
slave_rt=()
if [ -z "${E2E_SOEM_NO_RT:-}" ] && chrt -f 40 true 2> /dev/null; then slave_rt=(--rt-priority 40); fi

# Runs a SOEM program in the master namespace on m0; output (\r turned into
# newlines: simple_test overwrites its cycle line) to $E2E_TMP/NAME.log.
# SOEM gives every cyclic frame EC_TIMEOUTRET (2 ms); on a loaded machine the
# master process itself can miss that, so where SCHED_FIFO is allowed it runs
# at priority 30, below the slave's 40 (E2E_SOEM_NO_RT=1: never).
master_rt=()
if [ ${#slave_rt[@]} -gt 0 ]; then master_rt=(chrt -f 30); fi
soem_run() {
  local name=$1 limit=$2 prog=$3; shift 3
  timeout -s KILL "$limit" ip netns exec "$E2E_NS_M" "${master_rt[@]}" "$prog" m0 "$@" 2>&1 | tr '\r' '\n' > "$E2E_TMP/$name.log"
  return "${PIPESTATUS[0]}"
}
expect_line() {  # NAME REGEX WHAT
  grep -qE "$2" "$E2E_TMP/$1.log" || e2e_fail "$1: $3 (no line matching '$2')"
}
# A cycle whose frame is not back within SOEM's EC_TIMEOUTRET (2 ms) counts
# WKC -1 (EC_NOFRAME), or only the frames that came back when the map takes
# several (simple_ng shows a round trip of 2 ms or more then); on this 2-core VM shared by several builds that
# happens for a few cycles in 10000 even with SCHED_FIFO, and beside two CPU
# burners for 1-2 % of them. Those late frames are allowed up to
# E2E_SOEM_LATE_MAX (default 1000 = 10 %) and reported; every
# frame that did come back must carry exactly the expected WKC, and the slave
# must have returned every frame it got (its "lost 0" at exit, checked by
# check_slave_returned_all).
late_max=${E2E_SOEM_LATE_MAX:-1000}
check_slave_returned_all() {  # SLAVE_LOG_NAME
  grep -qE '^frames [0-9]+ returned [0-9]+ malformed 0 lost 0 ' "$E2E_TMP/$1.log" \
    || e2e_fail "$1: the slave did not return every frame: $(grep -m1 '^frames ' "$E2E_TMP/$1.log")"
}

# slaveinfo -map: count, names, SafeOp, and the PDO map read over CoE.
check_map() {
  local name=$1 count=$2; shift 2
  soem_run "$name" 60 "$slaveinfo" -map || e2e_fail "$name: slaveinfo exit $?"
  expect_line "$name" "^$count slaves found and configured\.$" "slave count"
  ! grep -q "Not all slaves reached safe operational state" "$E2E_TMP/$name.log" || e2e_fail "$name: not all in SafeOp"
  local n=0 want
  for want in "$@"; do
    n=$((n + 1))
    expect_line "$name" "^ Name:$want\$" "slave $n name"
  done
  [ "$(grep -c '^ State: 4$' "$E2E_TMP/$name.log")" -eq "$count" ] || e2e_fail "$name: not every slave reports State 4 (SafeOp)"
  [ "$(grep -c '^PDO mapping according to CoE :$' "$E2E_TMP/$name.log")" -eq "$count" ] \
    || e2e_fail "$name: CoE PDO map missing"
  # Every slave's map starts with the controlword at its own output offset.
  [ "$(grep -cE '^  \[0x[0-9A-F]{4}\.0\] 0x6040:0x00 0x10 UNSIGNED16 ' "$E2E_TMP/$name.log")" -eq "$count" ] \
    || e2e_fail "$name: controlword 6040h not in every RxPDO map"
  echo "$name: $(grep -cE '^  \[0x' "$E2E_TMP/$name.log") mapped entries, $(grep -m1 '^Calculated workcounter' "$E2E_TMP/$name.log")"
}

# slaveinfo -sdo: the SDO information walk over every object and entry.
check_sdo() {
  local name=$1 count=$2
  soem_run "$name" 120 "$slaveinfo" -sdo || e2e_fail "$name: slaveinfo exit $?"
  [ "$(grep -cE '^ CoE Object Description found, [0-9]+ entries\.$' "$E2E_TMP/$name.log")" -eq "$count" ] \
    || e2e_fail "$name: object list missing for a slave"
  local bad
  bad=$(grep -E ' (SDO|PACKET|MBX|EMERGENCY) slave:' "$E2E_TMP/$name.log" | grep -v ' error:06090011 ')
  [ -z "$bad" ] || e2e_fail "$name: SDO errors: $(echo "$bad" | head -3)"
  # 1.x: " Index: 1000 Datatype: ..." and "          Value :..." per entry;
  # 2.x: '0x1000      "name"      [VAR]' and '    0x00      "name"      [TYPE ACC]      value'.
  local objects entries
  objects=$(($(grep -cE '^ Index: ' "$E2E_TMP/$name.log") + $(grep -cE '^0x[0-9a-f]{4} +"' "$E2E_TMP/$name.log")))
  entries=$(($(grep -cE '^          Value :' "$E2E_TMP/$name.log") + $(grep -cE '^    0x[0-9a-f]{2} +"' "$E2E_TMP/$name.log")))
  [ "$objects" -gt 0 ] && [ "$entries" -ge "$objects" ] || e2e_fail "$name: $objects objects, $entries entries described"
  echo "$name: $objects objects described, $entries entries (values) read," \
    "$(grep -c ' error:06090011 ' "$E2E_TMP/$name.log") gaps reported (06090011h)"
}

# simple_test: Op and 10000 cycles, each with exactly the calculated WKC.
check_op() {
  local name=$1
  soem_run "$name" 150 "$simple_test" || e2e_fail "$name: simple_test exit $?"
  expect_line "$name" '^Operational state reached for all slaves\.$' "Op not reached"
  local want cycles exact
  want=$(sed -n 's/^Calculated workcounter \([0-9]*\)$/\1/p' "$E2E_TMP/$name.log")
  cycles=$(grep -c '^Processdata cycle' "$E2E_TMP/$name.log")
  exact=$(grep -cE "^Processdata cycle +[0-9]+, WKC $want , " "$E2E_TMP/$name.log")
  # simple_test prints a cycle only when its WKC is at least the expected one.
  if [ -z "$want" ] || [ "$exact" -ne "$cycles" ] || [ "$cycles" -lt $((10000 - late_max)) ]; then
    e2e_fail "$name: $cycles cycles printed, $exact with WKC ${want:-?} (want all, and at least $((10000 - late_max)))"
  fi
  ! grep -qE '^(ERROR|WARNING) : slave' "$E2E_TMP/$name.log" || e2e_fail "$name: state check fired"
  echo "$name: expected WKC $want, $exact/10000 cycles exact ($((10000 - cycles)) not printed: late or short); last: $(grep '^Processdata cycle' "$E2E_TMP/$name.log" | tail -1)"
}

# simple_ng (SOEM 2.x): Op, then 10000 iterations "Iteration N: T usec  WKC W
# O: .. I: .. T: .."; it prints "wrong (expected E)" for a short WKC, so
# every iteration must show exactly the expected WKC (given: 3 per slave with
# outputs and inputs, LRW). PRINTED: the WKC simple_ng itself expects, when
# it differs from the one every frame must carry (case b2).
check_op_ng() {
  local name=$1 want=$2 printed=${3:-$2}
  soem_run "$name" 150 "$simple_ng" || e2e_fail "$name: simple_ng exit $?"
  expect_line "$name" 'all slaves are now operational$' "Op not reached"
  local iters exact late
  iters=$(grep -cE '^Iteration +[0-9]+:' "$E2E_TMP/$name.log")
  exact=$(grep -cE "^Iteration +[0-9]+: +[0-9]+ usec  WKC $want  O:" "$E2E_TMP/$name.log")
  # Late: the round trip took SOEM's whole 2 ms timeout, so a frame (or one of
  # the frames, when the map needs several) was not back: WKC -1 or partial.
  late=$(grep -E "^Iteration +[0-9]+: +[0-9]+ usec  WKC -?[0-9]+ wrong \(expected $printed\)$" "$E2E_TMP/$name.log" \
    | awk '$3 >= 2000' | wc -l)
  [ "$iters" -eq 10000 ] && [ $((exact + late)) -eq 10000 ] && [ "$late" -le "$late_max" ] \
    || e2e_fail "$name: $iters iterations, $exact with WKC $want, $late late (WKC -1; at most $late_max)"
  echo "$name: $(grep -m1 'slaves found' "$E2E_TMP/$name.log" | tr -s ' '), $exact/10000 iterations with WKC $want, $late late;" \
    "last: $(grep -E '^Iteration' "$E2E_TMP/$name.log" | tail -1)"
}

# ec_sample (SOEM 2.x): DC configured, a cyclic thread at 1 ms with the DC
# time and its PI loop, 5000 samples 20 ms apart printing the thread's WKC
# and DC time; the CoE slaves in the cyclic mailbox handler (an SDO read of
# 1018h:02 every sample).
check_dc_sample() {  # NAME SLAVES WANT_WKC SLAVE_LOG_NAME
  local name=$1 count=$2 want=$3 slave=$4
  soem_run "$name" 150 "$ec_sample" || e2e_fail "$name: ec_sample exit $?"
  expect_line "$name" "^$count slaves found and configured\.$" "slave count"
  expect_line "$name" '^EtherCAT OP$' "Op not reached"
  local samples exact late
  samples=$(grep -cE '^Processdata cycle +[0-9]+ , Wck +-?[0-9]+, DCtime' "$E2E_TMP/$name.log")
  exact=$(grep -cE "^Processdata cycle +[0-9]+ , Wck +$want, DCtime +[1-9][0-9]*," "$E2E_TMP/$name.log")
  # Wck -1: the sampled cycle's frame took SOEM's whole EC_TIMEOUTRET (a
  # late host, as above), up to the same share as simple_test's.
  late=$(grep -cE '^Processdata cycle +[0-9]+ , Wck +-1, DCtime' "$E2E_TMP/$name.log")
  # A sample line can be cut by the cyclic thread's own output (seen: 3 of
  # 5000), so at least 4990 lines and every one with the expected Wck or late.
  [ "$samples" -ge 4990 ] && [ $((exact + late)) -eq "$samples" ] && [ "$late" -le $((late_max / 2)) ] \
    || e2e_fail "$name: $samples samples, $exact with Wck $want and a DC time, $late late (at most $((late_max / 2)))"
  e2e_slave_snapshot "$slave" "$(e2e_slave_program_pid "$E2E_SLAVE_PID")"
  [ "$(soem_state_messages "$name" "$slave")" -eq 0 ] || e2e_fail "$name: state check fired"
  echo "$name: $(grep -c 'added to cyclic mailbox handler' "$E2E_TMP/$name.log") slaves in the cyclic mailbox handler," \
    "$exact/5000 samples with Wck $want, $late late; last: $(grep -E '^Processdata cycle' "$E2E_TMP/$name.log" | tail -1)"
}

# The "slave N ..." lines of SOEM's check thread (eni_test, ec_sample) that
# say a slave left Op: "ERROR/WARNING/MESSAGE : slave N ..." - except "slave
# N lost" and its "found"/"recovered" when the slave (log SLAVE_LOG_NAME)
# dropped stale frames: then the check thread's own state reads got no
# answer, a late host, not a slave that left Op (lib/netns.sh "Live timing
# under load").
soem_state_messages() {  # LOG_NAME SLAVE_LOG_NAME
  local lost
  lost=$(grep -cE '^(ERROR : slave [0-9]+ lost|MESSAGE : slave [0-9]+ (found|recovered))$' "$E2E_TMP/$1.log")
  if [ "$lost" -gt 0 ] && [ "$(e2e_slave_stale "$2")" -gt 0 ]; then
    echo "$1: $lost lost/found/recovered messages while the slave dropped $(e2e_slave_stale "$2") stale frames (late, allowed)" >&2
    lost=0
  fi
  echo $((lost + $(grep -E '^(ERROR|WARNING|MESSAGE) : slave' "$E2E_TMP/$1.log" |
    grep -cvE '^(ERROR : slave [0-9]+ lost|MESSAGE : slave [0-9]+ (found|recovered))$')))
}

# eni_test's check thread prints "check wkc=W/E docheckstate=D!" when a cycle
# came back short (W < E) or a state check is pending; W = -1 is a late frame,
# and "W=E, D=1" the re-check after the thread's own state read came late.
# Short: 0 <= W < E; plus the state messages above.
eni_test_short() {  # LOG_NAME SLAVE_LOG_NAME
  local short
  short=$(sed -n 's/^check wkc=\(-\{0,1\}[0-9]*\)\/\([0-9]*\) .*/\1 \2/p' "$E2E_TMP/$1.log" | awk '$1 >= 0 && $1 < $2' | wc -l)
  echo $((short + $(soem_state_messages "$1" "$2")))
}

check_op_any() {  # NAME WANT_WKC
  if [ -n "$simple_test" ]; then check_op "$1"; fi
  if [ -n "$simple_ng" ]; then check_op_ng "${1}_ng" "$2"; fi
}

# (a) the embedded generic servo.
if e2e_start_slave servo "${slave_rt[@]}"; then
  check_map si_servo_map 1 ECATSLAVE-SERVO-1
  check_sdo si_servo_sdo 1
  check_op_any st_servo 3
  e2e_stop "$E2E_SLAVE_PID"
  check_slave_returned_all servo
  e2e_check_no_watchdog_during_run servo
else
  e2e_fail "(a) slave did not start"
fi

# (a2) ec_sample on its own slave: it stops its 1 ms cyclic thread before it
# asks for SafeOp, so the slave's SM watchdog rightly expires at the end; no
# watchdog check for this run.
if [ -n "$ec_sample" ]; then
  if e2e_start_slave dc_servo "${slave_rt[@]}"; then
    check_dc_sample ec_servo 1 3 dc_servo
    e2e_stop "$E2E_SLAVE_PID"
    check_slave_returned_all dc_servo
  else
    e2e_fail "(a2) slave did not start"
  fi
fi

# (b) the four seed drives in one chain.
d="$src/xml/devices"
chain="$d/simtach-rse.xml,$d/yaskawa-sigma5-sd.xml,$d/welcon-servo.xml,$d/leadshine-isv2-can.xml"
if e2e_start_slave chain "${slave_rt[@]}" --chain "$chain"; then
  check_map si_chain_map 4 RS400E CACR-JU102ACA Welcon-Servo-1axis iSV2-CAN6040V48
  check_sdo si_chain_sdo 4
  check_op_any st_chain 12
  e2e_stop "$E2E_SLAVE_PID"
  check_slave_returned_all chain
  e2e_check_no_watchdog_during_run chain
else
  e2e_fail "(b) slave chain did not start"
fi

# (b2) 199 I/O slaves (SOEM's EC_MAXSLAVE of 200 leaves 199) with their
# firmware on two threads (issue 30 item 3, docs/performance-log.md "Firmware
# lanes"): simple_ng takes them to Op and runs 10000 cycles, the slave's firmware runs split
# (split-runs > 0 at exit), no watchdog. Neither side at a SCHED_FIFO
# priority: the helper spins, and a FIFO helper on a 2-CPU host would take
# the master's CPU. Needs 2 CPUs.
if [ -n "$simple_ng" ] && [ "$(nproc)" -ge 2 ]; then
  if e2e_start_slave lanes --device "$src/tests/data/devices/io-32ch.xml" --count 199 --firmware-threads 2; then
    fifo_master=("${master_rt[@]}")
    master_rt=()
    # The map is 796 output, 796 input and 199 mailbox-status bytes (SOEM 2.x
    # reads each slave's SM1 status through the process data), in two frames:
    # the first has every output and the inputs of slaves 1-167 (3 each, 2 for
    # slaves 168-199: 565), the second the other inputs and every status byte
    # (1 each: 199). simple_ng expects 597 (outputs x 2 + inputs) and takes more.
    check_op_ng st_lanes_ng 764 597
    master_rt=("${fifo_master[@]}")
    e2e_stop "$E2E_SLAVE_PID"
    check_slave_returned_all lanes
    e2e_check_no_watchdog_during_run lanes > /dev/null
    splits=$(sed -n 's/^firmware-threads 2 split-runs \([0-9]*\) .*/\1/p' "$E2E_TMP/lanes.log")
    [ -n "$splits" ] && [ "$splits" -gt 0 ] \
      || e2e_fail "lanes: the firmware never ran split: $(grep '^firmware-threads' "$E2E_TMP/lanes.log")"
    echo "lanes: $(grep '^firmware-threads' "$E2E_TMP/lanes.log")"
  else
    e2e_fail "(b2) slave with two firmware threads did not start"
  fi
fi

# (c) SOEM 2.x eni_test: the master built with SOEM's sample ENI
# (tests/data/eni/soem-sample-eni.xml) against `ecat-slave --eni` of the same
# file: the ENI's CoE InitCmds at PreOp->SafeOp (SOEM checks the SII identity
# against the ENI first), Op, 10000 cycles with the calculated WKC (2: the
# sample's PDOs are not described, so only the mailbox-status FMMUs count).
if [ -n "$eni_test" ]; then
  if e2e_start_slave eni "${slave_rt[@]}" --eni "$src/tests/data/eni/soem-sample-eni.xml"; then
    soem_run eni_test 150 "$eni_test" || e2e_fail "eni_test: exit $?"
    expect_line eni_test '^2 slaves found and configured\.$' "slave count"
    expect_line eni_test '^Operational state reached for all slaves\.$' "Op not reached"
    want=$(sed -n 's/^Calculated workcounter \([0-9]*\)$/\1/p' "$E2E_TMP/eni_test.log")
    # eni_test prints a cycle only when its WKC is at least the expected one;
    # its check thread prints "check wkc=W/2" for the others.
    cycles=$(grep -cE '^Processdata cycle +[0-9]+, WKC' "$E2E_TMP/eni_test.log")
    exact=$(grep -cE "^Processdata cycle +[0-9]+, WKC ${want:-x} , " "$E2E_TMP/eni_test.log")
    e2e_slave_snapshot eni "$(e2e_slave_program_pid "$E2E_SLAVE_PID")"
    short=$(eni_test_short eni_test eni)
    [ "${want:-}" = 2 ] && [ "$exact" -eq "$cycles" ] && [ "$cycles" -ge $((10000 - late_max)) ] && [ "$short" -eq 0 ] \
      || e2e_fail "eni_test: $exact/$cycles printed cycles with WKC ${want:-?} (want 2), $short short WKCs"
    echo "eni_test: expected WKC ${want:-?}, $exact/10000 cycles exact, $((10000 - cycles)) late (WKC -1)"
    e2e_stop "$E2E_SLAVE_PID"
    check_slave_returned_all eni
    grep -q 'ENI slave 2: Sample device B' "$E2E_TMP/eni.log" || e2e_fail "eni: ecat-slave did not build the ENI's chain"
  else
    e2e_fail "(c) ecat-slave --eni did not start"
  fi
fi

# (d) the chain of tests/data/eni/servo-and-io.xml (a servo and an I/O device,
# both synthesised from the ENI: no --esi-dir) with process data: SOEM 2.x's
# simple_ng (plain autoconfiguration from the SII and CoE) and, if present,
# an eni_test compiled with that ENI (eni_test_servo_and_io: SOEM's
# scripts/eniconv.py on the ENI, linked with samples/eni_test/eni_test.c;
# docs/e2e.md), which sends the ENI's PDO mapping and assignment first.
# Expected WKC 6: LRW, outputs and inputs in both slaves.
eni_io_test=$(soem_find eni_test_servo_and_io) || eni_io_test=""
if [ -n "$simple_ng" ] || [ -n "$eni_io_test" ]; then
  if e2e_start_slave eni_io "${slave_rt[@]}" --eni "$src/tests/data/eni/servo-and-io.xml"; then
    [ -n "$simple_ng" ] && check_op_ng st_eni_io_ng 6
    if [ -n "$eni_io_test" ]; then
      soem_run eni_io_test 150 "$eni_io_test" || e2e_fail "eni_io_test: exit $?"
      expect_line eni_io_test '^2 slaves found and configured\.$' "slave count"
      expect_line eni_io_test '^Operational state reached for all slaves\.$' "Op not reached"
      want=$(sed -n 's/^Calculated workcounter \([0-9]*\)$/\1/p' "$E2E_TMP/eni_io_test.log")
      cycles=$(grep -cE '^Processdata cycle +[0-9]+, WKC' "$E2E_TMP/eni_io_test.log")
      exact=$(grep -cE "^Processdata cycle +[0-9]+, WKC ${want:-x} , " "$E2E_TMP/eni_io_test.log")
      e2e_slave_snapshot eni_io "$(e2e_slave_program_pid "$E2E_SLAVE_PID")"
      short=$(eni_test_short eni_io_test eni_io)
      [ "${want:-}" = 6 ] && [ "$exact" -eq "$cycles" ] && [ "$cycles" -ge $((10000 - late_max)) ] && [ "$short" -eq 0 ] \
        || e2e_fail "eni_io_test: $exact/$cycles printed cycles with WKC ${want:-?} (want 6), $short short WKCs"
      echo "eni_io_test: expected WKC ${want:-?}, $exact/10000 cycles exact, $((10000 - cycles)) late (WKC -1)"
    fi
    e2e_stop "$E2E_SLAVE_PID"
    check_slave_returned_all eni_io
  else
    e2e_fail "(d) ecat-slave --eni servo-and-io.xml did not start"
  fi
fi

if [ "$e2e_status" -ne 0 ] && [ -n "${ECAT_E2E_KEEP:-}" ]; then
  cp -r "$E2E_TMP" "$ECAT_E2E_KEEP" && echo "logs kept in $ECAT_E2E_KEEP"
fi
[ "$e2e_status" -eq 0 ] && echo "e2e_soem: OK"
exit "$e2e_status"
