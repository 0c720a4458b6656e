#!/usr/bin/env python3
"""One-off aid (issue 15): the Yaskawa Sigma-V-SD SERVOPACK parameters
2000h-22FFh and 5C00h as device-file objects, with the data type of each
inferred from what the manual gives (docs/seed-devices.md "Yaskawa servo
parameters"). The manual (seed 003, 5.4) lists index, sub-index, Pn number
and name only; its object table prints "-" for type, access and range. So:

* Size. A Pn number addresses one 16-bit word: the manual's own tables give
  every UDINT object two consecutive Pn numbers (1010h:1-4 = PnC00/C02/C04/
  C06, 1600h:1-16 = Pn800-Pn81E, 2301h:1/2 = PnB02/PnB04) and every USINT/
  UINT object one (PnCA0, PnBA0-PnBA2), and inside one object the
  sub-indices run over consecutive words. So a sub-index is taken as 32-bit
  (2 words) when the next sub-index of the same object has the Pn number
  two higher and the number between is not listed; otherwise 16-bit (1
  word). This reads size from layout only: a parameter that ends an object
  or a run cannot be seen to be 2 words (e.g. Pn524 may be).
* Function-selection parameters ("n.XXXX", four hex digits per the manual's
  notation section; names with Switch/Select/Selection/Allocation): 16-bit.
* Sign: no range is printed, so unsigned (UNSIGNED16/UNSIGNED32), the full
  range of the type; Pn406 keeps the manual's example range 0..800 (1 %),
  factory setting 800.
* Access rw (the manual: "accessible by SDO"), not PDO-mappable, default 0
  (not printed; the project's rule for values without a default).

Usage: yaskawa_params.py CSV xml|md
"""
import csv
import re
import sys

FUNCTION_WORDS = ("Switch", "Select", "Selection", "Allocation")


def rows(path):
    with open(path, newline="") as f:
        for r in csv.DictReader(f):
            i = int(r["index"], 16)
            if 0x2000 <= i <= 0x22FF or i == 0x5C00:
                pn = re.match(r"Pn([0-9A-F]{3})", r["notes"]).group(1)
                yield i, int(r["subindex"], 16), pn, r["name"]


def infer(params):
    listed = {int(pn, 16) for _, _, pn, _ in params}
    next_in_object = {}
    for k, (index, sub, pn, _) in enumerate(params):
        if k + 1 < len(params) and params[k + 1][0] == index and params[k + 1][1] == sub + 1:
            next_in_object[(index, sub)] = int(params[k + 1][2], 16)
    out = []
    for index, sub, pn, name in params:
        n = int(pn, 16)
        if pn == "406":
            out.append((index, sub, pn, name, "UNSIGNED16", "0", "800", "800", "manual example: 0 to 800, 1 %, factory 800"))
            continue
        if any(w in name for w in FUNCTION_WORDS):
            out.append((index, sub, pn, name, "UNSIGNED16", "0", "0xFFFF", "0", "function selection n.XXXX: 16 bits"))
            continue
        if next_in_object.get((index, sub)) == n + 2 and (n + 1) not in listed:
            out.append((index, sub, pn, name, "UNSIGNED32", "0", "0xFFFFFFFF", "0",
                        "next sub-index is Pn%03X, Pn%03X unlisted: 2 words" % (n + 2, n + 1)))
            continue
        out.append((index, sub, pn, name, "UNSIGNED16", "0", "0xFFFF", "0", "1 word"))
    return out


def esc(s):
    return s.replace("&", "&amp;").replace("<", "&lt;").replace(">", "&gt;").replace('"', "&quot;")


def xml(items):
    by_index = {}
    for it in items:
        by_index.setdefault(it[0], []).append(it)
    lines = []
    for index in sorted(by_index):
        group = by_index[index]
        if len(group) == 1 and group[0][1] == 0:
            _, _, pn, name, t, lo, hi, d, why = group[0]
            lines.append('    <Object index="#x%04X" name="%s" type="%s" access="rw" default="%s" min="%s" max="%s" '
                         'description="Pn%s; SERVOPACK parameter; type inferred: %s"/>' % (index, esc(name), t, d, lo, hi, pn, esc(why)))
            continue
        top = max(g[1] for g in group)
        lines.append('    <Object index="#x%04X" name="SERVOPACK parameters %04Xh" code="RECORD" '
                     'description="Pn%s...; names from the manual 5.4">' % (index, index, group[0][2]))
        lines.append('      <Entry sub="0" name="Highest sub-index supported" type="UNSIGNED8" access="ro" default="%d"/>' % top)
        for _, sub, pn, name, t, lo, hi, d, why in group:
            lines.append('      <Entry sub="%d" name="%s" type="%s" access="rw" default="%s" min="%s" max="%s" '
                         'description="Pn%s; type inferred: %s"/>' % (sub, esc(name), t, d, lo, hi, pn, esc(why)))
        lines.append("    </Object>")
    return "\n".join(lines)


def md(items):
    lines = ["| index:sub | Pn | name | type | why |", "|---|---|---|---|---|"]
    for index, sub, pn, name, t, lo, hi, d, why in items:
        lines.append("| %04Xh:%d | Pn%s | %s | %s | %s |" % (index, sub, pn, name, t, why))
    return "\n".join(lines)


def main():
    items = infer(list(rows(sys.argv[1])))
    print(xml(items) if sys.argv[2] == "xml" else md(items))


if __name__ == "__main__":
    main()
