#!/usr/bin/env bash
# The Python package ecatslave (python/, docs/control.md "Python"): its own
# tests with Debian's python3-pytest, against this build's ecat-slave served
# over UDP on loopback (no root) and ecat-master.
# Usage: python_ecatslave.sh SRCDIR BUILDDIR   (exit 77 = skipped)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
[ -x "$build/bin/ecat-slave" ] || { echo "skip: $build/bin/ecat-slave not built"; exit 77; }
# Debian's python3 (a python3 earlier on PATH, e.g. pyenv's, may lack python3-pytest).
python=""
for p in python3 /usr/bin/python3; do
  if "$p" -c 'import pytest' 2> /dev/null; then python=$p; break; fi
done
[ -n "$python" ] || { echo "skip: python3-pytest not installed (scripts/install-deps)"; exit 77; }
export ECAT_SLAVE="$build/bin/ecat-slave"
export ECAT_MASTER="$build/bin/ecat-master"
export PYTHONPATH="$src/python${PYTHONPATH:+:$PYTHONPATH}"
export PYTHONDONTWRITEBYTECODE=1
exec "$python" -m pytest -q -p no:cacheprovider "$src/python/tests"
