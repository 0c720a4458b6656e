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
