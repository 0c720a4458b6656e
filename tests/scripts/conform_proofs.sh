#!/usr/bin/env bash
# Issue 31 item 3: every case `ecat-conform --list` names has a failing-slave
# test. The proof files' lists (tests/master/conformance_proofs.hpp), printed
# by test_master's ConformanceProofs test, must equal the program's list.
# Usage: conform_proofs.sh SRCDIR BUILDDIR   (exit 77 = skipped)
set -uo pipefail
build=${2:?builddir}
conform="$build/bin/ecat-conform"
tests="$build/bin/test_master"
[ -x "$conform" ] || { echo "skip: $conform not built"; exit 77; }
[ -x "$tests" ] || { echo "skip: $tests not built"; exit 77; }

listed=$("$conform" --list | awk '{print $1}' | sort)
proven=$(ECAT_PRINT_PROVEN=1 "$tests" --gtest_filter='ConformanceProofs.*' | awk '$1 == "proven" {print $2}' | sort)
[ -n "$listed" ] || { echo "FAIL: ecat-conform --list printed nothing"; exit 1; }
missing=$(comm -23 <(echo "$listed") <(echo "$proven"))
extra=$(comm -13 <(echo "$listed") <(echo "$proven"))
status=0
[ -z "$missing" ] || { echo "FAIL: cases without a failing-slave test:"; echo "$missing"; status=1; }
[ -z "$extra" ] || { echo "FAIL: proven cases ecat-conform does not list:"; echo "$extra"; status=1; }
[ $status -eq 0 ] && echo "ok: $(echo "$listed" | wc -l) cases listed, each proven to fail on a broken slave"
exit $status
