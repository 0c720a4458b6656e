#!/usr/bin/env bash
# ecat-esigen end to end: exit codes (0 ok, 1 error, 2 bad options), outputs
# valid against the ETG ESI schema (1.14 and 1.17) and the device schema, the
# C++ tables compile, ESI -> device XML -> ESI is stable, and a failing run
# leaves no output file behind (and an existing one untouched).
# Usage: esigen_cli.sh SRCDIR BUILDDIR   (exit 77 = skipped)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
gen="$build/bin/ecat-esigen"
[ -x "$gen" ] || { echo "skip: $gen not built"; exit 77; }
command -v xmllint > /dev/null || { echo "skip: xmllint not installed"; exit 77; }
# shellcheck source=lib/esi_schemas.sh
. "$src/tests/scripts/lib/esi_schemas.sh" "$src"
[ ${#esi_schemas[@]} -gt 0 ] || { echo "skip: $esi_schema_why"; exit 77; }

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
status=0
fail() { echo "FAIL: $*"; status=1; }
expect_rc() {  # expected-rc description command...
  local want=$1 what=$2; shift 2
  "$@" > "$out/stdout" 2> "$out/stderr"
  local rc=$?
  [ "$rc" -eq "$want" ] || fail "$what: exit $rc, expected $want ($(head -c 300 "$out/stderr"))"
}
valid_esi() {
  local schema
  for schema in "${esi_schemas[@]}"; do
    xmllint --noout --schema "$schema" "$1" 2> "$out/lint" || fail "$1 invalid ($schema): $(head -3 "$out/lint")"
  done
}

# 1. Built-in default device: every output.
expect_rc 0 "default device" "$gen" --esi "$out/default.xml" --sii "$out/default.bin" \
  --cpp "$out/default.hpp" --device-xml "$out/default.device.xml"
valid_esi "$out/default.xml"
[ "$(stat -c %s "$out/default.bin")" -eq 2048 ] || fail "default SII is not 2048 bytes"
xmllint --noout --schema "$src/xml/schema/device.xsd" "$out/default.device.xml" 2> /dev/null \
  || fail "device XML does not match xml/schema/device.xsd"
if command -v c++ > /dev/null; then
  echo '#include "default.hpp"' > "$out/default_check.cpp"
  echo 'static_assert(ecat_device::kObjects.size() > 0);' >> "$out/default_check.cpp"
  c++ -std=c++20 -Wall -Wextra -Wpedantic -Werror -fsyntax-only "$out/default_check.cpp" \
    || fail "generated C++ tables do not compile"
fi
ls -A "$out" | grep -q '\.tmp-' && fail "temporary files left behind"

# 2. Determinism: a second run gives the same bytes.
expect_rc 0 "second run" "$gen" --esi "$out/default2.xml" --sii "$out/default2.bin"
cmp -s "$out/default.xml" "$out/default2.xml" || fail "ESI differs between runs"
cmp -s "$out/default.bin" "$out/default2.bin" || fail "SII differs between runs"

# 3. Every shipped device gives a schema-valid ESI.
for dev in "$src"/xml/devices/*.xml; do
  name=$(basename "$dev" .xml)
  expect_rc 0 "$name" "$gen" "$dev" --esi "$out/$name.esi.xml" --sii "$out/$name.bin"
  valid_esi "$out/$name.esi.xml"
done

# 4. Vendor ESI import: device XML, then the device XML gives the same ESI again.
vendor="$src/tests/data/esi/vendor-drives.xml"
expect_rc 0 "from-esi" "$gen" --from-esi "$vendor" --product-code '#x1001' --revision 0x20000 \
  --device-xml "$out/v.device.xml" --esi "$out/v1.xml"
grep -q "warning: Slots: no module is configured by the slots' defaults" "$out/stderr" || fail "import warnings missing"
valid_esi "$out/v1.xml"
expect_rc 0 "device xml -> esi" "$gen" "$out/v.device.xml" --esi "$out/v2.xml"
expect_rc 0 "esi -> esi" "$gen" --from-esi "$out/v2.xml" --device-xml "$out/v2.device.xml" --esi "$out/v3.xml"
cmp -s "$out/v2.xml" "$out/v3.xml" || fail "ESI -> model -> device XML -> ESI not stable"

# 4b. --strict: the import's warnings (repairs, elements not modelled) are errors.
expect_rc 1 "--strict with warnings" "$gen" --from-esi "$vendor" --product-code '#x1001' --revision 0x20000 \
  --strict --device-xml "$out/strict.xml"
grep -qE 'vendor-drives.xml:[0-9]+: .*\(--strict: import warnings are errors\)$' "$out/stderr" \
  || fail "--strict error is not 'file:line: ... (--strict ...)': $(tail -1 "$out/stderr")"
[ -e "$out/strict.xml" ] && fail "a --strict failure wrote its output"
expect_rc 2 "--strict without --from-esi" "$gen" --strict --esi "$out/x.xml"

# 5. Errors and bad options.
expect_rc 2 "unknown option" "$gen" --bogus
expect_rc 2 "no output" "$gen"
expect_rc 2 "device and --from-esi" "$gen" "$src/xml/devices/generic-servo.xml" --from-esi "$vendor" --esi "$out/x.xml"
expect_rc 2 "--revision without --from-esi" "$gen" --revision 1 --esi "$out/x.xml"
expect_rc 2 "bad namespace" "$gen" --cpp "$out/x.hpp" --cpp-namespace "9bad::x"
expect_rc 0 "nested namespace" "$gen" --cpp "$out/ns.hpp" --cpp-namespace "gen::servo_1"
expect_rc 2 "bad product code" "$gen" --from-esi "$vendor" --product-code zz --esi "$out/x.xml"
expect_rc 1 "missing device" "$gen" "$out/none.xml" --esi "$out/x.xml"
grep -q "none.xml" "$out/stderr" || fail "missing-device error does not name the file"
expect_rc 1 "unknown product" "$gen" --from-esi "$vendor" --product-code 77 --esi "$out/x.xml"
grep -qE '^.*vendor-drives.xml:[0-9]+: no device with product code #x0000004D' "$out/stderr" \
  || fail "unknown-product error is not 'file:line: message': $(cat "$out/stderr")"
[ "$(wc -l < "$out/stderr")" -eq 1 ] || fail "error is not one line"
[ -e "$out/x.xml" ] && fail "a failed run wrote x.xml"

# 6. Atomic output: SII does not fit -> exit 1, no ESI written, old file untouched.
echo "old" > "$out/keep.xml"
expect_rc 1 "SII too large" "$gen" "$src/tests/data/esi/eeprom-too-small.xml" \
  --esi "$out/keep.xml" --sii "$out/keep.bin"
[ "$(cat "$out/keep.xml")" = "old" ] || fail "failed run replaced keep.xml"
[ -e "$out/keep.bin" ] && fail "failed run wrote keep.bin"
# One output not writable -> the others are not written either.
expect_rc 1 "unwritable output" "$gen" --esi "$out/no-such-dir/a.xml" --sii "$out/partial.bin"
[ -e "$out/partial.bin" ] && fail "partial.bin written although another output failed"
ls -A "$out" | grep -q '\.tmp-' && fail "temporary files left behind after failures"

# 7. Multi-device files (issue 14 item 5): --list, one stable line per device
# (type, product code, revision, name; tab-separated), and the selection by
# product code, revision and type name; no match or several: an error listing
# the candidates.
expect_rc 0 "--list" "$gen" --from-esi "$vendor" --list
printf 'EXD-100\t#x00001001\t#x00010000\tEXD-100 servo (rev 1)\nEXD-100\t#x00001001\t#x00020000\tEXD-100 servo\nEXIO-8\t#x00001001\t#x00000001\tEXIO-8 digital I/O\n' > "$out/list.want"
cmp -s "$out/stdout" "$out/list.want" || fail "--list output: $(cat -A "$out/stdout")"
[ -s "$out/stderr" ] && fail "--list wrote to stderr: $(cat "$out/stderr")"
expect_rc 2 "--list with a selection" "$gen" --from-esi "$vendor" --list --type EXD-100
expect_rc 2 "--type without --from-esi" "$gen" --type EXD-100 --esi "$out/x.xml"
expect_rc 1 "ambiguous product code" "$gen" --from-esi "$vendor" --product-code '#x1001' --esi "$out/x.xml"
grep -qxF "$vendor:25: 3 devices match product code #x00001001; add --product-code, --revision or --type to choose one of: EXD-100 (product code #x00001001, revision #x00010000, line 26); EXD-100 (product code #x00001001, revision #x00020000, line 36); EXIO-8 (product code #x00001001, revision #x00000001, line 731)" "$out/stderr" \
  || fail "ambiguous selection message: $(cat "$out/stderr")"
expect_rc 1 "ambiguous type" "$gen" --from-esi "$vendor" --type EXD-100 --esi "$out/x.xml"
grep -qF ": 2 devices match type 'EXD-100';" "$out/stderr" || fail "ambiguous type message: $(cat "$out/stderr")"
expect_rc 1 "missing type" "$gen" --from-esi "$vendor" --type EXD-200 --esi "$out/x.xml"
grep -qxF "$vendor:25: no device with type 'EXD-200' in this file (it has: EXD-100 (product code #x00001001, revision #x00010000, line 26); EXD-100 (product code #x00001001, revision #x00020000, line 36); EXIO-8 (product code #x00001001, revision #x00000001, line 731))" "$out/stderr" \
  || fail "missing type message: $(cat "$out/stderr")"
expect_rc 0 "type and revision" "$gen" --from-esi "$vendor" --type EXD-100 --revision '#x10000' --device-xml "$out/sel.device.xml"
grep -q 'name="EXD-100 servo (rev 1)"' "$out/sel.device.xml" || fail "--type/--revision took another device"
expect_rc 0 "type alone" "$gen" --from-esi "$vendor" --type EXIO-8 --device-xml "$out/io.device.xml"
grep -q 'productCode="#x00001001" revision="#x00000001"' "$out/io.device.xml" || fail "--type EXIO-8 took another device"
expect_rc 0 "no selection" "$gen" --from-esi "$vendor" --device-xml "$out/first.device.xml"
grep -qF "$vendor:26: warning: Device: the file describes 3 devices; the first is taken" "$out/stderr" \
  || fail "no warning when the first of several devices is taken"

[ $status -eq 0 ] && echo "esigen_cli: ok"
exit $status
