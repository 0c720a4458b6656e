#!/usr/bin/env python3
"""Sends random and mutated EtherCAT frames (EtherType 88A4h) on a raw socket.

Used by tests/scripts/fault_random_frames.sh while a master keeps the segment
in Op. Frames are made from a seeded PRNG (reproducible with --seed):
  - random: a random EtherCAT header (length, type) and random payload bytes;
  - mutated: a well-formed datagram chain (ETG.1000.4 §5.2: 10-byte header,
    data, 2-byte WKC; "more" bit 15 of the length word) with random commands,
    addresses, lengths, flags and bytes flipped, truncated or extended.
With --safe, every datagram command is forced to a read or an unknown code
(no write may reach the slave), so the master's process data must stay
exact. Without it anything goes (writes to any register included).
Prints the number of frames sent and of EtherCAT replies seen.
"""
import argparse
import random
import socket
import struct
import time

ETHERTYPE_ECAT = 0x88A4
TYPE_DATAGRAMS = 1
MAX_PAYLOAD = 1498
# Commands (ETG.1000.4 Table 12): NOP APRD APWR APRW FPRD FPWR FPRW BRD BWR BRW LRD LWR LRW ARMW FRMW
READS = [0, 1, 4, 7, 10]
UNKNOWN = list(range(15, 256))


def datagram_chain(rng, safe):
    out = bytearray()
    n = rng.randint(1, 6)
    for k in range(n):
        cmd = rng.choice(READS + UNKNOWN[:8]) if safe else rng.randrange(256)
        length = rng.choice([0, 1, 2, 4, 8, rng.randrange(64), rng.randrange(300)])
        more = 0x8000 if k + 1 < n else 0
        flags = rng.choice([0, 0, 0x4000, 0x0800, rng.randrange(0x10000) & 0x7800])
        addr = rng.choice([rng.randrange(1 << 32), (0x1001 | (rng.randrange(0x1000) << 16)),
                           rng.randrange(0x1000) << 16, 0x00010000 * 0x0130])
        out += struct.pack('<BBIHH', cmd, rng.randrange(256), addr, (length & 0x7FF) | more | flags,
                           rng.randrange(0x10000))
        out += rng.randbytes(length)
        out += struct.pack('<H', rng.randrange(4))
    return out


def frame(rng, src_mac, safe):
    kind = rng.random()
    if kind < 0.3 and not safe:
        body = rng.randbytes(rng.randrange(MAX_PAYLOAD))
        hdr = rng.randrange(0x10000)
    else:
        body = datagram_chain(rng, safe)
        hdr = (len(body) & 0x7FF) | (TYPE_DATAGRAMS << 12)
        if rng.random() < 0.2:  # wrong header length or type
            hdr = rng.randrange(0x10000) if not safe else (rng.randrange(0x800) | (TYPE_DATAGRAMS << 12))
        if rng.random() < 0.2:  # truncated or extended
            cut = rng.randrange(len(body) + 1)
            body = body[:cut] if rng.random() < 0.5 else body + rng.randbytes(cut % 64)
        if not safe and rng.random() < 0.2:  # flipped bits anywhere
            b = bytearray(body)
            for _ in range(rng.randint(1, 4)):
                if b:
                    b[rng.randrange(len(b))] ^= 1 << rng.randrange(8)
            body = bytes(b)
    payload = struct.pack('<H', hdr) + body
    payload = payload[:MAX_PAYLOAD + 2]
    eth = b'\xff' * 6 + src_mac + struct.pack('>H', ETHERTYPE_ECAT)
    data = eth + payload
    return data + bytes(max(0, 60 - len(data)))


def recover_frame(src_mac):
    """One frame that switches write protection off again (Beckhoff ESC
    datasheet II 0x0020/0x0021, 0x0030/0x0031: the enable bit is valid for
    the rest of the frame, so enable + clear go together; both enables
    first, since ESC write protection also blocks the write to 0x0021).
    Random writes can switch protection on; a real ESC keeps it until reset
    too."""
    BWR = 8
    regs = [(0x0020, 1), (0x0030, 1), (0x0021, 0), (0x0031, 0)]
    body = bytearray()
    for k, (reg, value) in enumerate(regs):
        more = 0x8000 if k + 1 < len(regs) else 0
        body += struct.pack('<BBIHH', BWR, 0, reg << 16, 1 | more, 0) + bytes([value]) + b'\x00\x00'
    data = b'\xff' * 6 + src_mac + struct.pack('>H', ETHERTYPE_ECAT)
    data += struct.pack('<H', len(body) | (TYPE_DATAGRAMS << 12)) + body
    return data + bytes(max(0, 60 - len(data)))


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument('--iface', required=True)
    ap.add_argument('--count', type=int, default=100000)
    ap.add_argument('--seed', type=int, default=1)
    ap.add_argument('--safe', action='store_true')
    ap.add_argument('--recover', action='store_true', help='end with a frame that clears write protection')
    ap.add_argument('--rate', type=float, default=0, help='frames per second (0: as fast as possible)')
    a = ap.parse_args()
    rng = random.Random(a.seed)
    s = socket.socket(socket.AF_PACKET, socket.SOCK_RAW, socket.htons(ETHERTYPE_ECAT))
    s.bind((a.iface, ETHERTYPE_ECAT))
    s.setblocking(False)
    src_mac = bytes([0x04, 0x00, 0x00, 0xFA, 0x22, 0x00])  # unicast, not marked as returned
    sent = replies = 0
    start = time.monotonic()
    for i in range(a.count):
        f = frame(rng, src_mac, a.safe)
        while True:
            try:
                s.send(f)
                break
            except BlockingIOError:
                time.sleep(0.0005)
        sent += 1
        try:
            while True:
                r = s.recv(2048)
                if r[6:12] != src_mac:
                    replies += 1
        except BlockingIOError:
            pass
        if a.rate > 0:
            ahead = (i + 1) / a.rate - (time.monotonic() - start)
            if ahead > 0:
                time.sleep(ahead)
    if a.recover:
        time.sleep(0.1)
        s.send(recover_frame(src_mac))
        sent += 1
    print(f'sent {sent} other-frames-seen {replies} seconds {time.monotonic() - start:.1f}')


if __name__ == '__main__':
    main()
