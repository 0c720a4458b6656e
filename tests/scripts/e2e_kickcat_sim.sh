#!/usr/bin/env bash
# An independent slave simulator as the test subject (issue 31 item 4, issue 32
# item 3): KickCAT's network_simulator (leducp/KickCAT, simulation/) with its
# three shipped slave configurations in one chain - ecat402-drive.json (a
# servo drive built from its ESI, "EVS-NET-01"), freedom-k64f.json and
# xmc4800.json (EEPROM images + CoE dictionaries of KickCAT's slave stack
# examples) - on s0 of a veth pair between two network namespaces.
#  (a) `ecat-master --iface m0 --capture cap1`: the files, each slave's
#      identity, the object counts and the notes, the PDO mapping and
#      assignment, and the SII images (the two EEPROM files byte for byte);
#  (b) ecat-conform on each of the three slaves: every case's verdict equals
#      tests/data/kickcat/conform-expected.txt (the KickCAT defects it shows are
#      described in docs/conformance.md "KickCAT's simulated devices");
#  (c) `ecat-slave --topology cap1/topology.txt` (the captured twin) is captured
#      into cap2, and cap2's twin into cap3: cap2 == cap3 byte for byte (fixed
#      point); cap1 vs cap2: the device files equal but for the differences
#      docs/twins.md lists (the notes comment, SM2/SM3 sizes, a derived 1008h),
#      the SII fixed area (bytes 0-127) identical;
#  (d) ecat-conform on each slave of the twin, against the same expected file,
#      and the description-level cases (sii.*, od.*, esi.*, identity) give the
#      same verdict on the original and on the twin.
# A case whose verdict differs from the expected one is run once more alone
# (live timing on a loaded machine), and reported; a second difference fails.
# KickCAT is not a Debian package: network_simulator is taken from
# $ECAT_KICKCAT_BIN (a directory) or PATH, its slave configurations from
# $ECAT_KICKCAT_SRC (a KickCAT checkout); without either the test is skipped
# (exit 77). Build recipe: docs/twins.md.
# Usage: e2e_kickcat_sim.sh SRCDIR BUILDDIR
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
# shellcheck source-path=SCRIPTDIR source=lib/netns.sh
. "$src/tests/scripts/lib/netns.sh"

if [ -n "${ECAT_KICKCAT_BIN:-}" ] && [ -x "$ECAT_KICKCAT_BIN/network_simulator" ]; then
  sim="$ECAT_KICKCAT_BIN/network_simulator"
else
  sim=$(command -v network_simulator 2> /dev/null) || { echo "skip: KickCAT network_simulator not found (set ECAT_KICKCAT_BIN=dir)"; exit 77; }
fi
configs="${ECAT_KICKCAT_SRC:-}/simulation/slave_configs"
if [ -z "${ECAT_KICKCAT_SRC:-}" ] || [ ! -f "$configs/ecat402-drive.json" ]; then
  echo "skip: ECAT_KICKCAT_SRC does not name a KickCAT checkout (simulation/slave_configs/ecat402-drive.json)"; exit 77
fi
expected="$src/tests/data/kickcat/conform-expected.txt"
e2e_require_bins ecat-slave ecat-master ecat-conform
e2e_require_netns
e2e_setup kq
# shellcheck disable=SC2317  # run by the EXIT trap
keep_logs() {
  if [ -n "${ECAT_E2E_KEEP:-}" ]; then
    mkdir -p "$ECAT_E2E_KEEP" && cp -r "$E2E_TMP"/. "$ECAT_E2E_KEEP"/ && echo "logs kept in $ECAT_E2E_KEEP"
  fi
  e2e_cleanup
}
trap keep_logs EXIT
echo "KickCAT: $sim, configurations $configs ($(git -C "$ECAT_KICKCAT_SRC" rev-parse --short=12 HEAD 2> /dev/null || echo 'not a git checkout'))"

start_simulator() {
  (cd "$configs" && exec timeout -s TERM 900 ip netns exec "$E2E_NS_S" stdbuf -oL "$sim" -i s0 \
    -s ecat402-drive.json freedom-k64f.json xmc4800.json) > "$E2E_TMP/sim.log" 2>&1 &
  SIM_PID=$!
  E2E_PIDS+=("$SIM_PID")
  local _
  for _ in $(seq 1 600); do  # the drive's 440 KB ESI is parsed first
    grep -q 'Opening redundant interface' "$E2E_TMP/sim.log" 2> /dev/null && { sleep 0.5; return 0; }
    kill -0 "$SIM_PID" 2> /dev/null || break
    sleep 0.1
  done
  echo "FAIL: network_simulator did not start:"; tr '\r' '\n' < "$E2E_TMP/sim.log"; exit 1
}

# capture NAME: ecat-master --capture into $E2E_TMP/NAME.
capture() {
  e2e_master "$1" 120 --capture "$E2E_TMP/$1" || e2e_fail "$1: ecat-master --capture exited $?"
}

# conform TAG: ecat-conform on slaves 0-2; verdicts "slave test verdict" in $E2E_TMP/TAG.verdicts.
conform() {
  local tag=$1 s
  : > "$E2E_TMP/$tag.verdicts"
  for s in 0 1 2; do
    timeout -s KILL 600 ip netns exec "$E2E_NS_M" "$build/bin/ecat-conform" --iface m0 --slave "$s" \
      > "$E2E_TMP/$tag.s$s.txt" 2>&1
    echo "  [$tag slave $s] $(tail -1 "$E2E_TMP/$tag.s$s.txt")"
    awk -v s="$s" 'NR > 3 && ($2 == "PASS" || $2 == "FAIL" || $2 == "SKIP") { print s, $1, $2 }' \
      "$E2E_TMP/$tag.s$s.txt" >> "$E2E_TMP/$tag.verdicts"
  done
}

# check_verdicts TAG COLUMN: every verdict equals the expected file's column
# (3 = original, 4 = twin); a difference is re-run once alone.
check_verdicts() {
  local tag=$1 col=$2 s name want got again
  [ "$(wc -l < "$E2E_TMP/$tag.verdicts")" -eq "$(grep -vc '^#' "$expected")" ] ||
    e2e_fail "$tag: $(wc -l < "$E2E_TMP/$tag.verdicts") verdicts, $expected has $(grep -vc '^#' "$expected")"
  while read -r s name want; do
    got=$(awk -v s="$s" -v n="$name" '$1 == s && $2 == n { print $3 }' "$E2E_TMP/$tag.verdicts")
    [[ "|$want|" == *"|$got|"* ]] && continue
    again=$(timeout -s KILL 120 ip netns exec "$E2E_NS_M" "$build/bin/ecat-conform" --iface m0 --slave "$s" \
      --filter "$name" 2>&1 | awk -v n="$name" '$1 == n { print $2 }')
    if [ -n "$again" ] && [[ "|$want|" == *"|$again|"* ]]; then
      echo "note: $tag slave $s $name: $got, then $want when run alone (live timing)"
    else
      e2e_fail "$tag slave $s $name: expected $want, got $got (alone: ${again:-nothing}): $(grep -m1 "^$name " "$E2E_TMP/$tag.s$s.txt" | tr -s ' ')"
    fi
  done < <(grep -v '^#' "$expected" | awk -v c="$col" '{ print $1, $2, $c }')
}

# PDOs of a captured device file, one line each: "Rx 1600h sm2: 6040:0/16 ...".
pdo_lines() {
  awk '/<(Rx|Tx)Pdo /{ match($0, /index="#x[0-9A-F]+"/); idx = substr($0, RSTART + 9, 4)
         sm = "-"; if (match($0, /sm="[0-9]+"/)) sm = substr($0, RSTART + 4, RLENGTH - 5)
         line = substr($0, index($0, "<") + 1, 2) " " idx "h sm" sm ":" }
       /<Entry index=/ && line != "" { match($0, /index="#x[0-9A-F]+"/); i = substr($0, RSTART + 9, 4)
         match($0, /sub="[0-9]+"/); s = substr($0, RSTART + 5, RLENGTH - 6)
         match($0, /bits="[0-9]+"/); b = substr($0, RSTART + 6, RLENGTH - 7)
         line = line sprintf(" %s:%s/%s", i, s, b) }
       /<\/(Rx|Tx)Pdo>/ { print line; line = "" }' "$1"
}
expect_eq() {  # WHAT GOT WANT
  [ "$2" = "$3" ] || e2e_fail "$1: got '$2', expected '$3'"
}

# (a) the capture of KickCAT's devices.
start_simulator
# Now and then, under load, one request of the capture of KickCAT's drive is
# answered "unexpected response" and so is every SDO information request after
# it (its cause was not found: docs/twins.md). Such a capture (more notes than
# the clean one's) is taken again, at most twice, and said so.
clean_notes=28
c="$E2E_TMP/cap1"
for try in 1 2 3; do
  rm -rf "$c"
  capture cap1
  notes=$(wc -l < "$c/1-EVS-NET-01.notes.txt" 2> /dev/null || echo 0)
  [ "$notes" -gt "$clean_notes" ] || break
  echo "cap1: attempt $try ended with $notes notes: $(grep -v 'entry description failed' "$c/1-EVS-NET-01.notes.txt" | head -1)"
done
d1="$c/1-EVS-NET-01" d2="$c/2-KickCAT-slave-stack-example" d3="$c/3-xmc48slave"
# shellcheck disable=SC2012  # capture file names have no blanks (capture_base_name)
expect_eq "cap1 files" "$(cd "$c" && ls | tr '\n' ' ')" \
  "1-EVS-NET-01.notes.txt 1-EVS-NET-01.sii.bin 1-EVS-NET-01.xml 2-KickCAT-slave-stack-example.sii.bin 2-KickCAT-slave-stack-example.xml 3-xmc48slave.sii.bin 3-xmc48slave.xml topology.txt "
identity() { grep -o '<Identity vendorId="[^"]*" productCode="[^"]*" revision="[^"]*" serial="[^"]*"' "$1.xml"; }
expect_eq "slave 1 identity" "$(identity "$d1")" '<Identity vendorId="#x0000029C" productCode="#x03B11002" revision="#x00050005" serial="#x00000000"'
expect_eq "slave 2 identity" "$(identity "$d2")" '<Identity vendorId="#x0000079A" productCode="#x00DEFEDE" revision="#x00005A01" serial="#x00000001"'
expect_eq "slave 3 identity" "$(identity "$d3")" '<Identity vendorId="#x00001337" productCode="#x00004800" revision="#x00000000" serial="#x00000000"'
# The SII: the two EEPROM files KickCAT loads, byte for byte; the drive's
# image (KickCAT builds it from the ESI) by its size.
cmp "$d2.sii.bin" "$ECAT_KICKCAT_SRC/examples/slave/lan9252/freedom-k64f/nuttx/eeprom.bin" || e2e_fail "slave 2 SII differs from KickCAT's eeprom.bin"
cmp "$d3.sii.bin" "$ECAT_KICKCAT_SRC/examples/slave/xmc4800/xmc4800-relax/nuttx/eeprom_xmc4800.bin" || e2e_fail "slave 3 SII differs from KickCAT's eeprom_xmc4800.bin"
expect_eq "slave 1 SII size" "$(stat -c %s "$d1.sii.bin")" 16384
# The dictionary: object counts, the values KickCAT's dictionaries hold
# (1018h as the coe_xml files give it, not the EEPROM's identity), the notes.
expect_eq "object counts" "$(grep -c '<Object index=' "$d1.xml") $(grep -c '<Object index=' "$d2.xml") $(grep -c '<Object index=' "$d3.xml")" "579 16 22"
expect_eq "slave 2 1018h:01" "$(grep -o 'sub="1" name="Vendor ID" type="UNSIGNED32" access="ro" default="[^"]*"' "$d2.xml")" \
  'sub="1" name="Vendor ID" type="UNSIGNED32" access="ro" default="#x000006A5"'
expect_eq "slave 1 6502h" "$(grep -o '<Object index="#x6502" name="[^"]*" type="UNSIGNED32" access="ro" default="[^"]*"' "$d1.xml")" \
  '<Object index="#x6502" name="Supported drive modes" type="UNSIGNED32" access="ro" default="#x000F03E5"'
expect_eq "slave 1 Dc" "$(grep -o '<Dc [^>]*' "$d1.xml")" '<Dc minCycleTime="100000" maxCycleTime="0" freeRun="true" smSync="true" dcSync0="true" dcSync1="false"'
expect_eq "slave 1 notes" "$(wc -l < "$d1.notes.txt") $(grep -c 'entry description failed (unexpected response); entry left out' "$d1.notes.txt")" "$clean_notes 26"
if [ -e "$d2.notes.txt" ] || [ -e "$d3.notes.txt" ]; then e2e_fail "notes for slave 2 or 3"; fi
expect_eq "slave 1 PDOs" "$(pdo_lines "$d1.xml" | grep 'sm[23]:')" \
  "$(printf '%s\n' 'Rx 1600h sm2: 6040:0/16 607A:0/32 60FF:0/32 6060:0/8' 'Tx 1A00h sm3: 6041:0/16 6064:0/32 606C:0/32 6061:0/8')"
expect_eq "slave 2 PDOs" "$(pdo_lines "$d2.xml")" \
  "$(printf '%s\n' 'Rx 1600h sm2: 7000:0/8 7001:0/8 7002:0/8' 'Tx 1A00h sm3: 6000:0/16 6001:0/16 6002:0/16 6003:0/16 6004:0/16 6005:0/16')"
expect_eq "slave 3 PDOs" "$(pdo_lines "$d3.xml")" \
  "$(printf '%s\n' 'Rx 1600h sm2: 6000:0/16' 'Tx 1A00h sm3: 6000:0/16 6001:0/16 6002:0/16 6003:0/16 6004:0/16 6005:0/16 6006:0/16 6007:0/16 6008:0/16 6009:0/16 600A:0/16 600B:0/16 600C:0/16')"

# (b) ecat-conform on KickCAT's devices.
conform orig
check_verdicts orig 3
e2e_stop "$SIM_PID"

# (c) the captured twin, captured twice.
e2e_start_slave twin1 --topology "$c/topology.txt" || exit 1
capture cap2
# (d) ecat-conform on the twin.
conform twin
check_verdicts twin 4
e2e_stop "$E2E_SLAVE_PID"
e2e_start_slave twin2 --topology "$E2E_TMP/cap2/topology.txt" || exit 1
capture cap3
e2e_stop "$E2E_SLAVE_PID"
for f in $(cd "$E2E_TMP/cap2" && ls); do
  cmp "$E2E_TMP/cap2/$f" "$E2E_TMP/cap3/$f" || e2e_fail "cap2/$f and cap3/$f differ: the capture of the twin is not a fixed point"
done
# cap1 vs cap2: the device files, without what docs/twins.md says a twin adds
# (SM2/SM3 sizes in the SII the twin writes, 1008h derived from the name) or
# lacks (the notes comment, the .notes.txt); what remains is exactly the list
# below (EVS-NET-01: 1010h/1011h:01 read 1, 1C00h derived, the live statusword,
# 6502h's manufacturer bits); the SII's fixed area is identical.
normal() {
  sed -e '/^<!-- captured by/,/^-->$/d' -e '/<Object index="#x1008" name="Device name"/d' \
      -e '/type="\(Outputs\|Inputs\)"/s/ size="[0-9]*"//' "$1"
}
evs_twin_diff() {
  cat << 'DIFF'
<       <Entry sub="1" name="Ecat Store all" type="UNSIGNED32" access="rw" default="#x00000000" />
>       <Entry sub="1" name="Ecat Store all" type="UNSIGNED32" access="rw" default="#x00000001" />
<       <Entry sub="1" name="Ecat Restore all" type="UNSIGNED32" access="rw" default="#x00000000" />
>       <Entry sub="1" name="Ecat Restore all" type="UNSIGNED32" access="rw" default="#x00000001" />
>     <Object index="#x1C00" name="Sync manager type" code="ARRAY" type="UNSIGNED8">
>       <Entry sub="0" name="Number of entries" type="UNSIGNED8" access="ro" default="#x04" />
>       <Entry sub="1" name="SubIndex 001" type="UNSIGNED8" access="ro" default="#x01" />
>       <Entry sub="2" name="SubIndex 002" type="UNSIGNED8" access="ro" default="#x02" />
>       <Entry sub="3" name="SubIndex 003" type="UNSIGNED8" access="ro" default="#x03" />
>       <Entry sub="4" name="SubIndex 004" type="UNSIGNED8" access="ro" default="#x04" />
>     </Object>
<     <Object index="#x6041" name="Status Word" type="UNSIGNED16" access="ro" pdo="tx" default="#x0000" />
>     <Object index="#x6041" name="Status Word" type="UNSIGNED16" access="ro" pdo="tx" default="#x0250" />
<     <Object index="#x6502" name="Supported drive modes" type="UNSIGNED32" access="ro" default="#x000F03E5" />
>     <Object index="#x6502" name="Supported drive modes" type="UNSIGNED32" access="ro" default="#x000003E5" />
DIFF
}
for n in 1-EVS-NET-01 2-KickCAT-slave-stack-example 3-xmc48slave; do
  got=$(diff <(normal "$c/$n.xml") <(normal "$E2E_TMP/cap2/$n.xml") | grep '^[<>]')
  want=""
  [ "$n" != 1-EVS-NET-01 ] || want=$(evs_twin_diff)
  expect_eq "$n: KickCAT's capture vs the twin's" "$got" "$want"
  cmp -n 128 "$c/$n.sii.bin" "$E2E_TMP/cap2/$n.sii.bin" || e2e_fail "$n: the twin's SII fixed area differs"
done

# The description-level cases give the same verdict on both.
same=$(join <(awk '{ print $1 ":" $2, $3 }' "$E2E_TMP/orig.verdicts" | sort) <(awk '{ print $1 ":" $2, $3 }' "$E2E_TMP/twin.verdicts" | sort))
differ=$(echo "$same" | awk '$2 != $3' | wc -l)
desc_differ=$(echo "$same" | awk '$2 != $3 && $1 ~ /:(sii|od|esi)\./')
echo "original vs twin: $(echo "$same" | awk '$2 == $3' | wc -l) cases with the same verdict, $differ differ (behaviour of KickCAT's stack vs ecatslave's; docs/conformance.md)"
[ -z "$desc_differ" ] || echo "description-level cases that differ (each explained in docs/conformance.md): $(echo "$desc_differ" | tr '\n' ';')"
expect_eq "description-level differences" "$(echo "$desc_differ" | awk 'NF { print $1 }' | tr '\n' ' ')" \
  "0:od.mandatory_objects 1:od.default_pdos_match_sii 1:sii.pdo_entries_exist 1:sii.pdo_entry_types_match_od "

[ "$e2e_status" -eq 0 ] && echo "e2e_kickcat_sim: OK"
exit "$e2e_status"
