#!/usr/bin/env python3
"""One-off aid: regenerate a seed device file from its digest CSV.

    scripts/seed/gen.py simtach|yaskawa|welcon|leadshine [SEED_DIR] > xml/devices/X.xml

SEED_DIR defaults to /work/shared/seeds/digests. The output was reviewed by
hand before it was committed; docs/seed-devices.md records every choice.
"""
from __future__ import annotations

import importlib
import os
import sys

sys.dont_write_bytecode = True
sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))

from seedlib import (element, emit_object, emit_pdo, needs_remove,  # noqa: E402
                     profile_objects)


def emit(spec: dict) -> str:
    out = ['<?xml version="1.0" encoding="UTF-8"?>\n', "<!--\n", spec["header"], "\n\n",
           "  Generated once by scripts/seed/gen.py from the seed digest CSV, then\n"
           "  reviewed; edit this file, not the script output.\n-->\n",
           '<Device formatVersion="1">\n',
           '  <Include href="../profiles/cia301.xml"/>\n',
           '  <Include href="../profiles/cia402.xml"/>\n\n']
    out.append(element("Identity", spec["identity"]))
    if spec.get("esc"):
        out.append(element("Esc", spec["esc"]))
    out.append(element("Mailbox", spec["mailbox"]))
    out.append("  <SyncManagers>\n")
    for idx, typ, start, size, max_size, control in spec["sms"]:
        out.append(element("Sm", [("index", idx), ("type", typ), ("start", f"#x{start:04X}"),
                                  ("size", size), ("maxSize", max_size),
                                  ("control", f"#x{control:02X}")], "    "))
    out.append("  </SyncManagers>\n  <Fmmus>\n")
    for u in spec["fmmus"]:
        out.append(element("Fmmu", [("usage", u)], "    "))
    out.append("  </Fmmus>\n")
    dc = spec.get("dc")
    if dc:
        from seedlib import _attrs
        out.append(f"  <Dc {_attrs(dc['attrs'])}>\n")
        for name, desc, aa in dc["opmodes"]:
            out.append(element("OpMode", [("name", name), ("desc", desc),
                                          ("assignActivate", f"#x{aa:04X}")], "    "))
        out.append("  </Dc>\n")
    out.append("\n  <Objects>\n")
    if spec.get("removes"):
        out.append(f"    <!-- {spec['removes_why']} -->\n")
    for idx, name in spec.get("removes", []):
        out.append(f'    <Remove index="#x{idx:04X}"/>  <!-- {name} -->\n')
    profile = profile_objects(spec["repo"])
    for idx in sorted(spec["objects"]):
        o = spec["objects"][idx]
        if needs_remove(o, profile):
            out.append(f'    <Remove index="#x{idx:04X}"/>  <!-- redefined completely below -->\n')
        out.append(emit_object(o, none_pdo=idx in profile))
    out.append("  </Objects>\n\n")
    for p in spec["rx"]:
        out.append(emit_pdo(p, "RxPdo"))
    for p in spec["tx"]:
        out.append(emit_pdo(p, "TxPdo"))
    d = spec["drive"]
    out.append(f'\n  <Drive modes="{d["modes"]}" homingMethods="{d["homing"]}">\n')
    for name, value, unit in d["plant"]:
        out.append(element("Plant", [("name", name), ("value", value), ("unit", unit)], "    "))
    out.append("  </Drive>\n</Device>\n")
    return "".join(out)


def main() -> int:
    if len(sys.argv) < 2:
        print(__doc__, file=sys.stderr)
        return 2
    seed_dir = sys.argv[2] if len(sys.argv) > 2 else "/work/shared/seeds/digests"
    mod = importlib.import_module(sys.argv[1])
    repo = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
    spec = mod.build(seed_dir, repo)
    spec["repo"] = repo
    sys.stdout.write(emit(spec))
    return 0


if __name__ == "__main__":
    sys.exit(main())
