#!/usr/bin/env bash
# Issue 18: ecat-conform's whole suite against every shipped device with the
# firmware reaching its ESC over SPI framing to an emulated LAN9252 and an
# emulated ET1100 SPI slave (--pdi), plus the option errors (exit 2).
# Usage: conform_spi_pdi.sh SRCDIR BUILDDIR   (exit 77 = skipped)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
conform="$build/bin/ecat-conform"
[ -x "$conform" ] || { echo "skip: $conform not built"; exit 77; }

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
status=0
fail() { echo "FAIL: $*"; status=1; }

for device in "$src"/xml/devices/*.xml; do
  for chip in lan9252 et1100-spi; do
    name="$(basename "$device" .xml)-$chip"
    if ! "$conform" --device "$device" --pdi "$chip" --junit "$out/$name.xml" > "$out/$name.txt" 2>&1; then
      # Couplers and junctions have no PDI: there is no firmware to put behind SPI.
      if grep -q "the device has no PDI" "$out/$name.txt"; then echo "skip: $name: no PDI"; continue; fi
      fail "$name: $(grep -E 'FAIL|tests,' "$out/$name.txt" | head -5)"
      continue
    fi
    grep -q "firmware over SPI to an emulated" "$out/$name.txt" || fail "$name: not run over SPI"
    grep -q " 0 failed" "$out/$name.txt" || fail "$name: $(tail -1 "$out/$name.txt")"
    echo "ok: $name: $(tail -1 "$out/$name.txt")"
  done
done

"$conform" --device "$src/xml/devices/generic-servo.xml" --pdi ax58100 > "$out/bad" 2>&1
[ $? -eq 2 ] || fail "--pdi ax58100: expected exit 2"
grep -q "unknown PDI chip 'ax58100' (lan9252 or et1100-spi)" "$out/bad" || fail "--pdi ax58100: $(cat "$out/bad")"
"$conform" --iface lo --pdi lan9252 > "$out/bad" 2>&1
[ $? -ne 0 ] || fail "--pdi without --device accepted"

[ $status -eq 0 ] && echo "conform over SPI PDI: ok"
exit $status
