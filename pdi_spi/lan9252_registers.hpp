// Microchip LAN9252 host-side (SPI) registers and instructions, as far as
// the PDI backend uses them. Source: LAN9252 data sheet DS00001909 (SPI/SQI
// slave chapter, "EtherCAT CSR and Process Data RAM access" and system
// registers); docs/real-esc.md lists each value with where it comes from
// and which ones were only confirmed against vendor/SOES driver code.
#pragma once

#include <cstdint>

namespace ecat::pdi_spi::lan9252 {

// SPI instructions (DS00001909, SPI instruction table): one byte, then a
// 16-bit address, most significant byte first; data least significant byte
// first. FAST READ inserts one dummy byte after the address in SPI mode.
inline constexpr std::uint8_t kInstrRead = 0x03;
inline constexpr std::uint8_t kInstrFastRead = 0x0B;
inline constexpr std::uint8_t kInstrWrite = 0x02;
inline constexpr std::size_t kInstrHeader = 3;         // instruction + 2 address bytes
inline constexpr std::size_t kFastReadDummyBytes = 1;  // SPI (single) mode

// System control and status registers (byte addresses).
inline constexpr std::uint16_t kPramReadFifo = 0x0000;   // ECAT_PRAM_RD_DATA, 0x000-0x01F
inline constexpr std::uint16_t kPramWriteFifo = 0x0020;  // ECAT_PRAM_WR_DATA, 0x020-0x03F
inline constexpr std::uint16_t kFifoPortSize = 0x0020;
inline constexpr std::uint16_t kIdRev = 0x0050;
inline constexpr std::uint16_t kIrqCfg = 0x0054;
inline constexpr std::uint16_t kIntSts = 0x0058;
inline constexpr std::uint16_t kIntEn = 0x005C;
inline constexpr std::uint16_t kByteTest = 0x0064;
inline constexpr std::uint16_t kHwCfg = 0x0074;
inline constexpr std::uint16_t kResetCtl = 0x01F8;
inline constexpr std::uint16_t kCsrData = 0x0300;      // ECAT_CSR_DATA
inline constexpr std::uint16_t kCsrCmd = 0x0304;       // ECAT_CSR_CMD
inline constexpr std::uint16_t kPramRdAddrLen = 0x0308;
inline constexpr std::uint16_t kPramRdCmd = 0x030C;
inline constexpr std::uint16_t kPramWrAddrLen = 0x0310;
inline constexpr std::uint16_t kPramWrCmd = 0x0314;

inline constexpr std::uint32_t kByteTestValue = 0x87654321;  // BYTE_TEST: fixed pattern
inline constexpr std::uint32_t kHwCfgReady = 1u << 27;       // HW_CFG: device ready

// IRQ_CFG: IRQ_EN (bit 8), IRQ_POL (bit 4: 1 = active high), IRQ_BUF_TYPE
// (bit 0: 1 = push-pull). INT_STS/INT_EN bit 0: ECAT_INT, the EtherCAT
// interrupt (AL event request & AL event mask of the ESC core).
inline constexpr std::uint32_t kIrqCfgEnable = 1u << 8;
inline constexpr std::uint32_t kIrqCfgPolarityHigh = 1u << 4;
inline constexpr std::uint32_t kIrqCfgPushPull = 1u << 0;
inline constexpr std::uint32_t kIntEcat = 1u << 0;

// ECAT_CSR_CMD: CSR_BUSY (31, write 1 to start), R_nW (30, 1 = read),
// CSR_SIZE (18:16, 1/2/4 bytes), CSR_ADDR (15:0, ESC core address).
inline constexpr std::uint32_t kCsrBusy = 1u << 31;
inline constexpr std::uint32_t kCsrRead = 1u << 30;
inline constexpr unsigned kCsrSizeShift = 16;
inline constexpr std::uint32_t kCsrSizeMask = 0x7u << kCsrSizeShift;
inline constexpr std::uint32_t kCsrAddrMask = 0xFFFF;

// ECAT_PRAM_RD/WR_ADDR_LEN: length in bytes (31:16), ESC address (15:0).
inline constexpr unsigned kPramLenShift = 16;
inline constexpr std::uint32_t kPramAddrMask = 0xFFFF;
// ECAT_PRAM_RD/WR_CMD: busy (31, write 1 to start), abort (30, write 1),
// available count (12:8, DWORDs in the read FIFO / free in the write FIFO),
// available (0).
inline constexpr std::uint32_t kPramBusy = 1u << 31;
inline constexpr std::uint32_t kPramAbort = 1u << 30;
inline constexpr unsigned kPramCountShift = 8;
inline constexpr std::uint32_t kPramCountMask = 0x1Fu << kPramCountShift;
inline constexpr std::uint32_t kPramAvailable = 1u << 0;
inline constexpr unsigned kPramFifoDwords = 16;  // 64-byte FIFO each way

// Everything below 0x1000 on the ESC side is a register (CSR access);
// process RAM from 0x1000 goes through the FIFOs.
inline constexpr std::uint16_t kProcessRamStart = 0x1000;
inline constexpr std::size_t kDword = 4;

}  // namespace ecat::pdi_spi::lan9252
