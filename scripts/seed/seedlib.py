"""One-off aid: turn a seed drive's object-dictionary CSV (shared/seeds/digests)
plus a hand-written per-drive policy into an ecatslave device file.

The committed XML under xml/devices/ is the source of truth and was reviewed
by hand; this script only exists so the conversion can be repeated and its
choices read in one place. See docs/seed-devices.md.
"""
from __future__ import annotations

import csv
import re
from dataclasses import dataclass, field
from typing import Callable, Optional
from xml.sax.saxutils import quoteattr

ACCESS = {"RO": "ro", "RW": "rw", "WO": "wo", "CONST": "const"}

TYPE_ALIASES = {
    "UNSIGNED8": "UNSIGNED8", "UNSIGNED16": "UNSIGNED16", "UNSIGNED32": "UNSIGNED32",
    "UNSIGNED64": "UNSIGNED64", "INTEGER8": "INTEGER8", "INTEGER16": "INTEGER16",
    "INTEGER32": "INTEGER32", "INTEGER64": "INTEGER64", "BOOLEAN": "BOOLEAN",
    "VISIBLE_STRING": "VISIBLE_STRING", "OCTET_STRING": "OCTET_STRING", "REAL32": "REAL32",
}

BITS = {"BOOLEAN": 1, "INTEGER8": 8, "UNSIGNED8": 8, "INTEGER16": 16, "UNSIGNED16": 16,
        "INTEGER32": 32, "UNSIGNED32": 32, "REAL32": 32, "INTEGER64": 64, "UNSIGNED64": 64}


@dataclass
class Entry:
    sub: int
    name: str
    type: str = ""
    access: str = "ro"
    pdo: str = "none"
    default: str = ""
    min: str = ""
    max: str = ""
    unit: str = ""
    desc: str = ""
    backup: Optional[bool] = None
    length: Optional[int] = None       # strings: characters
    write_in: str = ""                 # "PreOp" etc.


@dataclass
class Obj:
    index: int
    name: str
    code: str = "VAR"                  # VAR | ARRAY | RECORD
    entries: list[Entry] = field(default_factory=list)
    desc: str = ""
    type: str = ""                     # RECORD: structured type (SM_SYNCHRONISATION ...)

    def sub(self, n: int) -> Entry:
        for e in self.entries:
            if e.sub == n:
                return e
        raise KeyError(f"{self.index:#06x}:{n}")


def read_rows(path: str) -> list[dict]:
    with open(path, newline="", encoding="utf-8") as f:
        return list(csv.DictReader(f))


def num(text: str) -> int:
    return int(text.strip(), 0)


def is_number(text: str) -> bool:
    try:
        int(text.strip(), 0)
        return True
    except ValueError:
        return False


def pdo_of(row: dict, access: str) -> str:
    p = row["pdo_mapping"].strip().upper()
    if p == "RXPDO":
        return "rx"
    if p == "TXPDO":
        return "tx"
    if p == "YES":  # manual says only "mappable": direction follows access
        return "rx" if access == "rw" else "tx"
    return "none"


def entry_from_row(row: dict) -> Entry:
    access = ACCESS.get(row["access"].strip().upper(), "")
    e = Entry(sub=num(row["subindex"]), name=row["name"].strip(),
              type=TYPE_ALIASES.get(row["data_type"].strip(), row["data_type"].strip()),
              access=access)
    e.pdo = pdo_of(row, access)
    for k in ("default", "min", "max"):
        v = row[k].strip()
        setattr(e, k, v)
    e.unit = row["unit"].strip()
    e.desc = row["notes"].strip()
    return e


def group(rows: list[dict], keep: Callable[[dict], bool] = lambda r: True) -> dict[int, list[dict]]:
    out: dict[int, list[dict]] = {}
    for r in rows:
        if not keep(r):
            continue
        out.setdefault(num(r["index"]), []).append(r)
    return out


def build_object(index: int, rows: list[dict], name: str | None = None) -> Obj:
    entries = sorted((entry_from_row(r) for r in rows), key=lambda e: e.sub)
    if len(entries) == 1 and entries[0].sub == 0:
        e = entries[0]
        return Obj(index=index, name=name or e.name, code="VAR", entries=[e])
    subs = [e for e in entries if e.sub != 0]
    types = {e.type for e in subs}
    contiguous = [e.sub for e in subs] == list(range(1, len(subs) + 1))
    code = "ARRAY" if len(types) == 1 and contiguous else "RECORD"
    if entries[0].sub != 0:
        # The CSV gave no "number of entries": CiA 301 sub 0, UNSIGNED8, ro.
        entries.insert(0, Entry(sub=0, name="Number of entries", type="UNSIGNED8", access="ro",
                                default=str(max(e.sub for e in subs))))
    sub0 = entries[0]
    m = re.match(r"(.*?):? *(highest sub-?index|number of (entries|mapped objects|assigned PDOs))",
                 sub0.name, re.I)
    derived = m.group(1).strip() if m and m.group(1).strip() else sub0.name
    sub0.name = "Highest sub-index supported"
    return Obj(index=index, name=name or derived, code=code, entries=entries)


# ----------------------------------------------------------------- emit XML

def fmt_hex(v: int, width: int) -> str:
    return f"#x{v:0{width}X}"


def _attrs(pairs: list[tuple[str, object]]) -> str:
    out = []
    for k, v in pairs:
        if v is None or v == "":
            continue
        if isinstance(v, bool):
            v = "true" if v else "false"
        out.append(f"{k}={quoteattr(str(v))}")
    return " ".join(out)


def value_attrs(e: Entry, with_type: bool = True, none_pdo: bool = False) -> list[tuple[str, object]]:
    return [
        ("name", e.name),
        ("type", e.type if with_type else None),
        ("length", e.length),
        ("access", e.access),
        ("writeIn", e.write_in or None),
        ("pdo", e.pdo if e.pdo != "none" or none_pdo else None),
        ("backup", e.backup),
        ("default", e.default),
        ("min", e.min),
        ("max", e.max),
        ("unit", e.unit),
        ("description", e.desc),
    ]


def object_pairs(o: Obj, none_pdo: bool = False) -> tuple[list, list]:
    """Attributes of the Object element and of each Entry element. none_pdo:
    also write pdo="none" (to override a profile's mappability)."""
    if o.code == "VAR":
        e = o.entries[0]
        pairs = [("index", fmt_hex(o.index, 4))] + value_attrs(e, none_pdo=none_pdo)
        pairs[1] = ("name", o.name)
        return pairs, []
    head = [("index", fmt_hex(o.index, 4)), ("name", o.name), ("code", o.code)]
    if o.code == "ARRAY":
        elem = {e.type for e in o.entries if e.sub != 0}
        head += [("type", elem.pop()), ("count", max(e.sub for e in o.entries))]
    elif o.type:
        head.append(("type", o.type))
    head.append(("description", o.desc))
    ents = [[("sub", e.sub)] + value_attrs(e, none_pdo=none_pdo)
            for e in o.entries]
    return head, ents


def emit_object(o: Obj, ind: str = "    ", none_pdo: bool = False) -> str:
    head, ents = object_pairs(o, none_pdo)
    if not ents:
        return f"{ind}<Object {_attrs(head)}/>\n"
    lines = [f"{ind}<Object {_attrs(head)}>\n"]
    for pairs in ents:
        lines.append(f"{ind}  <Entry {_attrs(pairs)}/>\n")
    lines.append(f"{ind}</Object>\n")
    return "".join(lines)


def profile_objects(repo: str) -> dict[int, tuple[dict, dict[int, dict]]]:
    import xml.etree.ElementTree as ET
    out = {}
    for p in ("cia301", "cia402"):
        for o in ET.parse(f"{repo}/xml/profiles/{p}.xml").getroot().iter("Object"):
            ents = {int(e.get("sub").replace("#x", "0x"), 0): dict(e.attrib) for e in o.iter("Entry")}
            out[int(o.get("index").replace("#x", "0x"), 0)] = (dict(o.attrib), ents)
    return out


def needs_remove(o: Obj, profile: dict) -> bool:
    """True if merging o over the profile's object would keep profile values
    that o does not restate (an attribute, an entry, the code), so the
    object must be removed and defined anew (docs/device-format.md)."""
    if o.index not in profile:
        return False
    p_attrs, p_ents = profile[o.index]
    head, ents = object_pairs(o, none_pdo=True)
    mine = {k for k, v in head if v not in (None, "")}
    if p_attrs.get("code", "VAR") != o.code:
        return True
    if o.code == "VAR":
        return any(k not in mine for k in p_attrs)
    if any(k not in mine for k in p_attrs if k not in ("access", "pdo", "default", "min", "max",
                                                       "unit", "backup", "setting", "readIn",
                                                       "writeIn")):
        return True
    my_ents = {dict(e)["sub"]: {k for k, v in e if v not in (None, "")} for e in ents}
    inherited = {k for k in p_attrs if k in ("access", "pdo", "default", "min", "max", "unit",
                                             "backup", "setting", "readIn", "writeIn")}
    for sub, keys in my_ents.items():
        if sub != 0 and any(k not in keys for k in inherited):
            return True
    for sub, attrs in p_ents.items():
        if sub not in my_ents or any(k not in my_ents[sub] for k in attrs):
            return True
    return False


@dataclass
class PdoSpec:
    index: int
    name: str
    entries: list[tuple[int, int, int, str]]   # index, sub, bits, name
    sm: Optional[int] = None
    fixed: bool = False
    max_entries: Optional[int] = None
    excludes: list[int] = field(default_factory=list)
    comment: str = ""


def pdo_from_mapping(obj: Obj, name: str, names: dict[tuple[int, int], str], **kw) -> PdoSpec:
    """Decode a mapping object's defaults (index<<16 | sub<<8 | bits)."""
    count = num(obj.sub(0).default or "0")
    ents = []
    for e in obj.entries[1:count + 1]:
        v = num(e.default)
        idx, sub, bits = v >> 16, (v >> 8) & 0xFF, v & 0xFF
        ents.append((idx, sub, bits, names.get((idx, sub), "")))
    kw.setdefault("max_entries", len(obj.entries) - 1)
    return PdoSpec(index=obj.index, name=name, entries=ents, **kw)


def emit_pdo(p: PdoSpec, tag: str) -> str:
    out = []
    if p.comment:
        out.append(f"  <!-- {p.comment} -->\n")
    head = _attrs([("index", fmt_hex(p.index, 4)), ("name", p.name), ("sm", p.sm),
                   ("fixed", p.fixed), ("maxEntries", p.max_entries),
                   ("excludes", " ".join(fmt_hex(x, 4) for x in p.excludes) or None)])
    if not p.entries:
        out.append(f"  <{tag} {head}/>\n")
        return "".join(out)
    out.append(f"  <{tag} {head}>\n")
    for idx, sub, bits, name in p.entries:
        out.append(f"    <Entry {_attrs([('index', fmt_hex(idx, 4)), ('sub', sub), ('bits', bits), ('name', name)])}/>\n")
    out.append(f"  </{tag}>\n")
    return "".join(out)


def element(tag: str, pairs: list[tuple[str, object]], ind: str = "  ") -> str:
    return f"{ind}<{tag} {_attrs(pairs)}/>\n"


def names_of(objs: dict[int, Obj]) -> dict[tuple[int, int], str]:
    out = {}
    for o in objs.values():
        for e in o.entries:
            out[(o.index, e.sub)] = o.name if o.code == "VAR" else e.name
    return out


def clean(text: str) -> str:
    return re.sub(r"\s+", " ", text).strip()


def profile_indices(repo: str) -> dict[int, str]:
    """Objects the two profiles declare (index -> name)."""
    import xml.etree.ElementTree as ET
    out = {}
    for p in ("cia301", "cia402"):
        for o in ET.parse(f"{repo}/xml/profiles/{p}.xml").getroot().iter("Object"):
            out[int(o.get("index").replace("#x", "0x"), 0)] = o.get("name")
    return out


def removes_for(repo: str, objs: dict, keep: set[int]) -> list[tuple[int, str]]:
    """Profile objects the drive's manual does not list -> <Remove>."""
    return [(idx, name) for idx, name in sorted(profile_indices(repo).items())
            if idx not in objs and idx not in keep]


def take_flag(e: Entry, pattern: str) -> None:
    """Move a "backup"-style flag out of the CSV note into the backup
    attribute (ESI Backup: the value is stored by 1010h)."""
    m = re.search(pattern, e.desc, re.I)
    if m:
        e.backup = True if m.group(1).lower() == "yes" else None


def strip_notes(e: Entry, patterns: list[str]) -> None:
    for p in patterns:
        e.desc = re.sub(p, "", e.desc, flags=re.I)
    e.desc = re.sub(r"(;\s*)+$", "", re.sub(r"^\s*;\s*", "", e.desc)).strip()
    e.desc = re.sub(r";\s*;", ";", e.desc)


def type_range(t: str) -> Optional[tuple[int, int]]:
    m = re.fullmatch(r"(UNSIGNED|INTEGER)(\d+)", t)
    if not m:
        return (0, 1) if t == "BOOLEAN" else None
    n = int(m.group(2))
    return (0, 2**n - 1) if m.group(1) == "UNSIGNED" else (-(2**(n - 1)), 2**(n - 1) - 1)


def check_values(objs: dict) -> list[str]:
    """Problems the loader would reject: values outside the type, a default
    outside min..max, non-numeric limits. Returned for the policy to fix."""
    out = []
    for o in objs.values():
        for e in o.entries:
            r = type_range(e.type)
            if r is None:
                continue
            vals = {}
            for k in ("default", "min", "max"):
                v = getattr(e, k)
                if v == "":
                    continue
                if e.type == "BOOLEAN" and v in ("true", "false"):
                    continue
                if not is_number(v):
                    out.append(f"{o.index:#06x}:{e.sub} {k}={v!r} not a number")
                    continue
                vals[k] = num(v)
                if not r[0] <= vals[k] <= r[1]:
                    out.append(f"{o.index:#06x}:{e.sub} {k}={v} outside {e.type}")
            d = vals.get("default")
            if d is not None and (("min" in vals and d < vals["min"]) or
                                  ("max" in vals and d > vals["max"])):
                out.append(f"{o.index:#06x}:{e.sub} default {d} outside {vals.get('min')}..{vals.get('max')}")
    return out
