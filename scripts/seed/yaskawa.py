"""Yaskawa Sigma-V-SD (CACR-JU, one axis) EtherCAT CoE: conversion policy.
Every deviation from the CSV is listed in docs/seed-devices.md."""
from __future__ import annotations

from seedlib import (Obj, build_object, group, names_of, num, pdo_from_mapping, read_rows,
                     removes_for, strip_notes, take_flag)

CSV = "yaskawa-sigma5-sd-coe-od.csv"

HEADER = """\
  Yaskawa Sigma-V-SD SERVOPACK (CACR-JU, ONE-AXIS model, product code
  0x02200201) with its EtherCAT (CoE) module, command profile CiA 402.
  Source: manual SIEP S800000 95 <3> (shared/seeds/003_*.txt) and its
  digest/CSV; choices in docs/seed-devices.md.

  The ESC does not process APRW/FPRW/BRW/LRW (manual 1.3/2.1):
  noReadWrite="true" noLrw="true". SII is 256 bytes. Mailboxes 2 x 128 bytes
  at 1000h/1080h, process data 0..256 bytes at 1100h/1400h (manual).
  Free-Run or DC Sync0, cycle 250 us..4 ms in 250 us steps (the step is not
  expressible in the format).

  Identity: vendor id 0x00000539 and product code 0x02200201 are the
  manual's. The revision number is NOT STATED (bit layout figure lost):
  revision is a PLACEHOLDER, and so is the 100Ah software version string
  (the manual gives only its shape "xxxx.*** (D:0000)").
  Two-axis objects (axis 2 at +800h / +400h, PDOs 1610h/1A10h) are not
  modelled. Servo parameters 2000h-22FFh and 5C00h are left out: the manual
  gives no data type, access or range for them (it defers to SIEP S800000 94)."""


def build(seed_dir: str, repo: str) -> dict:
    rows = read_rows(f"{seed_dir}/{CSV}")

    def keep(r: dict) -> bool:
        i = num(r["index"])
        if 0x2000 <= i <= 0x22FF or i == 0x5C00:
            return False          # Pn parameters: no type/access in this manual
        if i in (0x1610, 0x1A10):
            return False          # axis 2 of the two-axis SERVOPACK
        return True

    objs: dict[int, Obj] = {i: build_object(i, r) for i, r in group(rows, keep).items()}

    for o in objs.values():
        for e in o.entries:
            if e.default == "" and e.type and e.type != "VISIBLE_STRING":
                e.default = "0"
            take_flag(e, r"EEPROM=(Yes|No)")
            strip_notes(e, [r"EEPROM=(Yes|No)( in [0-9.]+ but No in appendix 5\.1)?",
                            r"axis 2 index = \+0x[48]00",
                            r"SM[23] \(process data (output|input)\) synchronization;?"])

    # Two-axis variants in the CSV: keep the one-axis values.
    objs[0x1018].sub(2).default = "0x02200201"
    objs[0xF000].sub(2).default = "1"
    objs[0xF000].sub(2).desc = "1 = one-axis SERVOPACK (2 on the two-axis unit). " + objs[0xF000].sub(2).desc
    for i, pdo in ((0x1C12, "0x1600"), (0x1C13, "0x1A00")):
        objs[i].sub(0).default = "1"
    for i in (0x1600, 0x1A00):
        objs[i].sub(0).max = "16"

    # 6072h: "set automatically to the motor's max torque at power ON".
    e = objs[0x6072].sub(0)
    e.default = "3000"
    e.desc = ("Set automatically to the motor's maximum torque at power ON (manual); "
              "the emulated motor's maximum is 300.0 % (our choice). " + e.desc)
    e = objs[0x6076].sub(0)
    e.default = "5390"
    e.desc = "Value not stated (motor dependent); 5390 mN m is the emulated motor's. " + e.desc

    # 1C32h/1C33h: the manual's own layout (sub 0 = 12 / 10; 0Ch = SM2
    # event miss count). 1C32h:01/02 are RO: the mode comes from 0980h.
    for i in (0x1C32, 0x1C33):
        objs[i].code = "RECORD"
        objs[i].name = "SM output parameter" if i == 0x1C32 else "SM input parameter"
    for i in (0x10F1, 0x1010, 0x1011, 0x2301, 0x2302, 0x2303, 0x2304, 0x23C8, 0x2310,
              0x60C2, 0xF000):
        objs[i].code = "RECORD" if i in (0x10F1, 0x2310, 0x23C8, 0x60C2, 0xF000) else "ARRAY"
    objs[0x1010].name = "Store parameters"
    objs[0x1011].name = "Restore default parameters"
    objs[0x10F1].name = "Sync error setting"
    objs[0x2301].name = "Position user unit"
    objs[0x2302].name = "Velocity user unit"
    objs[0x2303].name = "Acceleration user unit"
    objs[0x2304].name = "Torque user unit"
    objs[0x2310].name = "SERVOPACK adjusting command"
    objs[0x23C8].name = "Machine tools object"
    objs[0x607D].name = "Software position limit"
    objs[0x6099].name = "Homing speeds"
    objs[0x60C1].name = "Interpolation data record"
    objs[0x60C2].name = "Interpolation time period"
    objs[0xF000].name = "Modular device profile"
    # 2310h: STRING[16] of binary bytes; the appendix's "0..0xFF" limits are per byte.
    for s in (1, 3):
        e = objs[0x2310].sub(s)
        e.length, e.default, e.min, e.max = 16, "", "", ""

    objs[0x60B8].sub(0).desc = (
        "PnB64. bit 0 enable TP1, 1 continuous (0 = first event), 2 trigger: 0 Probe1 input, "
        "1 encoder phase C, 4 enable sampling TP1, 8 enable TP2, 9 continuous, 10 trigger "
        "(0 Probe2), 12 enable sampling TP2; others reserved (no negative-edge bits).")

    names = names_of(objs)
    rx = [pdo_from_mapping(objs[0x1600], "1st receive PDO mapping", names, sm=2)]
    tx = [pdo_from_mapping(objs[0x1A00], "1st transmit PDO mapping", names, sm=3)]

    for i in list(objs):
        if 0x1600 <= i <= 0x1BFF or i in (0x1C00, 0x1C10, 0x1C11, 0x1C12, 0x1C13, 0x1018,
                                          0x1008, 0x100A):
            del objs[i]

    removes = removes_for(repo, objs, keep={0x1008, 0x100A, 0x1018})
    return {
        "header": HEADER,
        "identity": [
            ("vendorId", "#x00000539"), ("vendorName", "YASKAWA ELECTRIC CORPORATION"),
            ("productCode", "#x02200201"), ("revision", "#x00010001"), ("serial", "0"),
            ("name", "CACR-JU102ACA"), ("type", "CACR-JU102ACA"), ("groupType", "Servo"),
            ("groupName", "Sigma-V-SD SERVOPACKs"), ("deviceType", "#x00020192"),
            ("softwareVersion", "0001.000 (D:0000)"),
            ("placeholders", "revision softwareVersion"),
        ],
        "esc": [("eepromSize", 256), ("noLrw", True), ("noReadWrite", True)],
        "mailbox": [("coe", True), ("foe", False), ("eoe", False), ("soe", False),
                    ("sdoInfo", True), ("pdoAssign", True), ("pdoConfig", True),
                    ("completeAccess", False), ("segmentedSdo", True)],
        "sms": [
            (0, "MailboxOut", 0x1000, 128, None, 0x26),
            (1, "MailboxIn", 0x1080, 128, None, 0x22),
            (2, "Outputs", 0x1100, None, 256, 0x64),
            (3, "Inputs", 0x1400, None, 256, 0x20),
        ],
        "fmmus": ["Outputs", "Inputs", "MailboxState"],
        "dc": {
            "attrs": [("minCycleTime", 250000), ("maxCycleTime", 4000000), ("freeRun", True),
                      ("smSync", False), ("dcSync0", True), ("dcSync1", False)],
            "opmodes": [("FreeRun", "Free Run", 0x0000),
                        ("DC", "DC-Synchron (Sync0)", 0x0300)],
        },
        "objects": objs,
        "removes": removes,
        "removes_why": ("Profile objects that this manual's object dictionary does not list "
                        "(no 60BBh/60BDh: the drive latches rising edges only)."),
        "rx": rx, "tx": tx,
        "drive": {"modes": "PP PV PT HM IP CSP CSV CST",
                  "homing": "1 2 7 8 9 10 11 12 13 14 24 28 33 34 35",
                  "plant": [
                      ("encoder_resolution", 1048576, "inc/rev (the manual's 20-bit example)"),
                      ("rated_torque", 5.39, "N m (6076h, our choice)"),
                      ("peak_torque", 16.17, "N m (300 %, 6072h, our choice)"),
                  ]},
    }
