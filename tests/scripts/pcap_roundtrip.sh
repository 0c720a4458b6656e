#!/usr/bin/env bash
# pcap round trip (issue 5 item 4): a master's capture -> ecat-slave
# --pcap-in/--pcap-out -> tshark. Checks that
#  - ecat-slave answers every master frame of the capture (replies already in
#    the capture are skipped) and reports no malformed or lost frame;
#  - every output frame is a returned frame (source MAC bit 1 set, the mark
#    an ESC leaves, ETG.1000.4 §5.1/Beckhoff ESC datasheet I §2);
#  - tshark decodes the output with no malformed packet and no expert error;
#  - the CoE SDO upload responses the master got while configuring carry the
#    generic servo's PDO assignment and mapping (1C12h/1C13h, 1600h/1A00h);
#  - a chain of the 4 seed drives round-trips with no malformed packet either.
# Usage: pcap_roundtrip.sh SRCDIR BUILDDIR   (exit 77 = skipped: no tshark)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
for b in ecat-slave ecat-master; do
  [ -x "$build/bin/$b" ] || { echo "skip: $build/bin/$b not built"; exit 77; }
done
command -v tshark > /dev/null || { echo "skip: tshark not installed"; exit 77; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
status=0
fail() { echo "FAIL: $*"; status=1; }
ts() { timeout 60 tshark "$@" 2> /dev/null; }

# roundtrip NAME MASTER-ARGS...: record, replay, decode; leaves $tmp/NAME.out.pcap.
roundtrip() {
  local name=$1; shift
  local cap="$tmp/$name.pcap" out="$tmp/$name.out.pcap"
  timeout 120 "$build/bin/ecat-master" --in-process --cycles 50 -q --record "$cap" "$@" > "$tmp/$name.master" 2>&1 \
    || { fail "$name: ecat-master exit $?: $(cat "$tmp/$name.master")"; return 1; }
  timeout 120 "$build/bin/ecat-slave" --pcap-in "$cap" --pcap-out "$out" > "$tmp/$name.slave" 2>&1 \
    || { fail "$name: ecat-slave exit $?: $(cat "$tmp/$name.slave")"; return 1; }
  local sent returned frames
  sent=$(ts -r "$cap" -Y 'eth.src[0] & 2 == 0' | wc -l)
  returned=$(ts -r "$out" -Y 'eth.src[0] & 2 == 2' | wc -l)
  frames=$(ts -r "$out" | wc -l)
  echo "$name: capture $(ts -r "$cap" | wc -l) frames ($sent from the master) -> $frames returned"
  grep '^frames ' "$tmp/$name.slave" | sed "s/^/  [$name slave] /"
  [ "$sent" -gt 0 ] || fail "$name: no master frame in the capture"
  [ "$returned" -eq "$sent" ] && [ "$frames" -eq "$sent" ] \
    || fail "$name: $sent master frames, $frames output frames, $returned marked as returned"
  grep -q "^frames $sent returned $sent malformed 0 lost 0 " "$tmp/$name.slave" \
    || fail "$name: ecat-slave statistics: $(grep '^frames' "$tmp/$name.slave")"
  local malformed
  malformed=$(ts -r "$out" -Y '_ws.malformed' | wc -l)
  [ "$malformed" -eq 0 ] || fail "$name: tshark finds $malformed malformed packet(s)"
  ts -r "$out" -q -z expert > "$tmp/$name.expert"
  if grep -q '^Errors' "$tmp/$name.expert"; then
    fail "$name: tshark expert errors:"; sed -n '/^Errors/,/^$/p' "$tmp/$name.expert"
  fi
}

# 1. The generic servo: SDO contents.
if roundtrip servo; then
  ts -r "$tmp/servo.out.pcap" -Y 'ecat_mailbox.coe.sdores' -T fields \
    -e ecat_mailbox.coe.sdoidx -e ecat_mailbox.coe.sdosub -e ecat_mailbox.coe.sdodata > "$tmp/sdo.txt"
  echo "servo: $(wc -l < "$tmp/sdo.txt") SDO responses decoded"
  # index sub data, as the generic servo's dictionary defines them.
  while read -r idx sub data; do
    grep -qx "$idx	$sub	$data" "$tmp/sdo.txt" || fail "servo: no SDO response $idx:$sub = $data"
  done <<'EXPECT'
0x1c12 0x00 0x01
0x1c12 0x01 0x1600
0x1c13 0x00 0x01
0x1c13 0x01 0x1a00
0x1600 0x01 0x60400010
0x1600 0x02 0x607a0020
0x1a00 0x01 0x60410010
0x1a00 0x02 0x60640020
EXPECT
  # The mailbox replies are CoE SDO responses (mailbox type 3), each the
  # reply to an upload request of the same object (no abort).
  aborts=$(ts -r "$tmp/servo.out.pcap" -Y 'ecat_mailbox.coe.abortcode' | wc -l)
  [ "$aborts" -eq 0 ] || fail "servo: $aborts SDO abort(s) in the round trip"
fi

# 2. A chain of the four seed drives.
d="$src/xml/devices"
roundtrip chain --device "$d/simtach-rse.xml" --device "$d/yaskawa-sigma5-sd.xml" \
  --device "$d/welcon-servo.xml" --device "$d/leadshine-isv2-can.xml" --expect-slaves 4

[ "$status" -eq 0 ] && echo "pcap_roundtrip: OK"
exit "$status"
