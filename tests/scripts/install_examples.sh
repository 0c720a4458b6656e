#!/usr/bin/env bash
# The installed package as a user sees it (issue 17): `cmake --install` into a
# staging prefix, then, against that prefix only (not the source tree):
#  - the layout: programs, libraries, headers, CMake package, pkg-config file,
#    device files, man pages; `--version` of every program;
#  - a file including every installed header compiles on the installed
#    include path alone (no installed header needs a non-installed one);
#  - a pkg-config build links and runs;
#  - each example in examples/ is configured out of tree with
#    find_package(ecatslave), built and run: the DIO16 slave (in-process, then
#    over UDP on 127.0.0.1 brought to Op by the installed ecat-master), the
#    GoogleTest fixture of master code, and the ecatslave_generate() tables.
# Usage: install_examples.sh SRCDIR BUILDDIR   (exit 77 = skipped)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
[ -x "$build/bin/ecat-esigen" ] || { echo "skip: $build not built"; exit 77; }

tmp=$(mktemp -d /tmp/ecat-install.XXXXXX)
slave_pid=""
cleanup() {
  [ -n "$slave_pid" ] && kill "$slave_pid" 2> /dev/null
  rm -rf "$tmp"
}
trap cleanup EXIT
status=0
fail() { echo "FAIL: $*"; status=1; }
cache() { sed -n "s/^$1:[A-Z]*=//p" "$build/CMakeCache.txt"; }

prefix="$tmp/prefix"
if ! cmake --install "$build" --prefix "$prefix" > "$tmp/install.log" 2>&1; then
  cat "$tmp/install.log"; echo "FAIL: cmake --install"; exit 1
fi
version=$(sed -n 's/^CMAKE_PROJECT_VERSION:[A-Z]*=//p' "$build/CMakeCache.txt")
libdir=$(cache CMAKE_INSTALL_LIBDIR)
cxx=$(cache CMAKE_CXX_COMPILER)
launcher=$(cache CMAKE_CXX_COMPILER_LAUNCHER)

# --- layout ------------------------------------------------------------------------
for f in include/ecatslave/slave/chain.hpp include/ecatslave/coe/object_store.hpp \
         include/ecatslave/esc/esc.hpp include/ecatslave/ds402/drive.hpp \
         include/ecatslave/master/master.hpp include/ecatslave/esi/device_loader.hpp \
         "$libdir/cmake/ecatslave/ecatslaveConfig.cmake" "$libdir/cmake/ecatslave/ecatslaveTargets.cmake" \
         "$libdir/cmake/ecatslave/ecatslaveGenerate.cmake" "$libdir/pkgconfig/ecatslave.pc" \
         share/ecatslave/devices/generic-servo.xml share/ecatslave/devices/simtach-rse.xml \
         share/ecatslave/profiles/cia402.xml share/ecatslave/schema/device.xsd \
         include/ecatslave/control/request_handler.hpp lib/python3/dist-packages/ecatslave/client.py \
         lib/python3/dist-packages/ecatslave/pytest_plugin.py; do
  [ -f "$prefix/$f" ] || fail "not installed: $f"
done
# The Python package imports from the installed place alone (docs/control.md).
if command -v python3 > /dev/null; then
  (cd "$tmp" && PYTHONPATH="$prefix/lib/python3/dist-packages" python3 -c 'import ecatslave.client, ecatslave.network') ||
    fail "the installed ecatslave Python package does not import"
fi
for layer in esc coe ds402 esi od transport master slave control; do
  ls "$prefix/$libdir"/libecatslave_"$layer".* > /dev/null 2>&1 || fail "no library libecatslave_$layer"
done
# Internal headers stay out (docs/api.md): one of each kind.
for f in esi/device_parse.hpp esc/datagram_engine.hpp coe/sdo_command.hpp; do
  [ ! -e "$prefix/include/ecatslave/$f" ] || fail "internal header installed: $f"
done
for p in ecat-esigen ecat-slave ecat-master ecat-conform; do
  [ -x "$prefix/bin/$p" ] || { fail "not installed: bin/$p"; continue; }
  got=$("$prefix/bin/$p" --version 2>&1)
  [ "$got" = "$p (ecatslave) $version" ] || fail "$p --version printed '$got'"
  if [ -n "$(cache HELP2MAN_PROGRAM | grep -v NOTFOUND)" ]; then
    page="$prefix/share/man/man1/$p.1.gz"
    if [ -f "$page" ]; then
      # roff escapes the dashes of options: \-\-help
      grep -qF -- '\-\-help' <<< "$(zcat "$page")" || fail "$p.1 does not list --help"
      grep -q "^\.TH .*\"ecatslave $version\"" <<< "$(zcat "$page")" || fail "$p.1 does not carry version $version"
    else
      fail "no man page $p.1.gz"
    fi
  fi
done
grep -qF -- 'state\-dir' <<< "$(zcat "$prefix/share/man/man1/ecat-slave.1.gz" 2> /dev/null)" \
  || fail "ecat-slave.1 lacks the --state-dir option"

# --- every installed header, with only the installed include path ------------------
(cd "$prefix/include/ecatslave" && find . -name '*.hpp' | sort | sed 's|^\./\(.*\)|#include "\1"|') \
  > "$tmp/all_headers.cpp"
echo 'int main() { return 0; }' >> "$tmp/all_headers.cpp"
"$cxx" -std=c++20 -fsyntax-only -Wall -Wextra -I "$prefix/include/ecatslave" "$tmp/all_headers.cpp" \
  > "$tmp/headers.log" 2>&1 || fail "installed headers do not compile on the installed include path: $(head -5 "$tmp/headers.log")"
n_headers=$(grep -c '#include' "$tmp/all_headers.cpp")

# --- pkg-config ------------------------------------------------------------------------
cat > "$tmp/pc.cpp" <<'CPP'
#include <cstdio>
#include "esi/device_loader.hpp"
int main() {
  auto d = ecat::esi::load_default_device();
  if (!d) return 1;
  std::printf("%s\n", d->identity.name.c_str());
  return 0;
}
CPP
if flags=$(PKG_CONFIG_PATH="$prefix/$libdir/pkgconfig" pkg-config --cflags --libs ecatslave 2> "$tmp/pc.err"); then
  # shellcheck disable=SC2086
  if $launcher "$cxx" "$tmp/pc.cpp" -o "$tmp/pc" $flags > "$tmp/pc.log" 2>&1; then
    got=$(LD_LIBRARY_PATH="$prefix/$libdir" "$tmp/pc")
    [ "$got" = "Generic servo" ] || fail "pkg-config program printed '$got'"
  else
    fail "pkg-config build: $(head -5 "$tmp/pc.log")"
  fi
else
  fail "pkg-config ecatslave: $(cat "$tmp/pc.err")"
fi

# --- examples, out of tree against the prefix ---------------------------------------------
configure_build() {  # name
  local dir="$tmp/$1"
  cmake -S "$src/examples/$1" -B "$dir" -G Ninja -DCMAKE_PREFIX_PATH="$prefix" \
        -DCMAKE_CXX_COMPILER="$cxx" ${launcher:+-DCMAKE_CXX_COMPILER_LAUNCHER="$launcher"} \
        > "$dir.log" 2>&1 && cmake --build "$dir" >> "$dir.log" 2>&1
  local rc=$?
  [ "$rc" -eq 0 ] || { tail -30 "$dir.log"; fail "example $1 did not build"; }
  return $rc
}

if configure_build dio16-slave; then
  if out=$("$tmp/dio16-slave/dio16-slave" "$src/examples/dio16-slave/dio16.xml" 2>&1); then
    grep -q "DIO16 in Op: 2 output bytes, 2 input bytes" <<< "$out" || fail "dio16 in-process: $out"
    grep -q "walking one over 16 channels read back" <<< "$out" || fail "dio16 in-process: $out"
  else
    fail "dio16 in-process run: $out"
  fi
  # Over UDP on loopback, brought to Op by the installed ecat-master.
  port=$((20000 + $$ % 20000))
  "$tmp/dio16-slave/dio16-slave" "$src/examples/dio16-slave/dio16.xml" --udp "$port" > "$tmp/slave.out" 2>&1 &
  slave_pid=$!
  for _ in $(seq 50); do grep -q serving "$tmp/slave.out" && break; sleep 0.1; done
  if master_out=$("$prefix/bin/ecat-master" --udp "127.0.0.1:$port" --expect-slaves 1 --cycles 200 2>&1); then
    grep -q 'all 1 slave(s) in Op' <<< "$master_out" || fail "ecat-master over UDP: $master_out"
    grep -q 'DIO16 16-channel digital I/O' <<< "$master_out" || fail "ecat-master did not name the DIO16: $master_out"
  else
    fail "ecat-master --udp against dio16-slave: $master_out"
  fi
  kill -TERM "$slave_pid"; wait "$slave_pid"; rc=$?; slave_pid=""
  [ "$rc" -eq 0 ] || fail "dio16-slave --udp exit $rc: $(cat "$tmp/slave.out")"
  grep -q "DIO16 stopped: [1-9][0-9]* application cycles" "$tmp/slave.out" || fail "dio16-slave --udp: $(cat "$tmp/slave.out")"
fi

if configure_build master-under-test; then
  ctest --test-dir "$tmp/master-under-test" --output-on-failure > "$tmp/mut.log" 2>&1 \
    || { cat "$tmp/mut.log"; fail "master-under-test: its GoogleTest fixture failed"; }
  grep -q "100% tests passed, 0 tests failed out of 2" "$tmp/mut.log" || fail "master-under-test: $(tail -5 "$tmp/mut.log")"
fi

if configure_build firmware-tables; then
  gen="$tmp/firmware-tables/servo_tables"
  for f in servo_tables.xml servo_tables.bin servo_tables.hpp; do
    [ -s "$gen/$f" ] || fail "ecatslave_generate made no $f"
  done
  xmllint --noout "$gen/servo_tables.xml" 2> /dev/null || fail "generated ESI is not well-formed XML"
  "$prefix/bin/ecat-esigen" "$prefix/share/ecatslave/devices/generic-servo.xml" --sii "$tmp/servo.bin" > /dev/null 2>&1
  cmp -s "$gen/servo_tables.bin" "$tmp/servo.bin" || fail "ecatslave_generate SII differs from ecat-esigen's"
  out=$("$tmp/firmware-tables/firmware_tables" 2>&1) || fail "firmware_tables: $out"
  grep -q "^Generic servo (ECATSLAVE-SERVO-1): vendor 0x00000000 product 0x00000402" <<< "$out" \
    || fail "firmware_tables printed: $out"
fi

[ "$status" -eq 0 ] && echo "ok: installed layout, $n_headers headers on the installed include path, pkg-config, 3 examples built and run"
exit $status
