#!/usr/bin/env bash
# The Debian package (issue 17): `cpack -G DEB` on the build, then
#  - its control fields: name, version, the run-time libraries dpkg-shlibdeps
#    found and the -dev packages the headers and CMake package need;
#  - its file list (dpkg-deb -c): programs, man pages, libraries, headers,
#    CMake package, pkg-config file, device files - and nothing outside /usr;
#  - its programs, unpacked with dpkg-deb -x (not installed: the test leaves
#    the machine as it was): --help, ESI + SII of an installed device file,
#    and ecat-slave with its default device brought to Op over UDP on
#    127.0.0.1 by the packaged ecat-master.
# ECAT_DEB_INSTALL=1 (as root) also installs it with apt-get, runs it from
# /usr/bin and removes it again.
# Usage: deb_package.sh SRCDIR BUILDDIR   (exit 77 = skipped)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
[ -x "$build/bin/ecat-esigen" ] || { echo "skip: $build not built"; exit 77; }
command -v dpkg-deb > /dev/null || { echo "skip: dpkg-deb not installed"; exit 77; }
command -v dpkg-shlibdeps > /dev/null || { echo "skip: dpkg-shlibdeps (dpkg-dev) not installed"; exit 77; }

tmp=$(mktemp -d /tmp/ecat-deb.XXXXXX)
slave_pid=""
cleanup() {
  [ -n "$slave_pid" ] && kill "$slave_pid" 2> /dev/null
  rm -rf "$tmp"
}
trap cleanup EXIT
status=0
fail() { echo "FAIL: $*"; status=1; }
version=$(sed -n 's/^CMAKE_PROJECT_VERSION:[A-Z]*=//p' "$build/CMakeCache.txt")
libdir=$(sed -n 's/^CMAKE_INSTALL_LIBDIR:[A-Z]*=//p' "$build/CMakeCache.txt")
help2man=$(sed -n 's/^HELP2MAN_PROGRAM:[A-Z]*=//p' "$build/CMakeCache.txt" | grep -v NOTFOUND)

if ! (cd "$tmp" && cpack -G DEB --config "$build/CPackConfig.cmake" -B "$tmp/out") > "$tmp/cpack.log" 2>&1; then
  cat "$tmp/cpack.log"; echo "FAIL: cpack -G DEB"; exit 1
fi
deb=$(ls "$tmp"/out/ecatslave_*.deb 2> /dev/null | head -1)
[ -f "$deb" ] || { cat "$tmp/cpack.log"; echo "FAIL: no ecatslave_*.deb"; exit 1; }
[ "$(basename "$deb")" = "ecatslave_${version}_$(dpkg --print-architecture).deb" ] || fail "package file name $(basename "$deb")"

# --- control fields ----------------------------------------------------------------
[ "$(dpkg-deb -f "$deb" Package)" = ecatslave ] || fail "Package: $(dpkg-deb -f "$deb" Package)"
[ "$(dpkg-deb -f "$deb" Version)" = "$version" ] || fail "Version: $(dpkg-deb -f "$deb" Version)"
depends=$(dpkg-deb -f "$deb" Depends)
for dep in libc6 libstdc++6 libpugixml1v5 libxml2 libpcap0.8 libfmt-dev libpugixml-dev libxml2-dev \
           libpcap-dev libexpected-dev nlohmann-json3-dev; do
  grep -q "\b$dep\b" <<< "$depends" || fail "Depends lacks $dep: $depends"
done

# --- file list ----------------------------------------------------------------------
dpkg-deb -c "$deb" | awk '{print $6}' | sed 's|^\./|/|' > "$tmp/files"
expect=(/usr/bin/ecat-esigen /usr/bin/ecat-slave /usr/bin/ecat-master /usr/bin/ecat-conform
        "/usr/$libdir/libecatslave_slave.a" "/usr/$libdir/libecatslave_esc.a" "/usr/$libdir/libecatslave_coe.a"
        "/usr/$libdir/libecatslave_ds402.a" "/usr/$libdir/libecatslave_esi.a" "/usr/$libdir/libecatslave_master.a"
        "/usr/$libdir/libecatslave_transport.a" "/usr/$libdir/libecatslave_od.a"
        /usr/include/ecatslave/slave/chain.hpp /usr/include/ecatslave/common/expected.hpp
        "/usr/$libdir/cmake/ecatslave/ecatslaveConfig.cmake" "/usr/$libdir/cmake/ecatslave/ecatslaveConfigVersion.cmake"
        "/usr/$libdir/cmake/ecatslave/ecatslaveTargets.cmake" "/usr/$libdir/cmake/ecatslave/ecatslaveGenerate.cmake"
        "/usr/$libdir/pkgconfig/ecatslave.pc"
        /usr/share/ecatslave/devices/generic-servo.xml /usr/share/ecatslave/profiles/cia301.xml
        /usr/share/ecatslave/schema/device.xsd /usr/share/doc/ecatslave/LICENSE /usr/share/doc/ecatslave/api.md
        "/usr/$libdir/libecatslave_control.a" /usr/include/ecatslave/control/request_handler.hpp
        /usr/lib/python3/dist-packages/ecatslave/client.py /usr/lib/python3/dist-packages/ecatslave/pytest_plugin.py)
if [ -n "$help2man" ]; then
  expect+=(/usr/share/man/man1/ecat-esigen.1.gz /usr/share/man/man1/ecat-slave.1.gz
           /usr/share/man/man1/ecat-master.1.gz /usr/share/man/man1/ecat-conform.1.gz)
fi
for f in "${expect[@]}"; do
  grep -qx -- "$f" "$tmp/files" || fail "not in the package: $f"
done
outside=$(grep -v '^/usr/\|^/$\|^/usr$' "$tmp/files")
[ -z "$outside" ] || fail "files outside /usr: $outside"
n_files=$(grep -vc '/$' "$tmp/files")

# --- the unpacked programs ------------------------------------------------------------
root="$tmp/root"
dpkg-deb -x "$deb" "$root"
bin="$root/usr/bin"
"$bin/ecat-esigen" --help > "$tmp/help" 2>&1 || fail "ecat-esigen --help: $(head -3 "$tmp/help")"
grep -q -- '--sii' "$tmp/help" || fail "ecat-esigen --help lacks --sii"
"$bin/ecat-esigen" "$root/usr/share/ecatslave/devices/simtach-rse.xml" --esi "$tmp/rse.xml" --sii "$tmp/rse.bin" \
  > "$tmp/gen.log" 2>&1 || fail "packaged ecat-esigen on a packaged device: $(head -3 "$tmp/gen.log")"
[ -s "$tmp/rse.xml" ] && [ -s "$tmp/rse.bin" ] || fail "packaged ecat-esigen wrote no ESI/SII"
port=$((20000 + ($$ + 7) % 20000))
"$bin/ecat-slave" --udp "127.0.0.1:$port" > "$tmp/slave.out" 2>&1 &
slave_pid=$!
sleep 0.5
if out=$("$bin/ecat-master" --udp "127.0.0.1:$port" --expect-slaves 1 --cycles 100 2>&1); then
  grep -q '"Generic servo"' <<< "$out" || fail "packaged ecat-slave did not serve its default device: $out"
  grep -q 'all 1 slave(s) in Op' <<< "$out" || fail "packaged ecat-master: $out"
else
  fail "packaged ecat-master against packaged ecat-slave: $out"
fi
kill "$slave_pid"; wait "$slave_pid" 2> /dev/null; slave_pid=""

# --- optional: a real install ------------------------------------------------------------
if [ "${ECAT_DEB_INSTALL:-0}" = 1 ] && [ "$(id -u)" -eq 0 ]; then
  if DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "$deb" > "$tmp/apt.log" 2>&1; then
    /usr/bin/ecat-esigen --version | grep -q "$version" || fail "installed ecat-esigen --version"
    man -w ecat-slave > /dev/null 2>&1 || fail "man ecat-slave not found after install"
    DEBIAN_FRONTEND=noninteractive apt-get remove -y -qq ecatslave > /dev/null 2>&1 || fail "apt-get remove"
  else
    fail "apt-get install $deb: $(tail -5 "$tmp/apt.log")"
  fi
fi

[ "$status" -eq 0 ] && echo "ok: $(basename "$deb"), $n_files files, Depends: $depends"
exit $status
