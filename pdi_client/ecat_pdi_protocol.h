/* The PDI host protocol (docs/pdi-host.md): how a firmware process reaches
 * the PDI of an ESC emulated by `ecat-slave --pdi-host PATH`, over a Unix
 * stream socket. C99, shared by the host (C++) and libecat_pdi (C).
 *
 * Every message, both ways, is a 4-byte header and a payload:
 *   byte 0    type (ECAT_PDI_MSG_*)
 *   byte 1    0 (reserved; anything else is a malformed message)
 *   byte 2-3  payload length, little endian (0..65535)
 * All numbers in payloads are little endian. Requests are answered in order,
 * one reply each (type | ECAT_PDI_REPLY); the host sends ECAT_PDI_MSG_HELLO
 * first and ECAT_PDI_MSG_LINES notifications between replies at any time. */
#ifndef ECAT_PDI_PROTOCOL_H
#define ECAT_PDI_PROTOCOL_H

#define ECAT_PDI_PROTOCOL_VERSION 1u
#define ECAT_PDI_HEADER_SIZE 4u
#define ECAT_PDI_MAX_PAYLOAD 65535u

/* Requests (firmware -> host) and their replies (type | ECAT_PDI_REPLY). */
#define ECAT_PDI_REPLY 0x80u
/* READ: u16 address, u16 length (1..65535, address + length <= 0x10000).
 * Reply: the `length` bytes read (direct PDI only). */
#define ECAT_PDI_MSG_READ 0x01u
/* WRITE: u16 address, the bytes (address + count <= 0x10000). Reply: empty
 * (direct PDI only). */
#define ECAT_PDI_MSG_WRITE 0x02u
/* SPI: the MOSI bytes of one transaction (chip select asserted for all of
 * them). Reply: as many MISO bytes (lan9252 / et1100-spi PDI only). */
#define ECAT_PDI_MSG_SPI 0x03u
/* TIME: empty. Reply: u64 the ESC's local time in ns (the clock the
 * emulation runs on; 0x0910 counts from it). */
#define ECAT_PDI_MSG_TIME 0x04u
/* LINES: empty. Reply: the lines payload (below), as they are now. */
#define ECAT_PDI_MSG_LINES 0x05u

/* Host -> firmware, unasked. */
/* HELLO, first message after connecting: u16 protocol version, u8 chip
 * (ECAT_PDI_CHIP_*), u8 0. */
#define ECAT_PDI_MSG_HELLO 0xC0u
/* LINES notification: sent when the AL event request 0x0220, the IRQ line
 * or a SYNC pulse changed since the last one. Payload (20 bytes):
 *   u32 AL event request 0x0220, u32 AL event mask 0x0204,
 *   u8 IRQ line (1 asserted: 0x0220 & 0x0204 != 0, or the LAN9252's IRQ pin),
 *   u8 SYNC pulses since the last lines message (bit 0 SYNC0, bit 1 SYNC1),
 *   u16 0, u64 the ESC's local time in ns. */
#define ECAT_PDI_MSG_NOTIFY 0xC1u
#define ECAT_PDI_LINES_SIZE 20u
#define ECAT_PDI_SYNC0 0x01u
#define ECAT_PDI_SYNC1 0x02u

/* The PDI the host offers (--pdi-chip). */
#define ECAT_PDI_CHIP_DIRECT 0u
#define ECAT_PDI_CHIP_LAN9252 1u
#define ECAT_PDI_CHIP_ET1100_SPI 2u

#endif /* ECAT_PDI_PROTOCOL_H */
