#!/usr/bin/env bash
# Runs tests/twins/twin_chain.sh on every file of the vendor ESI corpus and
# prints the markdown table of docs/twins.md ("Corpus results"): one row per
# device, each step, the number of import warnings (repairs and elements not
# modelled), and why a step failed. Not a ctest test (each file is one:
# twin_<name>); run it to refresh the table:
#   tests/twins/twins_table.sh SRCDIR BUILDDIR > /tmp/table.md
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
report=$(mktemp -d)
trap 'rm -rf "$report"' EXIT
pass=0 fail=0
for f in "$src"/tests/data/esi-vendor/*.xml; do
  if TWIN_REPORT_DIR="$report" bash "$src/tests/twins/twin_chain.sh" "$src" "$build" "$f" > /dev/null 2>&1; then
    pass=$((pass + 1))
  else
    fail=$((fail + 1))
  fi
done
vendor_of() { grep -F "| $1 |" "$src/tests/data/esi-vendor/SOURCE.md" | awk -F'|' '{gsub(/^ +| +$/, "", $3); print $3}'; }
echo "| file | vendor | device | product code | revision | import | loads | ESI/SII/OD agree | schema 1.14+1.17 | ESI stable | master to Op, WKC every cycle | ecat-conform | warnings | note |"
echo "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
while IFS='|' read -r _ file type pc rev imp load agree schema stable op conform repairs note; do
  echo "| $file | $(vendor_of "$file") | $type | $pc | $rev | $imp | $load | $agree | $schema | $stable | $op | $conform | $repairs | ${note//\/tmp\/tmp.*\/dev[0-9]*\//} |"
done < "$report/lines.txt"
echo
echo "Files: $pass passed, $fail failed (those failing are the known limits below, each a skip with its reason in ctest)."
echo
echo "### Import warnings per file (repairs and elements not modelled; kinds, with how often)"
echo
norm() {  # one warning kind: numbers, indices and values replaced by placeholders
  sed 's/^[^:]*:[0-9]*: warning: //; s/[0-9A-F]\{4\}h/NNNNh/g; s/#x[0-9A-Fa-f]*/#x../g; s/0x[0-9a-f]\{4,8\}/0x../g; s/[0-9]\+ bytes/N bytes/g; s/[0-9]\+-bit/N-bit/g; s/([0-9]\+ bits)/(N bits)/g; s/SI0 [0-9]\+\( 0x\.\.\)*/SI0 .../g; s/subindex [0-9A-F, ()Nbits]*/subindex .../; s/'"'"'[^'"'"']*'"'"'/'"'"'…'"'"'/g'
}
for w in "$report"/warnings-*.txt; do
  [ -e "$w" ] || continue
  f=${w##*/warnings-}
  f=${f%.txt}
  echo "- **$f**: $(norm < "$w" | sort | uniq -c | sort -rn | awk '{n=$1; $1=""; sub(/^ /, ""); printf "%s%s (%d)", sep, $0, n; sep="; "}')"
done
echo
echo "### ecat-conform skips (reason, how often across the corpus)"
echo
[ -e "$report/skips.txt" ] && sed 's/^[^ ]* [^:]*: //' "$report/skips.txt" | sort | uniq -c | sort -rn | awk '{n=$1; $1=""; sub(/^ /, ""); printf "- %s (%d)\n", $0, n}'

