#!/usr/bin/env bash
# Issue 31 item 3: every case `ecat-conform --list` names (with --device, so
# the device-file cases esi.* too) has a failing-slave test. The proof files' lists (tests/master/conformance_proofs.hpp), printed
# by test_master's ConformanceProofs test, must equal the program's list.
# Usage: conform_proofs.sh SRCDIR BUILDDIR   (exit 77 = skipped)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
conform="$build/bin/ecat-conform"
tests="$build/bin/test_master"
[ -x "$conform" ] || { echo "skip: $conform not built"; exit 77; }
[ -x "$tests" ] || { echo "skip: $tests not built"; exit 77; }

servo="$src/xml/devices/generic-servo.xml"
listed=$("$conform" --device "$servo" --list | awk '{print $1}' | sort)
proven=$(ECAT_PRINT_PROVEN=1 "$tests" --gtest_filter='ConformanceProofs.*' | awk '$1 == "proven" {print $2}' | sort)
[ -n "$listed" ] || { echo "FAIL: ecat-conform --list printed nothing"; exit 1; }
missing=$(comm -23 <(echo "$listed") <(echo "$proven"))
extra=$(comm -13 <(echo "$listed") <(echo "$proven"))
status=0
[ -z "$missing" ] || { echo "FAIL: cases without a failing-slave test:"; echo "$missing"; status=1; }
[ -z "$extra" ] || { echo "FAIL: proven cases ecat-conform does not list:"; echo "$extra"; status=1; }
# The esi.* cases from the command line: a broken copy of the device file
# given with --esi (FoE announced, the slave has none) fails, the shipped one passes.
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
sed 's/coe="true" foe="false"/coe="true" foe="true"/' "$servo" > "$tmp/servo-foe.xml"
if ! "$conform" --device "$servo" --esi "$servo" --filter 'esi.*' > "$tmp/ok.log"; then
  echo "FAIL: esi.* on the shipped file"; cat "$tmp/ok.log"; status=1
fi
"$conform" --device "$servo" --esi "$tmp/servo-foe.xml" --filter 'esi.mailbox_matches_sii' > "$tmp/broken.log"
rc=$?
if [ $rc -ne 1 ] || ! grep -q 'esi.mailbox_matches_sii.*FAIL' "$tmp/broken.log"; then
  echo "FAIL: --esi with FoE announced: exit $rc"; cat "$tmp/broken.log"; status=1
fi
[ $status -eq 0 ] && echo "ok: $(echo "$listed" | wc -l) cases listed, each proven to fail on a broken slave"
exit $status
