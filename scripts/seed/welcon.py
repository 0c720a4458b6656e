"""Welcon servo drive (CiA 301/402, EtherCAT CoE), axis 1 of the dual-axis
capable drive: conversion policy. Choices are listed in docs/seed-devices.md."""
from __future__ import annotations

import re

from seedlib import (build_object, check_values, group, is_number, names_of, num,
                     pdo_from_mapping, profile_objects, read_rows, removes_for, type_range)

CSV = "welcon-servo-od.csv"
MANUAL = "000_24d361abf1467c90.txt"

HEADER = """\
  Welcon servo drive (low-voltage DC servo, CiA 301/402), EtherCAT CoE
  interface. The drive is dual-axis capable: ONLY AXIS 1 IS MODELLED (axis 2
  would repeat 2000h-27FFh/6000h-67FFh at +800h and the PDOs at +10h).
  Source: "Welcon Servo Drive Reference Manual" (shared/seeds/000_*.txt) and
  its digest/CSV; choices in docs/seed-devices.md.

  PLACEHOLDERS: the manual gives no vendor id, product code, revision,
  serial, device name or version strings (1008h-100Ah, 1018h are printed
  with "-"). vendorId 0 is not an ETG vendor id.
  Objects the manual marks CANopen-only (1014h, 1016h, 1017h, 1400h-1403h,
  1800h-1803h, 5000h-5003h) or Ethernet-only (5004h) are left out.
  Not stated and chosen by us: SM layout, sync modes (free run, SM-synchron,
  DC Sync0) and the minimum cycle time (1 ms)."""

# 7.2.x headings of the manual for objects the CSV names only by sub 0.
RANGES = {0x21C5: "Notch Filter{n} for Current Command", 0x2201: "Velocity Control Parameter Set {n}",
          0x2281: "Position Control Parameter Set {n}", 0x2710: "Motion {n}"}


def manual_names(seed_dir: str) -> dict[int, str]:
    text = open(f"{seed_dir}/../{MANUAL}", encoding="utf-8").read()
    out: dict[int, str] = {}
    for m in re.finditer(r"7\.2\.\d+\. (0x[0-9A-Fa-f]{4}): ([^|<\n]*)", text):
        out.setdefault(int(m.group(1), 16), re.sub(r"\s+", " ", m.group(2)).strip())
    for first, pattern in RANGES.items():
        count = 16 if first == 0x2710 else 4
        for k in range(count):
            out[first + k] = pattern.format(n=k if first == 0x2710 else k + 1)
    out[0x20A0] = "Shared Hall Sensor Timing Configuration"
    return out


def build(seed_dir: str, repo: str) -> dict:
    rows = read_rows(f"{seed_dir}/{CSV}")
    names = manual_names(seed_dir)
    prof = profile_objects(repo)

    def bus(r: dict) -> str:
        m = re.search(r"bus=([A-Za-z+]+)", r["notes"])
        return m.group(1) if m else ""

    def keep(r: dict) -> bool:
        i = num(r["index"])
        if 0x1610 <= i <= 0x1619 or 0x1A10 <= i <= 0x1A19:
            return False          # axis 2
        return "ECAT" in bus(r)

    by_index = group(rows, keep)
    hints = {i: (re.search(r"object=(ARRAY|RECORD)", rs[0]["notes"]) or [None, None])[1]
             for i, rs in by_index.items()}
    objs = {i: build_object(i, r) for i, r in by_index.items()}

    moved: list[str] = []
    for o in objs.values():
        if o.code != "VAR" and hints.get(o.index):
            types = {e.type for e in o.entries if e.sub}
            o.code = hints[o.index] if len(types) == 1 else "RECORD"
        if o.name.lower().startswith("number of") or o.code != "VAR" and o.index in names:
            o.name = names.get(o.index, o.name)
        for e in o.entries:
            notes = e.desc
            m = re.search(r"backup=(YES|NO)", notes)
            if m and m.group(1) == "YES" and e.access == "rw":
                e.backup = True
            e.desc = re.sub(r"(axis2=0x[0-9A-Fa-f]+|bus=[A-Za-z+]+|backup=(YES|NO)|"
                            r"object=(ARRAY|RECORD))\s*;?\s*", "", notes).strip(" ;")
            # Limits that name another object ("Maximum Profile Velocity
            # (0x607F)") cannot be expressed: keep them in the description.
            for k in ("min", "max"):
                v = getattr(e, k)
                if v and not is_number(v):
                    e.desc = (e.desc + f"; {k}: {v}").strip("; ")
                    setattr(e, k, "")
                    moved.append(f"{o.index:04X}:{e.sub} {k}")
            if e.default == "" and e.type:
                p = prof.get(o.index)
                pd = None
                if p:
                    pe = p[1].get(e.sub) if o.code != "VAR" else p[0]
                    pd = (pe or {}).get("default") or (p[0].get("default") if o.code == "ARRAY" else None)
                if e.type == "VISIBLE_STRING":
                    e.default = ""
                elif e.type == "BOOLEAN":
                    e.default = "false"
                elif pd is not None and e.sub not in (4, 5):
                    e.default = pd.replace("#x", "0x")
                else:
                    e.default = "0"

    # ---- values the manual prints outside their own type or range --------
    fixes = {
        (0x606D, 0): ("max", "65535"),     # UNSIGNED16 (object list) vs UNSIGNED32 (detail)
        (0x60C0, 0): ("range", ""),        # INT16 printed with an INT32 range
        (0x6074, 0): ("default", "0"),     # read-only value printed with default 20
        (0x20A3, 5): ("default", "-600000"),  # not stated: as the sin/cos minimums
        (0x5012, 2): ("default", "68000"),    # not stated: top of the 5013h clamp range
    }
    for (i, s), (k, v) in fixes.items():
        e = objs[i].sub(s)
        if k == "range":
            e.min, e.max = "-32768", "32767"
        else:
            setattr(e, k, v)
    # Defaults of 0 below a printed minimum of 1 on read-only/diagnostic
    # values (2107h, 210Ah Hall patterns) and settings (2201h:08/09, 22E1h:04):
    # the default is kept and the minimum lowered to it.
    for i, s in ((0x2107, 0), (0x210A, 0), (0x22E1, 4)) + tuple((0x2201 + k, t) for k in range(4)
                                                                  for t in (8, 9)):
        e = objs[i].sub(s)
        if e.min and e.default and num(e.default) < num(e.min):
            e.desc = (e.desc + f"; printed minimum {e.min} is above the printed default").strip("; ")
            e.min = e.default
    # 1010h/1011h: writable in NMT Pre-Operational only; reads return 1.
    for i in (0x1010, 0x1011):
        e = objs[i].sub(1)
        e.default, e.write_in = "1", "PreOp"
        objs[i].type = ""
        objs[i].code = "ARRAY"
    objs[0x1C32].type = objs[0x1C33].type = "SM_SYNCHRONISATION"
    objs[0x1C32].name = "SM output parameter"
    objs[0x1C33].name = "SM input parameter"
    for i in (0x1C32, 0x1C33):
        for s in (1, 2):
            objs[i].sub(s).write_in = "PreOp"
        for s in (4, 5):
            objs[i].sub(s).default = ""      # derived from <Dc>
        for s in (2, 3, 5, 6, 9, 10):
            objs[i].sub(s).unit = "ns"
    objs[0x10F1].type = "ERROR_SETTING"
    # 67FFh: "device profile type" of the (multi-axis) device; not stated.
    objs[0x67FF].sub(0).default = "0x00020192"
    objs[0x6061].sub(0).backup = None

    problems = check_values(objs)
    if problems:
        raise SystemExit("welcon: unresolved value problems:\n  " + "\n  ".join(problems))

    pnames = names_of(objs)
    rx, tx = [], []
    for i in range(0x1600, 0x160A):
        fixed = 0x1604 <= i <= 0x1608
        rx.append(pdo_from_mapping(objs[i], f"RxPDO {i - 0x1600 + 1}", pnames, fixed=fixed,
                                   max_entries=None if fixed else 10))
    for i in range(0x1A00, 0x1A0A):
        fixed = 0x1A04 <= i <= 0x1A08
        tx.append(pdo_from_mapping(objs[i], f"TxPDO {i - 0x1A00 + 1}", pnames, fixed=fixed,
                                   max_entries=None if fixed else 10))
    rx[8].sm = 2
    tx[8].sm = 3
    tx[8].comment = ("1C13h:01 is printed as 1A00h, a free PDO that is empty by default; "
                     "1A08h, the counterpart of the default RxPDO 1608h, is assigned instead")

    for i in list(objs):
        if 0x1600 <= i <= 0x1BFF or i in (0x1C00, 0x1C10, 0x1C11, 0x1C12, 0x1C13, 0x1018):
            del objs[i]
    for i in (0x1008, 0x1009, 0x100A):
        del objs[i]                       # derived from <Identity>

    removes = removes_for(repo, objs, keep={0x1008, 0x1009, 0x100A, 0x1018})
    return {
        "header": HEADER,
        "identity": [
            ("vendorId", "#x00000000"), ("vendorName", "Welcon"),
            ("productCode", "#x00000010"), ("revision", "#x00000001"), ("serial", "0"),
            ("name", "Welcon Servo Drive"), ("type", "Welcon-Servo-1axis"), ("groupType", "Servo"),
            ("groupName", "Welcon servo drives"), ("deviceType", "#x00020192"),
            ("hardwareVersion", "unknown"), ("softwareVersion", "0.2041"),
            ("placeholders", "vendorId productCode revision serial type hardwareVersion "
                             "softwareVersion"),
        ],
        "esc": None,
        "mailbox": [("coe", True), ("foe", False), ("eoe", False), ("soe", False),
                    ("sdoInfo", True), ("pdoAssign", True), ("pdoConfig", True),
                    ("completeAccess", False), ("segmentedSdo", True)],
        "sms": [
            (0, "MailboxOut", 0x1000, 128, None, 0x26),
            (1, "MailboxIn", 0x1080, 128, None, 0x22),
            (2, "Outputs", 0x1100, None, 400, 0x64),
            (3, "Inputs", 0x1600, None, 400, 0x20),
        ],
        "fmmus": ["Outputs", "Inputs", "MailboxState"],
        "dc": {
            "attrs": [("minCycleTime", 1000000), ("freeRun", True), ("smSync", True),
                      ("dcSync0", True), ("dcSync1", False)],
            "opmodes": [("FreeRun", "Free Run", 0x0000),
                        ("SM-Synchron", "SM-Synchron", 0x0000),
                        ("DC", "DC-Synchron (Sync0)", 0x0300)],
        },
        "objects": objs,
        "removes": removes,
        "removes_why": "Profile objects that the manual's object list does not contain.",
        "rx": rx, "tx": tx,
        "drive": {"modes": "PP PV HM CSP CSV CST",
                  "homing": "-4 -3 1 2 3 4 5 6 7 8 9 10 11 12 13 14 17 18 19 20 21 22 23 24 25 "
                            "26 27 28 29 30 33 34 35 37",
                  "plant": [
                      ("encoder_resolution", 10000, "inc/rev (608Fh:01)"),
                      ("max_speed", 3000, "rpm (6080h)"),
                      ("rated_torque", 0.1, "N m (6076h)"),
                      ("peak_torque", 0.2, "N m (6072h = 200 %)"),
                      ("torque_constant", 0.075, "N m/A (2004h)"),
                  ]},
    }
