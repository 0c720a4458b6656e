#!/usr/bin/env bash
# Issue 32 item 3: `ecat-master --capture DIR` over EtherCAT-in-UDP on the
# loopback (no root): a network of (a) the default drive (generic-servo.xml,
# CoE with SDO information) and (b) a digital I/O device without a mailbox
# (tests/data/capture/dio8-no-mailbox.xml, captured from its SII alone) is
# captured into cap1; ecat-slave --topology cap1/topology.txt runs the
# capture and is captured into cap2; cap2's twin into cap3. Checks:
#   - cap1 == cap2 == cap3 byte for byte (device XML, SII image, topology):
#     the capture of a capture is a fixed point, and the twin's SII is the
#     image read from the original;
#   - exact values: identities, SII size, the drive's 6060h, 10F3h:01 and
#     1600h:02 defaults and 1018h, the I/O device's PDOs, the notes of the SII-only path;
#   - the captured files load (ecat-esigen DEVICE.xml writes an ESI).
# Usage: capture_roundtrip.sh SRCDIR BUILDDIR   (exit 77 = skipped)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
slave="$build/bin/ecat-slave"
master="$build/bin/ecat-master"
gen="$build/bin/ecat-esigen"
for b in "$slave" "$master"; do
  [ -x "$b" ] || { echo "skip: $b not built"; exit 77; }
done
out=$(mktemp -d)
pids=()
# shellcheck disable=SC2317  # run by the EXIT trap
cleanup() {
  local p
  for p in "${pids[@]}"; do kill "$p" 2> /dev/null; done
  wait 2> /dev/null
  [ -n "${CAPTURE_KEEP:-}" ] || rm -rf "$out"
}
trap cleanup EXIT
status=0
fail() { echo "FAIL: $*"; status=1; }
port=$((35100 + $$ % 400))

# capture N TOPOLOGY: runs ecat-slave --topology TOPOLOGY on the loopback and
# captures it into $out/capN; the master's and the slave's output in $out/capN.*.log.
capture() {
  local n=$1 topo=$2 p=$((port + $1))
  timeout -s TERM 60 "$slave" --topology "$topo" --udp "$p" > "$out/cap$n.slave.log" 2>&1 &
  local spid=$!
  pids+=("$spid")
  local _
  for _ in $(seq 1 200); do
    grep -q "slave(s) on" "$out/cap$n.slave.log" 2> /dev/null && break
    kill -0 "$spid" 2> /dev/null || break
    sleep 0.05
  done
  grep -q "slave(s) on" "$out/cap$n.slave.log" || { echo "FAIL: ecat-slave --topology $topo did not start:"; cat "$out/cap$n.slave.log"; exit 1; }
  timeout -s KILL 60 "$master" --udp "127.0.0.1:$p" --capture "$out/cap$n" > "$out/cap$n.master.log" 2>&1
  local rc=$?
  kill "$spid" 2> /dev/null
  wait "$spid" 2> /dev/null
  sed "s/^/  [cap$n] /" "$out/cap$n.master.log"
  [ $rc -eq 0 ] || { echo "FAIL: capture $n exited $rc"; exit 1; }
}

capture 1 "$src/tests/data/capture/drive-and-dio.txt"
capture 2 "$out/cap1/topology.txt"
capture 3 "$out/cap2/topology.txt"

files=$(cd "$out/cap1" && ls | tr '\n' ' ')
files=${files% }
echo "cap1: $files"
[ "$files" = "1-Generic-servo.sii.bin 1-Generic-servo.xml 2-DIO8-8-outputs-8-inputs--no-mailbox.notes.txt 2-DIO8-8-outputs-8-inputs--no-mailbox.sii.bin 2-DIO8-8-outputs-8-inputs--no-mailbox.xml topology.txt" ] ||
  fail "cap1 holds '$files'"

# The fixed point: every file of a capture equals the capture of its twin.
for f in $files; do  # file names without blanks (capture_base_name)
  for n in 2 3; do
    cmp "$out/cap1/$f" "$out/cap$n/$f" || fail "cap1/$f and cap$n/$f differ"
  done
done

drive="$out/cap1/1-Generic-servo"
dio="$out/cap1/2-DIO8-8-outputs-8-inputs--no-mailbox"
# The drive's SII image is the one ecat-slave made from generic-servo.xml.
if [ -x "$gen" ]; then
  if "$gen" "$src/xml/devices/generic-servo.xml" --sii "$out/orig-drive.bin" > "$out/gen.log" 2>&1; then
    cmp "$out/orig-drive.bin" "$drive.sii.bin" || fail "the drive's captured SII is not the original's image"
  else
    fail "ecat-esigen generic-servo.xml --sii: $(head -3 "$out/gen.log")"
  fi
  for x in "$drive.xml" "$dio.xml"; do
    "$gen" "$x" --esi "$out/reload.xml" > "$out/reload.log" 2>&1 || fail "$(basename "$x") does not load: $(head -3 "$out/reload.log")"
  done
fi

[ "$(stat -c %s "$drive.sii.bin")" = 2048 ] || fail "drive SII is $(stat -c %s "$drive.sii.bin") bytes, expected 2048"
[ "$(stat -c %s "$dio.sii.bin")" = 2048 ] || fail "dio SII is $(stat -c %s "$dio.sii.bin") bytes, expected 2048"
# Exact values: identities from the SII words 8-11 (vendor, product code).
[ "$(od -An -tx4 -j16 -N8 "$drive.sii.bin" | tr -s ' ')" = " 00000000 00000402" ] ||
  fail "drive identity words: $(od -An -tx4 -j16 -N8 "$drive.sii.bin")"
[ "$(od -An -tx4 -j16 -N8 "$dio.sii.bin" | tr -s ' ')" = " 00000000 00000808" ] ||
  fail "dio identity words: $(od -An -tx4 -j16 -N8 "$dio.sii.bin")"
grep -q 'productCode="#x00000808" revision="#x00010002"' "$dio.xml" || fail "dio identity not in its device file"
grep -q '<Mailbox coe="false"' "$dio.xml" || fail "dio captured with a mailbox"
grep -q 'captured from the SII alone' "$dio.notes.txt" || fail "no SII-only note for the dio: $(cat "$dio.notes.txt")"
grep -q '7000h:08 has no dictionary object; created as process data' "$dio.notes.txt" || fail "7000h:08 not noted"
grep -q '<RxPdo index="#x1600" name="Channel outputs" sm="0"' "$dio.xml" || fail "dio RxPDO 1600h not captured"
grep -q '<TxPdo index="#x1A00" name="Channel inputs" sm="1"' "$dio.xml" || fail "dio TxPDO 1A00h not captured"
[ "$(grep -c '<Entry index="#x7000"' "$dio.xml")" = 8 ] || fail "dio RxPDO entries: $(grep -c '<Entry index="#x7000"' "$dio.xml")"
# The drive's dictionary: identity object and uploaded values as defaults.
grep -q 'productCode="#x00000402"' "$drive.xml" || fail "drive product code"
grep -q 'deviceType="#x00020192"' "$drive.xml" || fail "drive device type 1000h"
grep -A3 'index="#x1018"' "$drive.xml" | head -12 > "$out/1018.txt"
grep -q 'Product code' "$out/1018.txt" || fail "1018h not captured: $(cat "$out/1018.txt")"
# Uploaded values as defaults: 10F3h:01 (diagnosis history, 16 messages) and
# the default RxPDO's second mapping entry, 607Ah:00 of 32 bits.
grep -q '<Entry sub="1" name="Maximum Messages" type="UNSIGNED8" access="ro" default="#x10" />' "$drive.xml" ||
  fail "10F3h:01 default: $(grep 'Maximum Messages' "$drive.xml")"
grep -q 'default="#x607A0020"' "$drive.xml" || fail "1600h:02 = 607A0020h not captured"
grep -q '<Object index="#x6060" name="Modes of operation" type="INTEGER8" access="rw" pdo="rx" default="#x00" />' "$drive.xml" ||
  fail "6060h: $(grep 'index="#x6060"' "$drive.xml")"
grep -q 'captured 2 slave(s)' "$out/cap1.master.log" || fail "summary line missing"
grep -q 'slave s2 2-DIO8-8-outputs-8-inputs--no-mailbox.xml at s1:1' "$out/cap1/topology.txt" || fail "topology: $(cat "$out/cap1/topology.txt")"

[ $status -eq 0 ] && echo "capture round trip: ok"
exit $status
