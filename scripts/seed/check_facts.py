#!/usr/bin/env python3
"""Checks the committed seed device files against facts taken straight from
the manuals (not from the converter), so a hand edit that breaks one is
caught. Run from anywhere: scripts/seed/check_facts.py  (exit 1 on a miss).
The C++ loader test (tests/esi, every file in xml/devices) checks that the
files load, give a schema-valid ESI and an SII that fits."""
from __future__ import annotations

import os
import sys
import xml.etree.ElementTree as ET

REPO = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def n(text: str) -> int:
    return int(text.replace("#x", "0x"), 0)


def load(name: str) -> ET.Element:
    return ET.parse(os.path.join(REPO, "xml", "devices", name)).getroot()


def assigned_bytes(root: ET.Element, tag: str) -> int:
    bits = sum(n(e.get("bits")) for p in root.iter(tag) if p.get("sm") is not None
               for e in p.iter("Entry"))
    return bits // 8


def obj(root: ET.Element, index: int) -> ET.Element | None:
    for o in root.iter("Object"):
        if n(o.get("index")) == index:
            return o
    return None


def default(root: ET.Element, index: int, sub: int = 0) -> int:
    o = obj(root, index)
    if sub == 0 and o.get("default") is not None:
        return n(o.get("default"))
    for e in o.iter("Entry"):
        if n(e.get("sub")) == sub:
            return n(e.get("default"))
    raise KeyError(f"{index:04X}:{sub}")


FACTS = []


def fact(file: str):
    def wrap(fn):
        FACTS.append((file, fn))
        return fn
    return wrap


@fact("simtach-rse.xml")
def simtach(r: ET.Element) -> list[tuple[str, object, object]]:
    ident = r.find("Identity")
    return [
        ("1018h:01 vendor id (Ch7)", n(ident.get("vendorId")), 0x0A880000),
        ("1018h:02 product code (Ch7)", n(ident.get("productCode")), 0x00100000),
        ("1018h:03 revision (Ch7)", n(ident.get("revision")), 0x00010A88),
        ("default RxPDO 1600h = 8 bytes (Omron example)", assigned_bytes(r, "RxPdo"), 8),
        ("default TxPDO 1A00h = 19 bytes (Omron example)", assigned_bytes(r, "TxPdo"), 19),
        ("6502h supported modes", default(r, 0x6502), 0x3AD),
        ("6098h default homing method", default(r, 0x6098), 17),
        ("6060h default CSP", default(r, 0x6060), 8),
        ("1C32h:02 cycle 4 ms", default(r, 0x1C32, 2), 4000000),
        ("homing methods 17-30, 35", r.find("Drive").get("homingMethods").split(),
         [str(x) for x in list(range(17, 31)) + [35]]),
    ]


@fact("yaskawa-sigma5-sd.xml")
def yaskawa(r: ET.Element) -> list[tuple[str, object, object]]:
    ident, esc, dc = r.find("Identity"), r.find("Esc"), r.find("Dc")
    sms = {n(s.get("index")): s for s in r.iter("Sm")}
    return [
        ("vendor id 539h", n(ident.get("vendorId")), 0x539),
        ("product code one axis", n(ident.get("productCode")), 0x02200201),
        ("no APRW/FPRW/BRW (1.3)", esc.get("noReadWrite"), "true"),
        ("no LRW (1.3)", esc.get("noLrw"), "true"),
        ("SII 256 bytes", n(esc.get("eepromSize")), 256),
        ("SM0/SM1/SM2/SM3 start", [n(sms[i].get("start")) for i in range(4)],
         [0x1000, 0x1080, 0x1100, 0x1400]),
        ("mailbox 128 bytes", [n(sms[i].get("size")) for i in (0, 1)], [128, 128]),
        ("process data up to 256 bytes", [n(sms[i].get("maxSize")) for i in (2, 3)], [256, 256]),
        ("default RxPDO 16 bytes", assigned_bytes(r, "RxPdo"), 16),
        ("default TxPDO 20 bytes", assigned_bytes(r, "TxPdo"), 20),
        ("DC cycle 250 us .. 4 ms", (n(dc.get("minCycleTime")), n(dc.get("maxCycleTime"))),
         (250000, 4000000)),
        ("no SM-synchron (1C32h:04 = 5)", (dc.get("smSync"), default(r, 0x1C32, 4)), ("false", 5)),
        ("6502h", default(r, 0x6502), 0x3ED),
        ("10F1h:02 sync error limit 9", default(r, 0x10F1, 2), 9),
        ("revision is a placeholder", "revision" in ident.get("placeholders").split(), True),
    ]


@fact("welcon-servo.xml")
def welcon(r: ET.Element) -> list[tuple[str, object, object]]:
    rx = {n(p.get("index")): p for p in r.iter("RxPdo")}
    return [
        ("1C12h:01 = 1608h", [i for i, p in rx.items() if p.get("sm")], [0x1608]),
        ("1604h-1608h fixed", [rx[i].get("fixed") for i in range(0x1604, 0x1609)], ["true"] * 5),
        ("6502h as printed", default(r, 0x6502), 0x3AF),
        ("6098h default 35", default(r, 0x6098), 35),
        ("6060h default 3", default(r, 0x6060), 3),
        ("605Ah default 6", default(r, 0x605A), 6),
        ("60C2h 2 x 10^-3 s", (default(r, 0x60C2, 1), default(r, 0x60C2, 2)), (2, -3)),
        ("axis 2 not modelled", [o.get("index") for o in r.iter("Object")
                                 if 0x2800 <= n(o.get("index")) <= 0x2FFF
                                 or 0x6800 <= n(o.get("index")) <= 0x6FFF], []),
        ("identity placeholders", "vendorId" in r.find("Identity").get("placeholders"), True),
    ]


@fact("leadshine-isv2-can.xml")
def leadshine(r: ET.Element) -> list[tuple[str, object, object]]:
    return [
        ("modes PP PV PT HM only", r.find("Drive").get("modes"), "PP PV PT HM"),
        ("6098h default 19", default(r, 0x6098), 19),
        ("609Ah default 500000", default(r, 0x609A), 500000),
        ("6092h:01 10000 pulses/rev", default(r, 0x6092, 1), 10000),
        ("3002h EEPROM trigger present", obj(r, 0x3002) is not None, True),
        ("no CAN COB-ID objects", [i for i in (0x1005, 0x1014, 0x1400, 0x1800)
                                   if obj(r, i) is not None], []),
        ("vendor id is a placeholder",
         "vendorId" in r.find("Identity").get("placeholders").split(), True),
    ]


def main() -> int:
    bad = 0
    for file, fn in FACTS:
        for what, got, want in fn(load(file)):
            if got != want:
                bad += 1
                print(f"{file}: {what}: got {got!r}, want {want!r}")
    print(f"{len(FACTS)} files checked, {bad} mismatches")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
