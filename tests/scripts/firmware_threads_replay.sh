#!/usr/bin/env bash
# ecat-slave --firmware-threads (issue 30 item 3, slave::Chain::
# set_firmware_threads): a capture of the project's master taking 200 drives
# through DC set-up to Op and moving them (ecat-master --in-process --dc
# --move --record) is replayed by ecat-slave on simulated time with the
# firmware on one thread and on two. The replies are byte for byte the same
# file, and the two-thread run did split its firmware (its statistics:
# split-runs > 0): the SYNC0 polls before the frames find all 200 drives due (at least
# Chain::kMinSplitSlaves).
# --firmware-threads auto gives the same replies whichever it chooses, and
# says what it chose and why. Then more threads than CPUs (a warning) and
# the option's errors.
# Usage: firmware_threads_replay.sh SRCDIR BUILDDIR   (exit 77 = skipped)
set -uo pipefail
build=${2:?builddir}
slave="$build/bin/ecat-slave"
master="$build/bin/ecat-master"
[ -x "$slave" ] && [ -x "$master" ] || { echo "skip: ecat-slave/ecat-master not built"; exit 77; }
out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
status=0
fail() { echo "FAIL: $*"; status=1; }
n=200

timeout 120 "$master" --in-process --count $n --dc --move --cycles 200 -q --record "$out/cap.pcap" > "$out/master" 2>&1 \
  || { echo "FAIL: ecat-master exit $?: $(tail -5 "$out/master")"; exit 1; }
for threads in 1 2; do
  timeout 120 "$slave" --pcap-in "$out/cap.pcap" --pcap-out "$out/out$threads.pcap" --count $n \
    --firmware-threads $threads > "$out/slave$threads" 2>&1 \
    || fail "--firmware-threads $threads: ecat-slave exit $?: $(tail -5 "$out/slave$threads")"
done
cmp -s "$out/out1.pcap" "$out/out2.pcap" || fail "the replies with two firmware threads differ from one thread's"
[ -s "$out/out1.pcap" ] || fail "no reply written"
grep -q "^frames .* lost 0 " "$out/slave1" || fail "one thread: $(grep '^frames' "$out/slave1")"
# Every drive in Op at the end, on both runs.
for threads in 1 2; do
  ops=$(grep -c '^  slave .* OP  ' "$out/slave$threads")
  [ "$ops" -eq $n ] || fail "--firmware-threads $threads: $ops of $n drives in Op"
done
splits=$(sed -n 's/^firmware-threads 2 split-runs \([0-9]*\) .*/\1/p' "$out/slave2")
[ -n "$splits" ] && [ "$splits" -gt 0 ] || fail "two threads never split: $(grep '^firmware-threads' "$out/slave2")"
grep -q '^firmware-threads' "$out/slave1" && fail "one thread prints a firmware-threads line"
echo "replayed: $(grep '^frames' "$out/slave1" | cut -d' ' -f1-2); two threads: $(grep '^firmware-threads' "$out/slave2")"

# auto on the 200 drives: 1 or 2 by the host (CPUs, the cores' round trip),
# the reason printed, the replies those of one thread.
timeout 120 "$slave" --pcap-in "$out/cap.pcap" --pcap-out "$out/auto.pcap" --count $n \
  --firmware-threads auto > "$out/slave-auto" 2>&1 \
  || fail "--firmware-threads auto: ecat-slave exit $?: $(tail -5 "$out/slave-auto")"
chosen=$(sed -n 's/^ecat-slave: --firmware-threads auto: \([12]\) (.*)$/\1/p' "$out/slave-auto")
[ -n "$chosen" ] || fail "auto printed no choice: $(head -5 "$out/slave-auto")"
cmp -s "$out/out1.pcap" "$out/auto.pcap" || fail "the replies with auto ($chosen) differ from one thread's"
if [ "$chosen" = 2 ]; then
  grep -q '^firmware-threads 2 split-runs' "$out/slave-auto" || fail "auto chose 2 but runs one thread"
  grep -q "auto: 2 ($n slaves, [0-9]* CPUs, a cache line between the cores and back in [0-9]* ns)" "$out/slave-auto" \
    || fail "auto 2 without its reason: $(grep auto "$out/slave-auto")"
fi
echo "auto: $(grep 'auto:' "$out/slave-auto")"

# More threads than CPUs: a warning (the helpers spin), and the run goes on
# (an empty capture: only its global header).
printf '\xd4\xc3\xb2\xa1\x02\x00\x04\x00\x00\x00\x00\x00\x00\x00\x00\x00\xff\xff\x00\x00\x01\x00\x00\x00' > "$out/empty.pcap"
many=$(( $(nproc) + 1 ))
if "$slave" --pcap-in "$out/empty.pcap" --pcap-out "$out/e.pcap" --firmware-threads $many > "$out/many" 2>&1; then
  grep -q "warning: --firmware-threads $many on [0-9]* CPU(s)" "$out/many" || fail "no warning for $many threads: $(cat "$out/many")"
else
  fail "--firmware-threads $many: exit $?: $(cat "$out/many")"
fi
"$slave" --pcap-in "$out/empty.pcap" --pcap-out "$out/e.pcap" --firmware-threads 1 > "$out/one" 2>&1
grep -q "warning" "$out/one" && fail "a warning with one thread: $(cat "$out/one")"
# auto with one slave: one thread, whatever the host.
"$slave" --pcap-in "$out/empty.pcap" --pcap-out "$out/e.pcap" --firmware-threads auto > "$out/auto1" 2>&1 \
  || fail "--firmware-threads auto, one slave: exit $?: $(cat "$out/auto1")"
grep -q "^ecat-slave: --firmware-threads auto: 1 (1 slave(s): fewer than the 192 a run needs to be split)$" "$out/auto1" \
  || fail "auto with one slave: $(cat "$out/auto1")"

# The option's range: 0, 65 and a word other than auto are refused by name,
# before anything runs.
for bad in 0 65 fast; do
  if "$slave" --pcap-in "$out/cap.pcap" --pcap-out "$out/bad.pcap" --firmware-threads $bad > "$out/bad" 2>&1; then
    fail "--firmware-threads $bad accepted"
  fi
  grep -q -- "--firmware-threads" "$out/bad" || fail "--firmware-threads $bad: error does not name the option: $(cat "$out/bad")"
done
# --firmware-threads-recheck (seconds, 0..3600, only with auto) and --spin-us
# (auto or 0..1,000,000): out of range or without auto, refused by name.
for bad in "--firmware-threads-recheck -1" "--firmware-threads-recheck 3601" "--firmware-threads-recheck 5 --firmware-threads 2" \
  "--spin-us -1" "--spin-us 1000001" "--spin-us often"; do
  # shellcheck disable=SC2086  # the option and its value are two words
  if "$slave" --pcap-in "$out/cap.pcap" --pcap-out "$out/bad.pcap" $bad > "$out/bad" 2>&1; then
    fail "$bad accepted"
  fi
  grep -q -- "${bad%% *}" "$out/bad" || fail "$bad: error does not name the option: $(cat "$out/bad")"
done
exit $status
