#!/usr/bin/env bash
# ecat-slave --foe-password / --foe-busy against ecat-conform over UDP (issue
# 31): the Elmo Gold twin (its ESI lists FoE) with a state directory, its
# files behind a password and each FoE request answered BUSY twice; the FoE
# cases told so (--foe-password, --foe-busy, --foe-denied) all pass. Without
# --foe-busy on the slave, foe.busy_then_complete fails ("no BUSY"); with
# another password on the slave, the writes are refused (0x800A) and skip.
# Usage: foe_cli.sh SRCDIR BUILDDIR   (exit 77 = skipped)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
slave="$build/bin/ecat-slave"
conform="$build/bin/ecat-conform"
[ -x "$slave" ] && [ -x "$conform" ] || { echo "skip: ecat-slave/ecat-conform not built"; exit 77; }
elmo="$src/tests/data/esi-vendor/elmo-gold-ecat.xml"

tmp=$(mktemp -d)
slave_pid=""
cleanup() { [ -n "$slave_pid" ] && kill "$slave_pid" 2> /dev/null; wait 2> /dev/null; rm -rf "$tmp"; }
trap cleanup EXIT
status=0
fail() { echo "FAIL: $*"; status=1; }
port=$((20000 + ($$ + 11) % 20000))

start_slave() {  # extra ecat-slave options
  [ -n "$slave_pid" ] && { kill "$slave_pid"; wait "$slave_pid" 2> /dev/null; }
  rm -rf "$tmp/state"; mkdir -p "$tmp/state"
  "$slave" --udp "127.0.0.1:$port" --esi "$elmo" --state-dir "$tmp/state" "$@" > "$tmp/slave.log" 2>&1 &
  slave_pid=$!
  sleep 0.5
  kill -0 "$slave_pid" 2> /dev/null || { fail "ecat-slave $*: $(head -5 "$tmp/slave.log")"; return 1; }
}
conform() {  # log-name extra ecat-conform options
  local log=$1; shift
  "$conform" --udp "127.0.0.1:$port" --filter 'foe.*' --foe-denied .denied "$@" > "$tmp/$log" 2>&1
}
verdict() {  # log case -> PASS/FAIL/SKIP
  awk -v c="$2" '$1 == c {print $2}' "$tmp/$1"
}

# Bad values are usage errors.
"$slave" --foe-busy 70000 --pcap-in /dev/null > "$tmp/bad.log" 2>&1
[ $? -ne 0 ] && grep -q -- '--foe-busy' "$tmp/bad.log" || fail "--foe-busy 70000 accepted: $(head -3 "$tmp/bad.log")"
"$slave" --foe-password nope --pcap-in /dev/null > "$tmp/bad.log" 2>&1
[ $? -ne 0 ] && grep -q -- '--foe-password' "$tmp/bad.log" || fail "--foe-password nope accepted: $(head -3 "$tmp/bad.log")"

if start_slave --foe-password 0xC0FFEE --foe-busy 2; then
  conform all.log --foe-password 0xC0FFEE --foe-busy || fail "FoE cases with password and BUSY: $(cat "$tmp/all.log")"
  for c in foe.write_ack_numbers foe.read_back foe.read_packet_numbers foe.read_not_found foe.access_denied \
           foe.wrong_password foe.busy_then_complete; do
    [ "$(verdict all.log "$c")" = PASS ] || fail "$c: $(grep -F "$c" "$tmp/all.log")"
  done
fi
if start_slave --foe-password 0xC0FFEE; then
  conform nobusy.log --foe-password 0xC0FFEE --foe-busy
  [ "$(verdict nobusy.log foe.busy_then_complete)" = FAIL ] && grep -q 'no BUSY' "$tmp/nobusy.log" \
    || fail "no --foe-busy on the slave: $(grep -F busy "$tmp/nobusy.log")"
  conform otherpw.log --foe-password 0xC0FFEF
  [ "$(verdict otherpw.log foe.write_ack_numbers)" = SKIP ] && grep -q 'ERR 0x800A' "$tmp/otherpw.log" \
    || fail "another password: $(grep -F write_ack "$tmp/otherpw.log")"
fi
[ $status -eq 0 ] && echo "ok: ecat-slave --foe-password/--foe-busy, every FoE case as expected over UDP"
exit $status
