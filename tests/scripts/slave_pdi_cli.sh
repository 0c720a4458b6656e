#!/usr/bin/env bash
# Issue 18: ecat-slave --pdi without hardware - the errors a user meets
# first are clear and end the program (exit 1 / 2): a missing spidev, a
# device that is not SPI, a bad chip name, a bad --irq-gpio, --pdi with a
# network medium, more than one device.
# Usage: slave_pdi_cli.sh SRCDIR BUILDDIR   (exit 77 = skipped)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
slave="$build/bin/ecat-slave"
[ -x "$slave" ] || { echo "skip: $slave not built"; exit 77; }
dev="$src/xml/devices/generic-servo.xml"

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
status=0
fail() { echo "FAIL: $*"; status=1; }
expect() {  # rc message-substring args...
  local want=$1 text=$2; shift 2
  timeout 10 "$slave" "$@" > "$out/o" 2>&1
  local rc=$?
  [ "$rc" -eq "$want" ] || fail "$*: exit $rc, expected $want ($(head -c 300 "$out/o"))"
  grep -qF -- "$text" "$out/o" || fail "$*: no '$text' in: $(head -c 300 "$out/o")"
}

expect 1 "/nonexistent/spidev0.0: cannot open: No such file or directory" --device "$dev" --pdi lan9252:/nonexistent/spidev0.0
expect 1 "/dev/null: setting the SPI mode:" --device "$dev" --pdi et1100-spi:/dev/null
expect 1 "--pdi unknown PDI chip 'ax58100' (lan9252 or et1100-spi)" --device "$dev" --pdi ax58100:/dev/spidev0.0
expect 1 "--pdi 'lan9252': expected CHIP:SPIDEV" --device "$dev" --pdi lan9252
expect 1 "--pdi runs the firmware of exactly one device" --device "$dev" --device "$dev" --pdi lan9252:/dev/null
expect 1 "--irq-gpio /dev/gpiochip0:x: line is not a number" --device "$dev" --pdi lan9252:/dev/null --irq-gpio /dev/gpiochip0:x
expect 2 "excludes" --device "$dev" --pdi lan9252:/dev/null --udp 34980

[ $status -eq 0 ] && echo "ecat-slave --pdi errors: ok"
exit $status
