#!/usr/bin/env bash
# The digital-twin chain for every device of one vendor ESI file (issue 14 item 3):
#   import      ecat-esigen --from-esi FILE (device chosen by --product-code/--revision)
#               -> ESI, SII and our device XML; the repairs are the import warnings
#   load        the device XML loads again (ecat-esigen DEVICE.xml)
#   agree       ecat-conform in-process, the sii.* / od.* / esi.* cases: no FAIL
#   schema      the re-emitted ESI is valid against ETG.2000 1.14 and 1.17
#               (or the schemas ECAT_ESI_SCHEMAS names; skipped, as in esigen_cli.sh,
#               where no schema is found: tests/scripts/lib/esi_schemas.sh)
#   stable      device XML -> ESI -> model -> device XML -> ESI gives the same ESI
#   op          ecat-master --in-process: Init -> PreOp -> SafeOp -> Op, then cycles
#               with the expected WKC on every one (exit 1 otherwise)
#   conform     ecat-conform in-process, every case: no FAIL; a SKIP carries its reason
# One line per device on stdout: "twin|file|device|product|revision|import|load|agree|
# schema|stable|op|conform|repairs|note" (docs/twins.md's table is made from these
# lines by tests/twins/twins_table.sh). With TWIN_REPORT_DIR set, the lines and the
# repair warnings are also written there.
# Usage: twin_chain.sh SRCDIR BUILDDIR ESI-FILE   (exit 77 = skipped: tools missing)
set -uo pipefail
src=${1:?srcdir}
build=${2:?builddir}
esi=${3:?esi file}
gen="$build/bin/ecat-esigen"
conform="$build/bin/ecat-conform"
master="$build/bin/ecat-master"
for b in "$gen" "$conform" "$master"; do
  [ -x "$b" ] || { echo "skip: $b not built"; exit 77; }
done
command -v xmllint > /dev/null || { echo "skip: xmllint not installed"; exit 77; }
# shellcheck source=../scripts/lib/esi_schemas.sh
. "$src/tests/scripts/lib/esi_schemas.sh" "$src"
have_schema=0
[ ${#esi_schemas[@]} -gt 0 ] && have_schema=1
cycles=${TWIN_CYCLES:-200}

out=$(mktemp -d)
trap 'rm -rf "$out"' EXIT
file=$(basename "$esi")
status=0
report_dir=${TWIN_REPORT_DIR:-}

# The devices of the file, in file order, from one `ecat-esigen --list` (type,
# product code, revision, name; the importer's own reading, so a multi-MB file
# is parsed once, not three times per device as xpath queries did).
"$gen" --from-esi "$esi" --list > "$out/list.tsv" 2> "$out/list.err"
count=$(wc -l < "$out/list.tsv")
[ "${count:-0}" -gt 0 ] 2> /dev/null || { echo "FAIL: $file: no Device listed: $(head -2 "$out/list.err" | tr '\n' ' ')"; exit 1; }

# JUnit results of ecat-conform (one element per line as ecat-conform writes
# them): failed case names, and skipped ones as "name: reason".
junit_failed() { awk -F'"' '/<testcase /{for(i=1;i<NF;i++) if ($i ~ / name=$/) n=$(i+1)} /<failure /{print n}' "$1"; }
junit_skipped() {
  awk -F'"' '/<testcase /{for(i=1;i<NF;i++) if ($i ~ / name=$/) n=$(i+1)}
    /<skipped /{m=""; for(i=1;i<NF;i++) if ($i ~ / message=$/) m=$(i+1); print n ": " m}' "$1" |
    sed 's/&quot;/"/g; s/&apos;/'"'"'/g; s/&lt;/</g; s/&gt;/>/g; s/&amp;/\&/g'
}

declare -A seen known_hit
declare -a schema_files=() schema_dev=()
i=0
while IFS=$'\t' read -r type pc rev _name; do
  i=$((i + 1))
  type=$(printf '%s' "$type" | tr -d '\r|' | sed 's/^ *//;s/ *$//')
  [ "$pc" = "?" ] && pc=""
  [ "$rev" = "?" ] && rev=""
  d="$out/dev$i"
  mkdir -p "$d"
  r_import=- r_load=- r_agree=- r_schema=- r_stable=- r_op=- r_conform=- repairs=0 note=""
  line() {
    local l="twin|$file|$type|$pc|${rev:-}|$r_import|$r_load|$r_agree|$r_schema|$r_stable|$r_op|$r_conform|$repairs|$note"
    echo "$l" >> "$out/lines.txt"
  }
  fail() { note="${note:+$note; }$*"; status=1; echo "FAIL: $file device $i ($type): $*"; }

  # A device without a product code is not an EtherCAT slave: passive
  # terminals (end caps, potential feeds, Physics without an EtherCAT port)
  # are listed for the configurator's terminal plan; no master ever sees one.
  if [ -z "$pc" ]; then
    note="no product code: a passive terminal without an EtherCAT slave controller, nothing for a master to see"
    line
    continue
  fi
  sel=(--product-code "$pc")
  [ -n "$rev" ] && sel+=(--revision "$rev")
  key="${pc}/${rev}"
  if [ -n "${seen[$key]:-}" ]; then
    sel+=(--type "$type")
    if [ -n "${seen[$key/$type]:-}" ]; then
      note="same product code, revision and type as device ${seen[$key/$type]}: not selectable"
      line
      continue
    fi
  fi
  seen[$key]=${seen[$key]:-$i}
  seen[$key/$type]=$i

  # 1. import
  if "$gen" --from-esi "$esi" "${sel[@]}" --esi "$d/esi1.xml" --sii "$d/sii.bin" \
       --device-xml "$d/device.xml" > /dev/null 2> "$d/import.err"; then
    r_import=ok
  else
    r_import=FAIL
    fail "import: $(grep -v ': warning: ' "$d/import.err" | head -2 | tr '\n' ' ')"
    line
    continue
  fi
  repairs=$(grep -c ': warning: ' "$d/import.err")
  if [ -n "$report_dir" ] && [ "$repairs" -gt 0 ]; then
    grep ': warning: ' "$d/import.err" | sed 's|^[^:]*/\([^/:]*\):|\1:|' >> "$report_dir/warnings-$file.txt"
  fi

  # 2. the twin's device file loads
  if "$gen" "$d/device.xml" --esi "$d/esi2.xml" > /dev/null 2> "$d/load.err"; then
    r_load=ok
  else
    r_load=FAIL
    fail "device XML does not load: $(head -2 "$d/load.err" | tr '\n' ' ')"
    line
    continue
  fi

  # 3. ecat-conform, whole suite in-process (JUnit); the sii/od/esi cases give "agree"
  "$conform" --device "$d/device.xml" --junit "$d/conform.xml" > "$d/conform.out" 2>&1
  crc=$?
  if [ ! -s "$d/conform.xml" ]; then
    r_agree=FAIL r_conform=FAIL
    fail "ecat-conform exit $crc without results: $(tail -2 "$d/conform.out" | tr '\n' ' ')"
  else
    failed=$(junit_failed "$d/conform.xml")
    # Known findings (tests/twins/known-conform.txt) are reported, not failed.
    kept=""
    for c in $failed; do
      why=$(grep -v '^#' "$src/tests/twins/known-conform.txt" 2> /dev/null | grep -F "$file|$c|" | head -1 | cut -d'|' -f3-)
      if [ -n "$why" ]; then
        echo "known: $file device $i ($type): $c: $why"
        known_hit["$c"]=1
      else
        kept="$kept $c"
      fi
    done
    failed=$(echo $kept | tr ' ' '\n' | grep . || true)
    agree_failed=$(echo "$failed" | grep -E '^(sii|od|esi)\.' || true)
    if [ -z "$agree_failed" ]; then r_agree=ok; else r_agree=FAIL; fail "agree: $(echo $agree_failed)"; fi
    skipped=$(junit_skipped "$d/conform.xml")
    nskip=$(echo -n "$skipped" | grep -c . || true)
    unexplained=$(echo "$skipped" | grep -E ': *$' || true)
    if [ -z "$failed" ] && [ -z "$unexplained" ]; then
      r_conform="ok"
      [ "$nskip" -gt 0 ] && r_conform="ok, $nskip skip"
    else
      r_conform=FAIL
      [ -n "$failed" ] && fail "conform: $(echo $failed)"
      [ -n "$unexplained" ] && fail "skip without reason: $(echo $unexplained)"
    fi
    [ -n "$report_dir" ] && [ -n "$skipped" ] && echo "$skipped" | sed "s|^|$file $type: |" >> "$report_dir/skips.txt"
    # A device whose ESI offers only DC OpModes runs the suite in DC Sync0
    # mode (ecat-conform programs SYNC0 before every PreOp->SafeOp); the row says so.
    if grep -q '^ecat-conform: DC Sync0 mode' "$d/conform.out"; then
      note="${note:+$note; }ecat-conform in DC Sync0 mode (the ESI offers only DC OpModes)"
    fi
  fi

  # 4. schema: every device's ESI is validated after the loop, one xmllint run
  #    per schema for the whole file (the schema is then read once, not per device)
  if [ $have_schema -eq 1 ]; then
    schema_files+=("$d/esi1.xml")
    schema_dev+=("$i")
    r_schema=pending
  else
    r_schema=skip
  fi

  # 5. stable: device XML -> ESI -> model -> device XML -> ESI
  if "$gen" --from-esi "$d/esi2.xml" --device-xml "$d/device2.xml" --esi "$d/esi3.xml" > /dev/null 2> "$d/st.err" &&
     "$gen" "$d/device2.xml" --esi "$d/esi4.xml" > /dev/null 2>> "$d/st.err" &&
     cmp -s "$d/esi2.xml" "$d/esi3.xml" && cmp -s "$d/esi3.xml" "$d/esi4.xml"; then
    r_stable=ok
  else
    r_stable=FAIL
    fail "ESI not stable: $(grep -v ': warning: ' "$d/st.err" | head -2 | tr '\n' ' ')$(diff "$d/esi2.xml" "$d/esi3.xml" 2> /dev/null | head -4 | tr '\n' ' ')"
  fi

  # 6. the project's master to Op, expected WKC on every cycle
  # A drive that refuses free run (AL status code 0x0028, "synchronization
  # not supported": Inovance IS620N's 1C32h) is run again in DC Sync0 mode,
  # as its configurator would set it up; the row says so.
  if "$master" --in-process --device "$d/device.xml" --cycles "$cycles" --expect-slaves 1 -q \
       > "$d/master.out" 2>&1; then
    r_op=ok
  elif grep -q "AL status code 0x0028" "$d/master.out" &&
       "$master" --in-process --device "$d/device.xml" --cycles "$cycles" --expect-slaves 1 -q --dc \
         > "$d/master-dc.out" 2>&1; then
    r_op="ok (DC)"
    note="${note:+$note; }free run refused with 0x0028; Op in DC Sync0 mode"
  else
    r_op=FAIL
    fail "master: $(tail -2 "$d/master.out" | tr '\n' ' ')"
  fi
  line
done < "$out/list.tsv"

# 4. (after the loop) the schema step of every device at once; xmllint names
# each file that fails ("F fails to validate") and the errors carry its path.
if [ ${#schema_files[@]} -gt 0 ]; then
  lints=()
  for si in "${!esi_schemas[@]}"; do
    xmllint --noout --schema "${esi_schemas[$si]}" "${schema_files[@]}" > "$out/lint$si" 2>&1
    lints+=("$out/lint$si")
  done
  for k in "${!schema_files[@]}"; do
    f=${schema_files[$k]}
    n=${schema_dev[$k]}
    valid=1
    for l in "${lints[@]}"; do
      if grep -q -F "$f fails to validate" "$l" || ! grep -q -F "$f validates" "$l"; then valid=0; fi
    done
    if [ $valid -eq 0 ]; then
      msg="ESI invalid: $(grep -h -F "$f:" "${lints[@]}" | head -2 | sed "s|$out/||g" | tr '\n' ' ')"
      status=1
      echo "FAIL: $file device $n: $msg"
      # the device's line gets FAIL and the message
      awk -F'|' -v OFS='|' -v row="$n" -v msg="$msg" 'NR == row && $9 == "pending" {$9 = "FAIL"; $14 = ($14 == "" ? msg : $14 "; " msg)} {print}' \
        "$out/lines.txt" > "$out/lines.new" && mv "$out/lines.new" "$out/lines.txt"
    fi
  done
fi
sed -i 's/^\(twin|\([^|]*|\)\{7\}\)pending|/\1ok|/' "$out/lines.txt"
cat "$out/lines.txt"
[ -n "$report_dir" ] && cat "$out/lines.txt" >> "$report_dir/lines.txt"
# A known conformance finding that no device of the file shows any more is stale.
while IFS='|' read -r kfile kcase _; do
  [ "$kfile" = "$file" ] || continue
  if [ -z "${known_hit[$kcase]:-}" ]; then
    echo "FAIL: $file: $kcase passes but is listed in tests/twins/known-conform.txt: remove it there"
    status=1
  fi
done < <(grep -v '^#' "$src/tests/twins/known-conform.txt" 2> /dev/null)
known=$(grep -v '^#' "$src/tests/twins/known-limits.txt" 2> /dev/null | grep -F "$file|" | cut -d'|' -f2-)
if [ -n "$known" ]; then
  if [ $status -ne 0 ]; then
    echo "skip: $file: known limit: $known"
    exit 77
  fi
  echo "FAIL: $file passes but is listed in tests/twins/known-limits.txt: remove it there"
  exit 1
fi
[ $status -eq 0 ] && echo "twin_chain $file: ok ($count device(s))"
exit $status
