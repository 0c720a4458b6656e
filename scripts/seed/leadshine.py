"""Leadshine iSV2-CAN integrated servo (CANopen DS301/DSP402), presented over
CoE: conversion policy. Every choice is listed in docs/seed-devices.md."""
from __future__ import annotations

import re

from seedlib import (Entry, Obj, PdoSpec, build_object, group, names_of, num, read_rows,
                     removes_for)

CSV = "leadshine-isv2-can-od.csv"

HEADER = """\
  Leadshine iSV2-CAN integrated servo motor (modelled: CAN6040V48, 400 W),
  a CANopen DS301 V4.02 / DSP402 V2.01 drive PRESENTED OVER CoE.
  Source: the iSV2-CAN user manual (shared/seeds/004_*.txt) and its
  digest/CSV; choices in docs/seed-devices.md.

  PLACEHOLDERS: the manual gives no 1018h identity and no 1000h device type.
  vendorId 0 (not an ETG vendor id), productCode and revision are ours;
  deviceType 0x00020192 is the CiA 402 servo value.
  CANopen-only objects (COB-IDs 1005h-1007h/1012h-1015h, heartbeat
  1016h/1017h, SDO server 1200h, PDO communication 1400h-1403h/1800h-1803h)
  have no meaning on EtherCAT and are left out. The manual gives no default
  PDO mapping: the four RxPDOs/TxPDOs carry the CiA 402 predefined mapping,
  and the PP pair (1602h/1A02h) is assigned by default.
  Pr parameters (2xxxh) have no data type in the manual: the type is inferred
  from the printed range (16 bit unless the range needs 32); parameters
  without a range (class 7 factory data and a few others) are left out."""


def _infer_type(lo: str, hi: str) -> str:
    a, b = num(lo), num(hi)
    if a < 0:
        return "INTEGER16" if -32768 <= a and b <= 32767 else "INTEGER32"
    return "UNSIGNED16" if b <= 0xFFFF else "UNSIGNED32"


def build(seed_dir: str, repo: str) -> dict:
    rows = read_rows(f"{seed_dir}/{CSV}")
    can_only = {0x1005, 0x1006, 0x1007, 0x1012, 0x1013, 0x1014, 0x1015, 0x1016, 0x1017,
                0x1200, 0x1400, 0x1401, 0x1402, 0x1403, 0x1800, 0x1801, 0x1802, 0x1803}
    left_out: list[str] = []

    def keep(r: dict) -> bool:
        i = num(r["index"])
        if i in can_only or i in (0x1001, 0x1003):
            return False
        if 0x1600 <= i <= 0x1BFF:
            return False          # built from the RxPdo/TxPdo elements below
        if 0x2000 <= i <= 0x2FFF and not (r["min"] and r["max"]):
            left_out.append(r["index"])
            return False
        if i in (0x3000, 0x3004, 0x5012):
            return False          # nothing but a name is known
        return True

    rows_kept = [r for r in rows if keep(r)]
    for r in rows_kept:
        i = num(r["index"])
        if 0x2000 <= i <= 0x2FFF:
            r["access"] = "RW"
            r["data_type"] = _infer_type(r["min"], r["max"])
            r["pdo_mapping"] = "NO"
        elif i in (0x3001, 0x3002, 0x3003, 0x3010, 0x4000):
            r["data_type"] = "UNSIGNED16"
            r["access"] = "RO" if i in (0x3001, 0x3010) else "RW"
            r["pdo_mapping"] = "NO"
            r["default"] = "0"
    objs: dict[int, Obj] = {i: build_object(i, r) for i, r in group(rows_kept).items()}

    for o in objs.values():
        for e in o.entries:
            if e.default == "" and e.type:
                e.default = "0"
            m = re.match(r"Pr(\d\.\d\d)", e.desc)
            if m and o.index < 0x3000:
                e.desc = re.sub(r"\s*Data type/access not stated; subindex assumed 0x00 "
                                r"\(manual gives index only\)\.", "", e.desc)

    # Pr6.58/6.59: a 32-bit homing position split in two 16-bit halves; the
    # printed +-2147483647 is the range of the whole value.
    for i, t in ((0x2658, "INTEGER16"), (0x2659, "UNSIGNED16")):
        e = objs[i].sub(0)
        e.type, e.min, e.max = t, "", ""
        e.desc = "Half of the 32-bit homing position (range of the whole: +-2147483647). " + e.desc

    fix = {
        # index: (type, access, pdo, default, min, max) -- None keeps the CSV value
        0x605B: ("INTEGER16", None, None, None, None, None),
        0x605C: ("INTEGER16", None, None, None, None, None),
        0x6060: (None, None, None, "1", "-2", "6"),
        0x6061: (None, "ro", "tx", "1", "", ""),
        0x6071: ("INTEGER16", None, None, None, None, None),
        0x607A: (None, None, "rx", None, None, None),
        0x607C: (None, None, "rx", None, None, None),
        0x6098: ("INTEGER8", None, None, None, "-6", "37"),
        0x609A: (None, "rw", "rx", None, None, None),
        0x60FD: (None, None, None, None, "", ""),
        0x6502: (None, None, None, "0x0000002D", "", ""),
    }
    for i, (t, a, p, d, lo, hi) in fix.items():
        e = objs[i].sub(0)
        for attr, v in (("type", t), ("access", a), ("pdo", p), ("default", d), ("min", lo),
                        ("max", hi)):
            if v is not None:
                setattr(e, attr, v)
    for s in (1, 2):
        objs[0x607D].sub(s).pdo = "rx"
        objs[0x60FE].sub(s).max = "0xFFFFFFFF"
    objs[0x607D].sub(0).type = "UNSIGNED8"
    objs[0x607D].name = "Software position limit"
    objs[0x608F].name = "Position encoder resolution"
    objs[0x6091].name = "Gear ratio"
    objs[0x6092].name = "Feed constant"
    objs[0x6099].name = "Homing speeds"
    objs[0x60FE].name = "Digital outputs"
    for i, s, t, a, p in ((0x608F, 2, "UNSIGNED32", "ro", "tx"),
                          (0x6092, 2, "UNSIGNED32", "rw", "rx")):
        e = objs[i].sub(s)
        e.type, e.access, e.pdo = t, a, p
    for i in (0x607D, 0x608F, 0x6091, 0x6092, 0x6099):
        objs[i].sub(0).type = "UNSIGNED8"
        objs[i].sub(0).access = "ro"
        objs[i].sub(0).min = objs[i].sub(0).max = ""
    objs[0x608F].sub(1).default = "10000"
    # 4.1.1: electronic gear changes are "only valid under Pre-operation mode".
    for i in (0x6091, 0x6092):
        for s in (1, 2):
            objs[i].sub(s).write_in = "PreOp"
    for i in (0x608F, 0x6092):
        objs[i].code = "ARRAY"

    # 1003h: "most recent errors are stored in 1003h" -- depth not stated.
    objs[0x1003] = Obj(index=0x1003, name="Pre-defined error field", code="ARRAY", entries=[
        Entry(sub=0, name="Number of errors", type="UNSIGNED8", access="rw", default="0",
              desc="Write 0 to clear (CiA 301). Depth 8 is our choice (not stated)."),
    ] + [Entry(sub=n, name=f"Standard error field {n}", type="UNSIGNED32", access="ro",
               default="0") for n in range(1, 9)])

    names = names_of(objs)

    def pdo(index: int, name: str, ents: list[int], sm: int | None = None) -> PdoSpec:
        bits = {0x6040: 16, 0x6060: 8, 0x607A: 32, 0x60FF: 32, 0x6041: 16, 0x6061: 8,
                0x6064: 32, 0x606C: 32}
        return PdoSpec(index=index, name=name, sm=sm, max_entries=4,
                       entries=[(i, 0, bits[i], names[(i, 0)]) for i in ents])

    rx = [pdo(0x1600, "RxPDO 1", [0x6040]),
          pdo(0x1601, "RxPDO 2", [0x6040, 0x6060]),
          pdo(0x1602, "RxPDO 3 (PP)", [0x6040, 0x607A], sm=2),
          pdo(0x1603, "RxPDO 4 (PV)", [0x6040, 0x60FF])]
    tx = [pdo(0x1A00, "TxPDO 1", [0x6041]),
          pdo(0x1A01, "TxPDO 2", [0x6041, 0x6061]),
          pdo(0x1A02, "TxPDO 3 (PP)", [0x6041, 0x6064], sm=3),
          pdo(0x1A03, "TxPDO 4 (PV)", [0x6041, 0x606C])]
    rx[0].comment = ("CiA 402 predefined PDO mapping (the manual states none; its only "
                     "example, 1A00h = 6041h, matches it). 4 entries: the manual's example")

    removes = removes_for(repo, objs, keep={0x1000, 0x1001, 0x1008, 0x1018, 0x1C32, 0x1C33})
    return {
        "header": HEADER,
        "identity": [
            ("vendorId", "#x00000000"), ("vendorName", "Leadshine Technology Co., Ltd."),
            ("productCode", "#x00006040"), ("revision", "#x00000001"), ("serial", "0"),
            ("name", "iSV2-CAN6040V48"), ("type", "iSV2-CAN6040V48"), ("groupType", "Servo"),
            ("groupName", "iSV2-CAN integrated servo motors"), ("deviceType", "#x00020192"),
            ("placeholders", "vendorId productCode revision deviceType"),
        ],
        "esc": [("dc", False)],
        "mailbox": [("coe", True), ("foe", False), ("eoe", False), ("soe", False),
                    ("sdoInfo", True), ("pdoAssign", True), ("pdoConfig", True),
                    ("completeAccess", False), ("segmentedSdo", True)],
        "sms": [
            (0, "MailboxOut", 0x1000, 128, None, 0x26),
            (1, "MailboxIn", 0x1080, 128, None, 0x22),
            (2, "Outputs", 0x1100, None, 32, 0x64),
            (3, "Inputs", 0x1400, None, 32, 0x20),
        ],
        "fmmus": ["Outputs", "Inputs", "MailboxState"],
        "dc": {
            "attrs": [("minCycleTime", 1000000), ("freeRun", True), ("smSync", True),
                      ("dcSync0", False), ("dcSync1", False)],
            "opmodes": [("FreeRun", "Free Run (CANopen event-driven PDOs)", 0x0000),
                        ("SM-Synchron", "SM-Synchron (CANopen SYNC)", 0x0000)],
        },
        "objects": objs,
        "removes": removes,
        "removes_why": ("Profile objects the manual does not list. 1010h/1011h: parameters "
                        "are saved through 3002h instead. 1C32h/1C33h stay: they describe "
                        "the CoE presentation, not the CANopen drive."),
        "rx": rx, "tx": tx,
        "left_out": left_out,
        "drive": {"modes": "PP PV PT HM",
                  "homing": ("-6 -5 -4 -3 -2 -1 1 2 3 4 5 6 7 8 9 10 11 12 13 14 17 18 19 20 21 "
                             "22 23 24 25 26 27 28 29 30 33 34 35 37"),
                  "plant": [
                      ("encoder_resolution", 10000, "inc/rev (608Fh:01)"),
                      ("max_speed", 6000, "rpm (6080h)"),
                      ("over_speed", 7200, "rpm (Pr5.13 = 0: 1.2 x maximum)"),
                      ("rated_torque", 3.0, "N m (6076h)"),
                      ("peak_torque", 9.0, "N m (6072h = 300 %)"),
                  ]},
    }
