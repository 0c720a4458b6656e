# Shared helpers of the end-to-end and fault scripts (tests/scripts/e2e_*.sh,
# fault_*.sh): two network namespaces joined by a veth pair, a slave started
# in one, cleaned up by an EXIT trap even when the script fails. Source it
# after setting src/build; every long command runs under `timeout`.
# shellcheck shell=bash disable=SC2034,SC2154  # $build, e2e_status: shared with the sourcing script

# Exit 77 (ctest: skipped) with the reason unless root and `ip netns` work.
e2e_require_netns() {
  if [ "$(id -u)" -ne 0 ]; then echo "skip: needs root to create network namespaces"; exit 77; fi
  command -v ip > /dev/null || { echo "skip: iproute2 (ip) not installed"; exit 77; }
  local probe="ecatprobe$$"
  if ! ip netns add "$probe" 2> /dev/null; then echo "skip: cannot create a network namespace"; exit 77; fi
  ip netns del "$probe"
}

# Exit 77 unless the named programs are built.
e2e_require_bins() {
  local b
  for b in "$@"; do
    [ -x "$build/bin/$b" ] || { echo "skip: $build/bin/$b not built"; exit 77; }
  done
}

E2E_NS_S=""; E2E_NS_M=""; E2E_TMP=""; E2E_PIDS=()
e2e_status=0
e2e_fail() { echo "FAIL: $*"; e2e_status=1; }

e2e_cleanup() {
  local p
  for p in "${E2E_PIDS[@]}"; do kill -TERM "$p" 2> /dev/null; done
  for p in "${E2E_PIDS[@]}"; do
    timeout 5 tail --pid="$p" -f /dev/null 2> /dev/null || kill -KILL "$p" 2> /dev/null
  done
  [ -n "$E2E_NS_S" ] && ip netns del "$E2E_NS_S" 2> /dev/null
  [ -n "$E2E_NS_M" ] && ip netns del "$E2E_NS_M" 2> /dev/null
  [ -n "$E2E_TMP" ] && rm -rf "$E2E_TMP"
  return 0
}

# Namespaces ecs<tag>$$ (slave side) and ecm<tag>$$ (master side) with a
# veth pair: "s0" in the slave namespace, "m0" in the master namespace.
# Interfaces carry no IP address; EtherCAT is raw Ethernet (EtherType 88A4h).
e2e_setup() {
  local tag=${1:-x}
  E2E_NS_S="ecs${tag}$$"; E2E_NS_M="ecm${tag}$$"
  E2E_TMP=$(mktemp -d)
  trap e2e_cleanup EXIT
  trap 'exit 130' INT TERM
  ip netns add "$E2E_NS_S" || { echo "FAIL: ip netns add"; exit 1; }
  ip netns add "$E2E_NS_M" || { echo "FAIL: ip netns add"; exit 1; }
  ip link add s0 netns "$E2E_NS_S" type veth peer name m0 netns "$E2E_NS_M" || { echo "FAIL: veth"; exit 1; }
  ip -n "$E2E_NS_S" link set s0 up && ip -n "$E2E_NS_M" link set m0 up || { echo "FAIL: link up"; exit 1; }
  ip -n "$E2E_NS_S" link set lo up; ip -n "$E2E_NS_M" link set lo up
}

# Starts ecat-slave in the slave namespace on s0 with the given extra
# arguments; stderr/stdout go to $E2E_TMP/$name.log. Sets E2E_SLAVE_PID.
e2e_start_slave() {
  local name=$1; shift
  timeout -s TERM "${E2E_SLAVE_TIMEOUT:-600}" ip netns exec "$E2E_NS_S" \
    "$build/bin/ecat-slave" --iface s0 "$@" > "$E2E_TMP/$name.log" 2>&1 &
  E2E_SLAVE_PID=$!
  E2E_PIDS+=("$E2E_SLAVE_PID")
  # Wait until it says it is up (the raw socket is open) or died.
  local i
  for i in $(seq 1 100); do
    grep -q "slave(s) on" "$E2E_TMP/$name.log" 2> /dev/null && return 0
    kill -0 "$E2E_SLAVE_PID" 2> /dev/null || break
    sleep 0.05
  done
  echo "FAIL: ecat-slave did not start:"; cat "$E2E_TMP/$name.log"
  return 1
}

# The PID of the ecat-slave program itself (child of timeout/ip netns exec).
e2e_slave_program_pid() {
  local p=$1 c
  for _ in 1 2 3; do
    c=$(pgrep -P "$p" | head -1)
    [ -z "$c" ] && break
    p=$c
  done
  echo "$p"
}

# Stops a started process with SIGTERM and waits (bounded) for it.
e2e_stop() {
  local p=$1
  kill -TERM "$p" 2> /dev/null
  timeout 10 tail --pid="$p" -f /dev/null 2> /dev/null || kill -KILL "$p" 2> /dev/null
  wait "$p" 2> /dev/null
}

# Runs ecat-master in the master namespace on m0; output to $E2E_TMP/$name.log
# and echoed with a prefix. Returns the master's exit code.
# E2E_MASTER_RT: a command prefix for the master (e.g. `chrt -f 50`), set by
# e2e_use_realtime.
E2E_MASTER_RT=()
e2e_master() {
  local name=$1 limit=$2; shift 2
  timeout -s KILL "$limit" ip netns exec "$E2E_NS_M" "${E2E_MASTER_RT[@]}" "$build/bin/ecat-master" --iface m0 "$@" \
    > "$E2E_TMP/$name.log" 2>&1
  local rc=$?
  sed "s/^/  [$name] /" "$E2E_TMP/$name.log"
  return $rc
}

# The statistics line of a master run ("cycles C lost L wkc-errors W ...").
e2e_cycle_line() { grep -m1 '^cycles ' "$E2E_TMP/$1.log"; }

# Checks the final statistics ecat-slave printed at exit (log NAME): every
# slave's SM watchdog expired at most once, i.e. only after the master had
# gone. The WKC cannot show this: an ESC counts SM2 writes in SafeOp too.
e2e_check_no_watchdog_during_run() {
  local name=$1 bad
  bad=$(grep -E '^ +slave +[0-9]+ ' "$E2E_TMP/$name.log" | grep -Ev ' watchdog [01] ')
  [ -z "$bad" ] || e2e_fail "$name: SM watchdog expired while the master ran: $bad"
  grep -E '^ +slave +[0-9]+ ' "$E2E_TMP/$name.log" | sed "s/^/  [$name at exit] /"
}

# Real-time scheduling where the kernel allows it (root with SCHED_FIFO): the
# master's cyclic loop at `chrt -f 50` and, through E2E_SLAVE_RT, the slave at
# `--rt-priority 40`, as real EtherCAT masters and slaves run. Without it, a
# DC slave on a loaded 2-core machine sees the master's SM2 writes miss
# several Sync0 periods and rightly leaves Op (0x001A/0x0034). E2E_NO_RT=1
# turns it off.
E2E_SLAVE_RT=()
e2e_use_realtime() {
  [ -z "${E2E_NO_RT:-}" ] || return 0
  chrt -f 50 true 2> /dev/null || return 0
  E2E_MASTER_RT=(chrt -f 50)
  E2E_SLAVE_RT=(--rt-priority 40)
}

# --- Live timing under load (issue 29 item 3; docs/e2e.md "Live timing under
# load"). These runs share two cores with builds and other tests: the kernel
# may stall the master or the slave process for tens of milliseconds. What
# the spec allows then, and only then:
#  - a DC slave whose SYNC0s came without new outputs counts them (1C32h:0Bh)
#    and leaves Op, or refuses Op at start-up, with 001Ah (sync error);
#  - a slave that got no process data for its SM watchdog time (100 ms)
#    leaves Op with 001Bh (SM watchdog), and counts the expiry;
#  - a frame the slave took from its socket later than --max-frame-age after
#    it arrived is lost on the wire (ecat-slave's "stale-dropped"): the
#    master retries it, and loses the cycle when every retry was late too.
# Such an outcome counts as "late" only with the evidence beside it: the
# master's own log shows it missed its cycle (cycle-jitter-max-us or
# start-up-cycle-gap-max-us above the period, skipped-periods or
# sync0-without-frame above 0), or the slave dropped stale frames. Everything
# else still fails at once: an AL code not allowed, a wrong WKC on a frame
# that came back, a lost frame the slave did not drop as stale, a wrong
# value, a state error while nobody was late. A late run is tried again (up
# to E2E_LIVE_ATTEMPTS, default 3); when every attempt was late the test
# passes with a NOTE, as nothing was shown wrong.
E2E_LIVE_ATTEMPTS=${E2E_LIVE_ATTEMPTS:-3}
E2E_VERDICT=""

# The last statistics block of a slave log: its "frames ..." line and the
# per-slave lines after it (printed at exit, on SIGUSR1 or by --stats).
e2e_slave_last_stats() {
  awk '/^frames / { block = "" } /^frames / || /^ +slave +[0-9]+ / { block = block $0 "\n" } END { printf "%s", block }' \
    "$E2E_TMP/$1.log" 2> /dev/null
}

# The stale-dropped count of a slave log's last statistics (0: none).
e2e_slave_stale() {
  local n
  n=$(e2e_slave_last_stats "$1" | sed -n 's/^frames .* stale-dropped \([0-9]*\).*/\1/p')
  echo "${n:-0}"
}

# The distinct AL codes other than 0x0000 in a slave log's last statistics.
e2e_slave_codes() {
  e2e_slave_last_stats "$1" | sed -n 's/.*AL code \(0x[0-9A-Fa-f]*\).*/\1/p' | sort -u | grep -v '^0x0000$' | tr '\n' ' '
}

# Asks a running ecat-slave (program PID, log NAME) for its statistics
# (SIGUSR1) and waits (bounded) until they are in the log.
e2e_slave_snapshot() {
  local name=$1 pid=$2 before i
  before=$(grep -c '^frames ' "$E2E_TMP/$name.log" 2> /dev/null)
  kill -USR1 "$pid" 2> /dev/null || return 1
  for i in $(seq 1 40); do
    [ "$(grep -c '^frames ' "$E2E_TMP/$name.log" 2> /dev/null)" -gt "$before" ] && { sleep 0.05; return 0; }
    sleep 0.05
  done
  return 1
}

# Whether a master log (NAME) shows the master itself missed its cycle of
# PERIOD_US microseconds.
e2e_master_was_late() {
  local log="$E2E_TMP/$1.log" period=$2 v
  v=$(sed -n 's/.*cycle-jitter-max-us \([0-9.]*\).*/\1/p' "$log" | head -1)
  [ -n "$v" ] && awk -v j="$v" -v p="$period" 'BEGIN { exit !(j > p) }' && return 0
  v=$(sed -n 's/^start-up-cycle-gap-max-us \([0-9.]*\)$/\1/p' "$log" | head -1)
  [ -n "$v" ] && awk -v j="$v" -v p="$period" 'BEGIN { exit !(j > p) }' && return 0
  grep -qE 'skipped-periods [1-9]' "$log" && return 0
  grep -qE 'sync0-without-frame [1-9]' "$log" && return 0
  return 1
}

# Judges one ecat-master run (log MASTER) against its slave (log SLAVE,
# whose last statistics - at exit, or a snapshot just after the run - are
# read), cycle PERIOD_US, exit code RC, and the AL codes the spec allows a
# late run (e.g. "0x001A 0x001B"). STALE_BEFORE: the slave's stale-dropped
# count before the run (a slave that serves several runs; default 0);
# WD_MAX: SM watchdog expiries a slave may show (default 1: the one after the
# master has gone). Returns 0 (passed), 2 (late, allowed: try again) or 1
# (failed); sets E2E_VERDICT to one line saying why. PARTIAL: exchanges of a
# two-port master that ended with one port's frame only (the ring's
# primary-down and secondary-down counts; default 0): when master
# or slave was late, a frame that came back on one port before the other
# port's frame is taken as the reply (as SOEM's ecx_waitinframe_red does),
# so up to that many cycles may carry the WKC of part of the ring.
e2e_judge_master_run() {
  local mlog=$1 slog=$2 period=$3 rc=$4 allowed=$5 stale_before=${6:-0} wd_max=${7:-1} partial=${8:-0}
  local stale codes code late=no line lost wkc state wd
  stale=$(( $(e2e_slave_stale "$slog") - stale_before ))
  codes=$(e2e_slave_codes "$slog")
  if e2e_master_was_late "$mlog" "$period" || [ "$stale" -gt 0 ]; then late=yes; fi
  wd=$(e2e_slave_last_stats "$slog" | sed -n 's/^ .* watchdog \([0-9]*\) .*/\1/p' | awk -v m="$wd_max" '$1 > m' | wc -l)
  if [ "$rc" -eq 0 ] && [ "$wd" -eq 0 ]; then
    E2E_VERDICT="passed (stale-dropped $stale)"
    return 0
  fi
  for code in $codes; do
    case " $allowed " in
      *" $code "*) ;;
      *) E2E_VERDICT="AL code $code is not one the spec allows a late master ($allowed)"; return 1 ;;
    esac
  done
  line=$(grep -m1 '^cycles ' "$E2E_TMP/$mlog.log")
  if [ -z "$line" ]; then
    # The start-up failed: only a refusal with an allowed code, or a frame
    # lost while the slave dropped stale ones, and only when someone was late.
    local refused
    refused=$(sed -n 's/.* refused, AL status code \(0x[0-9A-Fa-f]*\).*/\1/p' "$E2E_TMP/$mlog.log" | head -1)
    if [ -n "$refused" ]; then
      case " $allowed " in
        *" $refused "*) ;;
        *) E2E_VERDICT="start-up refused with $refused, not one the spec allows a late master ($allowed)"; return 1 ;;
      esac
    elif ! grep -qiE 'timeout|timed out|no reply|lost' "$E2E_TMP/$mlog.log" || [ "$stale" -le 0 ]; then
      E2E_VERDICT="start-up failed: $(grep -m1 -o 'ecat-master: .*' "$E2E_TMP/$mlog.log")"
      return 1
    fi
    if [ "$late" = no ]; then
      E2E_VERDICT="start-up failed ($(grep -m1 -o 'ecat-master: .*' "$E2E_TMP/$mlog.log")) while neither master nor slave was late"
      return 1
    fi
    E2E_VERDICT="late start-up: $(grep -m1 -o 'ecat-master: .*' "$E2E_TMP/$mlog.log" | sed 's/^ecat-master: //'); $(grep -m1 '^start-up-cycle-gap-max-us' "$E2E_TMP/$mlog.log"), slave stale-dropped $stale"
    return 2
  fi
  lost=$(sed -n 's/.* lost \([0-9]*\) .*/\1/p' <<< "$line")
  wkc=$(sed -n 's/.* wkc-errors \([0-9]*\) .*/\1/p' <<< "$line")
  state=$(sed -n 's/.* state-errors \([0-9]*\) .*/\1/p' <<< "$line")
  # A wrong WKC is explained only by lateness: a slave that left Op with an
  # allowed code (a SafeOp slave takes no outputs: its LRW counts 1, not 3)
  # or an exchange that ended with one port's frame (PARTIAL).
  if [ "${wkc:-1}" != 0 ] && { [ "$late" = no ] || { [ "${wkc:-1}" -gt "$partial" ] &&
    { [ "${state:-0}" = 0 ] || [ -z "$codes" ]; }; }; }; then
    E2E_VERDICT="wrong WKC on $wkc cycles (late: $late, one-port exchanges: $partial, AL codes: ${codes:-none}): $line"
    return 1
  fi
  if [ "${lost:-1}" != 0 ] && [ "$stale" -le 0 ]; then
    E2E_VERDICT="$lost frames lost that the slave did not drop as stale: $line"
    return 1
  fi
  if [ "$late" = no ]; then
    E2E_VERDICT="failed while neither master nor slave was late (exit $rc, slaves with SM watchdog expiries during the run: $wd): $line"
    return 1
  fi
  if [ "${state:-0}" = 0 ] && [ "${lost:-0}" = 0 ] && [ "${wkc:-0}" = 0 ] && [ "$wd" -eq 0 ]; then
    E2E_VERDICT="exit $rc with no lost frame, WKC error or state error: $(grep -m1 -o 'ecat-master: .*' "$E2E_TMP/$mlog.log")"
    return 1
  fi
  E2E_VERDICT="late run (lost $lost, wkc-errors $wkc, state-errors $state, AL codes ${codes:-none}, slave stale-dropped $stale; master $(sed -n 's/.*\(cycle-jitter-max-us [0-9.]*\).*/\1/p' <<< "$line"))"
  return 2
}

# An ecat-master run (log NAME, time limit LIMIT, then its arguments)
# against a slave that keeps running (program PID, log SLAVE), judged by
# e2e_judge_master_run from a statistics snapshot taken right after it; a
# late run is run again (e2e_live_phase). ALLOWED codes in E2E_ALLOWED
# (default "0x001B": free run), watchdog expiries not judged (the slave
# serves several runs).
E2E_ALLOWED="0x001B"
e2e_master_on_running_slave() {
  local name=$1 limit=$2 slave=$3 pid=$4; shift 4
  local before rc
  e2e_slave_snapshot "$slave" "$pid"
  before=$(e2e_slave_stale "$slave")
  e2e_master "$name" "$limit" "$@"
  rc=$?
  e2e_slave_snapshot "$slave" "$pid"
  e2e_judge_master_run "$name" "$slave" 1000 "$rc" "$E2E_ALLOWED" "$before" 1000000
}

# Runs one live phase up to E2E_LIVE_ATTEMPTS times. PHASE (called with the
# remaining arguments) is a function that starts the slave, runs the master, stops the slave and returns what
# e2e_judge_master_run returned (0/1/2), with E2E_VERDICT set. A failure
# fails the test; a late attempt is tried again; all attempts late: a NOTE.
e2e_live_phase() {
  local label=$1 phase=$2 try rc
  shift 2
  for try in $(seq 1 "$E2E_LIVE_ATTEMPTS"); do
    E2E_VERDICT=""
    "$phase" "$@"
    rc=$?
    case $rc in
      0) echo "$label (attempt $try): $E2E_VERDICT"; return 0 ;;
      2) echo "$label (attempt $try): $E2E_VERDICT - allowed when late, trying again" ;;
      *) e2e_fail "$label (attempt $try): $E2E_VERDICT"; return 1 ;;
    esac
  done
  echo "NOTE: $label: every one of $E2E_LIVE_ATTEMPTS attempts was late (host stalls); nothing shown wrong, not a failure"
  return 0
}
