"""SIMTACH RSE (V3) EtherCAT servo: policy for the CSV -> device-file conversion.
Every deviation from the CSV is listed in docs/seed-devices.md."""
from __future__ import annotations

import re

from seedlib import (Entry, Obj, build_object, group, names_of, pdo_from_mapping,
                     read_rows, removes_for)

CSV = "simtach-rse-ethercat-od.csv"
OUT = "simtach-rse.xml"

HEADER = """\
  SIMTACH RSE series (V3.0/V3.1) EtherCAT AC servo drive, modelled as the
  RS400E (Appendix A factory motor data are a 400 W motor;
  the TwinCAT example scans an RS750E). CoE only, CiA 402.
  Source: the "RSE EtherCAT Series Servo User Manual" (shared/seeds/002_*.txt)
  and its digest/CSV; choices in docs/seed-devices.md.

  Identity: vendor id 0x0A880000, product code 0x00100000, revision
  0x00010A88 are the manual's 1018h values as printed (the vendor id looks
  word-swapped but is kept). Hardware/software version strings are
  "determined by version" in the manual: PLACEHOLDERS.
  Not stated and chosen by us: SM addresses/sizes/control bytes, FMMU
  count, mailbox size, minimum cycle time (printed 0xE8480000, read as
  125000 ns), SDO complete access / segmented transfer (off)."""


def _reserved(e: Entry) -> None:
    m = re.match(r"Reserved \[AppA (P\d\d\.\d\d): (.*)\]$", e.name)
    if m:
        e.desc = f"Reserved in Ch7; Appendix A maps {m.group(1)} ({m.group(2)}) here. " + e.desc
        e.name = "Reserved"
    if e.name == "(unnamed)":
        e.name = "Reserved"


def build(seed_dir: str, repo: str) -> dict:
    rows = read_rows(f"{seed_dir}/{CSV}")
    by_index = group(rows)
    objs: dict[int, Obj] = {i: build_object(i, r) for i, r in by_index.items()}

    # ---- fixes where the manual is silent or contradicts itself ----------
    for o in objs.values():
        for e in o.entries:
            _reserved(e)
            if e.default == "" and e.type and e.type != "VISIBLE_STRING":
                e.default = "0"          # run-time values: start at 0
            if e.default.upper() == "TRUE":
                e.default = "true"
    # 2002h: the manual says ARRAY but sub 02/08 are UDINT and 09 DINT.
    objs[0x2002].code = "RECORD"
    # 200Ah: sub0 printed 10 while entries run to 12h.
    objs[0x200A].sub(0).default = "18"
    # 2005h subs 02..08: PDO column lost in the dump; as sub 01 (YES -> rx).
    for e in objs[0x2005].entries[2:]:
        e.pdo = "rx"
    # 2008h:0A is a setting (AppA P05.16) like :0B/:0C but printed RO.
    objs[0x2008].sub(0x0A).access = "rw"
    # 60FEh:01/02 printed RO but written by the master (CiA 402: rw, RxPDO).
    for s in (1, 2):
        objs[0x60FE].sub(s).access = "rw"
        objs[0x60FE].sub(s).pdo = "rx"
    objs[0x60FE].sub(0).pdo = "none"
    # 1C32h/1C33h:05 minimum cycle time printed 0xE8480000 (3.9 s).
    for i in (0x1C32, 0x1C33):
        e = objs[i].sub(5)
        e.default = "125000"
        e.desc = ("Printed 0xE8480000 (3.9 s, implausible); read as 0x0001E848 = 125000 ns. "
                  "Allowed cycle times are not stated.")
        objs[i].code = "RECORD"
        objs[i].type = "SM_SYNCHRONISATION"
    # 1C33h:20 default "-": no sync error reported = FALSE.
    objs[0x1C33].sub(0x20).default = "false"
    objs[0x1C32].sub(0x20).default = "false"
    # 6502h printed as a second "60FFh".
    objs[0x6502].name = "Supported drive modes"
    # 605Dh is referenced (6040h bit 8) but never defined: the profile's
    # CiA 402 definition stays.
    del objs[0x605D]

    # Descriptions that pointed at the digest: the facts themselves.
    for e in objs[0x2004].entries + objs[0x2005].entries:
        e.desc = e.desc.replace("FunIN code 0-31 (see digest)", "FunIN code 0-31 (see 2004h)")
    objs[0x2004].desc = (
        "FunIN codes: 0 normal input, 1 servo enable, 2 alarm clear, 3 pulse inhibit, 4 clear "
        "position deviation, 5 positive limit, 6 negative limit, 7 gain switch, 8 gear-ratio "
        "switch, 9 zero-speed clamp, 10 control mode select 1, 11 emergency stop, 12 position "
        "command inhibit, 13 step position trigger, 14-17 multi-segment switch 1-4, 18 torque "
        "direction, 19 speed direction, 20 position direction, 21 multi-segment position enable, "
        "22 back-to-home input, 23 home switch, 24-28 USER1-5, 29 control mode select 2, "
        "30 probe 1, 31 probe 2.")
    objs[0x2005].desc = (
        "FunOUT codes: 0 holding brake, 1 alarm, 2 position reached, 3 speed reached, 4 servo "
        "ready, 5 internal position command shutdown, 6 homing complete, 7-12 USER1-6, 13 torque "
        "reached, 14 out of tolerance, 15-30 reserved, 31 universal output (60FEh).")
    objs[0x6040].sub(0).desc = (
        "bit 0 switch on, 1 enable voltage, 2 quick stop (0 = active), 3 enable operation, "
        "4-6 mode specific, 7 fault reset (rising edge; while 1 other commands are ignored), "
        "8 halt, 9 mode specific (undefined), 10 reserved, 11-15 manufacturer (unused).")
    objs[0x6041].sub(0).desc = (
        "bit 0 ready to switch on, 1 switched on, 2 operation enabled, 3 fault, 4 voltage "
        "enabled, 5 quick stop, 6 switch on disabled, 7 warning, 9 remote, 10 target reached, "
        "11 internal limit active, 12-13 mode specific, 15 home found (manufacturer). Values "
        "(Ch6.2): 0250h switch on disabled, 0231h ready, 0233h switched on, 0237h operation "
        "enabled, 0217h quick stop, 021Fh fault reaction, 0218h fault.")
    e = objs[0x6098].sub(0)
    e.desc = e.desc.replace(" (see digest)", "")

    names = names_of(objs)
    rx_names = {0x1600: "RxPDO 1 (CSP)", 0x1601: "RxPDO 2 (PP)", 0x1602: "RxPDO 3 (PV)"}
    tx_names = {0x1A00: "TxPDO 1 (CSP)", 0x1A01: "TxPDO 2", 0x1A02: "TxPDO 3"}
    rx = [pdo_from_mapping(objs[i], n, names, excludes=[x for x in rx_names if x != i])
          for i, n in rx_names.items()]
    tx = []
    for i, n in tx_names.items():
        o = objs[i]
        if i == 0x1A02:
            # Ch7 prints sub0 = 0 (empty); Ch5 gives 6041h + 6064h. Ch5 taken.
            o.sub(0).default = "2"
            o.sub(1).default = "0x60410010"
            o.sub(2).default = "0x60640020"
        tx.append(pdo_from_mapping(o, n, names, excludes=[x for x in tx_names if x != i]))
    rx[0].sm = 2
    tx[0].sm = 3
    tx[2].comment = ("1A02h default: Ch7 prints it empty (sub0 = 0), Ch5 maps "
                     "6041h + 6064h; Ch5 is used")

    # Generated by the loader from the PDO elements / identity.
    for i in list(objs):
        if 0x1600 <= i <= 0x1BFF or i in (0x1C00, 0x1C12, 0x1C13, 0x1018):
            del objs[i]

    # 1008h-100Ah: strings, derived from <Identity>; 1010h/1011h: CiA 301.
    for i in (0x1008, 0x1009, 0x100A):
        del objs[i]
    for i, sig in ((0x1010, "save"), (0x1011, "load")):
        o = objs[i]
        e = o.entries[-1]
        e.type, e.default = "UNSIGNED32", "1"
        e.desc = (f"Write the signature \"{sig}\" to execute (Appendix A). Read value 1 = "
                  "device saves on command (CiA 301; manual silent). " + e.desc)
        o.code = "ARRAY"
    objs[0x1010].name = "Store parameters"
    objs[0x1011].name = "Restore default parameters"
    removes = removes_for(repo, objs, keep={0x1008, 0x1009, 0x100A, 0x1018, 0x605D})

    return {
        "header": HEADER,
        "identity": [
            ("vendorId", "#x0A880000"), ("vendorName", "SIMTACH"),
            ("productCode", "#x00100000"), ("revision", "#x00010A88"), ("serial", "0"),
            ("name", "RS400E"), ("type", "RS400E"), ("groupType", "Servo"),
            ("groupName", "RSE EtherCAT servo drives"), ("deviceType", "#x00020192"),
            ("hardwareVersion", "unknown"), ("softwareVersion", "unknown"),
            ("placeholders", "hardwareVersion softwareVersion"),
        ],
        "esc": None,
        "mailbox": [("coe", True), ("foe", False), ("eoe", False), ("soe", False),
                    ("sdoInfo", True), ("pdoAssign", True), ("pdoConfig", True),
                    ("completeAccess", False), ("segmentedSdo", False)],
        "sms": [
            (0, "MailboxOut", 0x1000, 128, None, 0x26),
            (1, "MailboxIn", 0x1080, 128, None, 0x22),
            (2, "Outputs", 0x1100, None, 48, 0x64),
            (3, "Inputs", 0x1400, None, 48, 0x20),
        ],
        "fmmus": ["Outputs", "Inputs", "MailboxState"],
        "dc": {
            "attrs": [("minCycleTime", 125000), ("freeRun", True), ("smSync", True),
                      ("dcSync0", True), ("dcSync1", True)],
            "opmodes": [("SM-Synchron", "SM-Synchron", 0x0000),
                        ("DC", "DC-Synchron (Sync0)", 0x0300)],
        },
        "objects": objs,
        "removes": removes,
        "removes_why": ("Profile objects that the manual's object dictionary (Ch7) does not "
                        "list. 605Dh is kept: 6040h bit 8 refers to it although it is never "
                        "defined."),
        "rx": rx, "tx": tx,
        "drive": {"modes": "PP PV PT HM CSP CSV CST",
                  "homing": "17 18 19 20 21 22 23 24 25 26 27 28 29 30 35",
                  "plant": [
                      ("encoder_resolution", 131072, "inc/rev (2002h:03 = 17 bit)"),
                      ("rated_speed", 3000, "rpm (2000h:05)"),
                      ("max_speed", 5000, "rpm (2000h:06)"),
                      ("rated_torque", 1.27, "N m (2000h:07)"),
                      ("peak_torque", 3.82, "N m (2000h:08)"),
                      ("rotor_inertia", 0.63e-4, "kg m^2 (2000h:09)"),
                      ("torque_constant", 0.55, "N m/A (2000h:0E)"),
                  ]},
    }
