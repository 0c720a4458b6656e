#!/usr/bin/env bash
# ecat-slave's device choice (issue 14 items 4 and 5), checked on exact
# output without a network: the devices are loaded before the medium, so a
# replay of an empty capture (--pcap-in) shows which chain was built.
#  * --esi FILE with --product-code/--revision/--type: the one device chosen,
#    an error listing the candidates when the selection is ambiguous or empty;
#  * --eni FILE [--esi-dir DIR]: the ENI's chain, each slave's dictionary from
#    the matching ESI or synthesised, ENI errors as file:line.
# Usage: slave_select_cli.sh SRCDIR BUILDDIR   (exit 77 = skipped)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
slave="$build/bin/ecat-slave"
gen="$build/bin/ecat-esigen"
[ -x "$slave" ] && [ -x "$gen" ] || { echo "skip: ecat-slave/ecat-esigen not built"; exit 77; }

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
status=0
fail() { echo "FAIL: $*"; status=1; }
# A pcap file with only its global header (little-endian, Ethernet).
printf '\xd4\xc3\xb2\xa1\x02\x00\x04\x00\x00\x00\x00\x00\x00\x00\x00\x00\xff\xff\x00\x00\x01\x00\x00\x00' > "$out/empty.pcap"
run() {  # expected-rc description args...
  local want=$1 what=$2; shift 2
  "$slave" "$@" --pcap-in "$out/empty.pcap" --pcap-out "$out/o.pcap" > "$out/stdout" 2> "$out/stderr"
  local rc=$?
  [ "$rc" -eq "$want" ] || fail "$what: exit $rc, expected $want ($(head -c 400 "$out/stderr"))"
}
has() {  # description fixed-string file
  grep -qF -- "$2" "$3" || fail "$1: no line with '$2' in: $(cat "$3")"
}

vendor="$src/tests/data/esi/vendor-drives.xml"
run 0 "--type" --esi "$vendor" --type EXIO-8
has "--type EXIO-8" "  slave   1 EXIO-8 digital I/O " "$out/stderr"
run 0 "--type --revision" --esi "$vendor" --type EXD-100 --revision '#x10000'
has "--type --revision" "  slave   1 EXD-100 servo (rev 1) " "$out/stderr"
run 1 "ambiguous" --esi "$vendor" --product-code 0x1001
[ "$(cat "$out/stderr")" = "ecat-slave: $vendor:25: 3 devices match product code #x00001001; add --product-code, --revision or --type to choose one of: EXD-100 (product code #x00001001, revision #x00010000, line 26); EXD-100 (product code #x00001001, revision #x00020000, line 36); EXIO-8 (product code #x00001001, revision #x00000001, line 731)" ] \
  || fail "ambiguous: $(cat "$out/stderr")"
run 1 "no match" --esi "$vendor" --type EXD-100 --revision 3
has "no match" "$vendor:25: no device with type 'EXD-100' revision #x00000003 in this file (it has: " "$out/stderr"
run 2 "--type without --esi" --type EXIO-8

eni="$src/tests/data/eni/servo-and-io.xml"
mkdir -p "$out/esi"
"$gen" --esi "$out/esi/generic-servo.xml" || fail "ecat-esigen --esi"
run 0 "--eni --esi-dir" --eni "$eni" --esi-dir "$out/esi"
has "--eni slave 1" "ecat-slave: ENI slave 1: Axis 1 (ECATSLAVE-SERVO-1) vendor #x00000000 product #x00000402 revision #x00010000: dictionary from $out/esi/generic-servo.xml" "$out/stderr"
has "--eni slave 2" "ecat-slave: ENI slave 2: IO 1 (IOBOX-8) vendor #x00000999 product #x00002222 revision #x00000001: dictionary synthesised from the ENI" "$out/stderr"
has "--eni cyclic" "ecat-slave: ENI cyclic: 1 command(s), expected WKC 6 per cycle" "$out/stderr"
has "--eni chain" "  slave   1 Generic servo " "$out/stderr"
has "--eni chain" "  slave   2 IO 1 (IOBOX-8) " "$out/stderr"
run 0 "--eni without --esi-dir" --eni "$src/tests/data/eni/soem-sample-eni.xml"
has "sample warning" "soem-sample-eni.xml:41: warning: Pdo: PDO #x1A02 is assigned but the ENI does not describe its entries; it is made with none" "$out/stderr"
has "sample chain" "  slave   2 Sample device B " "$out/stderr"
sed 's|<Ccs>1</Ccs>|<Ccs>4</Ccs>|' "$eni" > "$out/bad.xml"
run 1 "bad ENI" --eni "$out/bad.xml"
line=$(grep -n '<Ccs>4</Ccs>' "$out/bad.xml" | cut -d: -f1)
[ "$(cat "$out/stderr")" = "ecat-slave: $out/bad.xml:$line: Ccs 4 is neither 1 nor 2" ] \
  || fail "bad ENI: $(cat "$out/stderr")"
run 2 "--eni with --esi" --eni "$eni" --esi "$vendor"
run 2 "--esi-dir without --eni" --esi-dir "$out/esi"

[ $status -eq 0 ] && echo "slave_select_cli: ok"
exit $status
