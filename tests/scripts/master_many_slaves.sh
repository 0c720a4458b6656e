#!/usr/bin/env bash
# ecat-master with a process image of several frames (issue 16 item 5), in
# process, no network: 80 generic servos (80 x (outputs + inputs) is beyond
# one 1486-byte LRW datagram, so each cycle takes several frames) scanned,
# taken to Op through PreOp and SafeOp, cycled; every cycle must come back
# with the expected WKC in every datagram (summary "wkc-errors 0", exit 0),
# and the pcap of the run must show the cycles' LRWs at continuous logical
# addresses (checked with tshark when it is installed).
# Usage: master_many_slaves.sh SRCDIR BUILDDIR   (exit 77 = skipped)
set -uo pipefail
build=${2:?builddir}
master="$build/bin/ecat-master"
[ -x "$master" ] || { echo "skip: $master not built"; exit 77; }
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
status=0
fail() { echo "FAIL: $*"; status=1; }

timeout 300 "$master" --in-process --count 80 --cycles 20 -q --record "$tmp/run.pcap" > "$tmp/out" 2>&1
rc=$?
cat "$tmp/out"
[ "$rc" -eq 0 ] || fail "ecat-master exit $rc"
grep -q '^cycles 20 lost 0 wkc-errors 0 state-errors 0 ' "$tmp/out" || fail "summary: $(head -1 "$tmp/out")"

if command -v tshark > /dev/null; then
  # Command, logical address and length of every datagram the master sent
  # (several datagrams of a frame: comma-separated); LRW = command 12.
  timeout 120 tshark -r "$tmp/run.pcap" -Y 'eth.src[0] & 2 == 0 && ecat.cmd == 12' -T fields \
    -e ecat.cmd -e ecat.lad -e ecat.subframe.length 2> /dev/null > "$tmp/lrw"
  [ -s "$tmp/lrw" ] || fail "no LRW in the capture"
  # Per cycle the datagrams start at 0 and each starts where the last ended.
  awk -F'\t' '
    function num(s,   v, i, c) {  # decimal or 0x-hex (mawk has no strtonum)
      if (substr(s, 1, 2) != "0x") return s + 0
      v = 0
      for (i = 3; i <= length(s); ++i) { c = index("0123456789abcdef", tolower(substr(s, i, 1))) - 1; v = v * 16 + c }
      return v
    }
    {
      n = split($1, c, ","); split($2, a, ","); split($3, l, ",");
      for (i = 1; i <= n; ++i) {
        if (num(c[i]) != 12) continue;
        lad = num(a[i]); len = num(l[i]);
        if (lad == 0) {
          if (cycles > 0) { if (size > 0 && at != size) bad = 1; size = at }
          cycles++; at = 0
        }
        if (lad != at || len > 1486) bad = 1;
        at += len
      }
    } END {
      if (at != size) bad = 1
      if (bad || cycles < 20 || size <= 1486) { print "bad layout, cycles " cycles ", image " size; exit 1 }
      print "LRW cycles " cycles ", image " size " bytes"
    }' "$tmp/lrw" || fail "LRW addresses not continuous"
fi
exit $status
