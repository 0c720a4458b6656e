#!/usr/bin/env bash
# ecat-slave --http in a real browser (issue 27, docs/webview.md): Debian's
# chromium, headless, driven by python3-selenium through chromium-driver,
# against 5 drives served over UDP on loopback and ecat-master bringing them
# to Op. The page shows 5 slaves in Op; a click cuts a cable, the slaves
# behind it lose their link on the page and ecat-master counts WKC errors; a
# drive fault engaged from the fault form shows that drive in Fault with its
# EMCY; clicks clear it and restore the cable. The screenshot goes to
# $ECAT_WEBVIEW_SCREENSHOT (default: the build tree; docs/webview.png is made
# so); $ECAT_WEBVIEW_ARGS adds options of lib/web_browser.py (the 20-drive
# walkthrough: "--slaves 20 --cut 7 --drive-fault 3 --window 1100,2600 --describe").
# Usage: web_browser.sh SRCDIR BUILDDIR   (exit 77 = skipped)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
[ -x "$build/bin/ecat-slave" ] && [ -x "$build/bin/ecat-master" ] ||
  { echo "skip: $build/bin/ecat-slave or ecat-master not built"; exit 77; }
command -v chromium > /dev/null || { echo "skip: chromium not installed (scripts/install-deps)"; exit 77; }
command -v chromedriver > /dev/null || { echo "skip: chromium-driver not installed (scripts/install-deps)"; exit 77; }
# Debian's python3 (a python3 earlier on PATH, e.g. pyenv's, may lack python3-selenium).
python=""
for p in python3 /usr/bin/python3; do
  if "$p" -c 'import selenium' 2> /dev/null; then python=$p; break; fi
done
[ -n "$python" ] || { echo "skip: python3-selenium not installed (scripts/install-deps)"; exit 77; }
export PYTHONDONTWRITEBYTECODE=1
# shellcheck disable=SC2086 # ECAT_WEBVIEW_ARGS is a list of options
exec timeout 180 "$python" "$src/tests/scripts/lib/web_browser.py" --slave "$build/bin/ecat-slave" \
  --master "$build/bin/ecat-master" --screenshot "${ECAT_WEBVIEW_SCREENSHOT:-$build/webview.png}" ${ECAT_WEBVIEW_ARGS:-}
