// The application side of an ESC: the Process Data Interface. A µC on a real
// ESC sees exactly this (SOES's ESC_read/ESC_write): reads and writes of the
// register file and process RAM, with the sync-manager buffer rules applied
// from the PDI side (ESC datasheet Section I §8). coe/ and ds402/ reach the
// ESC only through it, so the emulated ESC could be swapped for a real one.
#pragma once

#include <cstdint>
#include <span>

#include "common/le.hpp"

namespace ecat::esc {

class Pdi {
 public:
  virtual ~Pdi() = default;

  // Reads `out.size()` bytes starting at `address`. Reading the last byte of
  // a full write-direction SM buffer releases it (mailbox empty / 3-buffer
  // swap), as on silicon. Addresses past the end read as 0.
  virtual void read(std::uint16_t address, std::span<std::uint8_t> out) noexcept = 0;
  // Writes `in` at `address`. Writing the last byte of a read-direction SM
  // buffer makes it available to the master. Read-only bits are kept.
  virtual void write(std::uint16_t address, std::span<const std::uint8_t> in) noexcept = 0;

  // Whole-buffer accesses that may skip a copy (issue 8: the process-data
  // cycle). read_buffer is read(address, scratch) - every SM rule, event and
  // watchdog effect the same - but may return the bytes where they already
  // are instead of copying them into `scratch`; the returned span (scratch
  // or that view, scratch.size() bytes) stays valid until the next access
  // to this Pdi or the next frame through the ESC.
  virtual std::span<const std::uint8_t> read_buffer(std::uint16_t address, std::span<std::uint8_t> scratch) noexcept {
    read(address, scratch);
    return scratch;
  }
  // write(address, bytes) in two steps: write_buffer_begin returns where to
  // put the bytes (`scratch`, or the place they will be written to, with
  // unspecified contents); write_buffer_commit(address, that span) then
  // carries out the write - every SM rule, event and watchdog effect as
  // write() at the time of the commit. No other access to this Pdi and no
  // frame may come between the two.
  virtual std::span<std::uint8_t> write_buffer_begin(std::uint16_t /*address*/, std::span<std::uint8_t> scratch) noexcept {
    return scratch;
  }
  virtual void write_buffer_commit(std::uint16_t address, std::span<const std::uint8_t> bytes) noexcept {
    write(address, bytes);
  }

  std::uint8_t read_u8(std::uint16_t address) noexcept {
    std::uint8_t b[1]{};
    read(address, b);
    return b[0];
  }
  std::uint16_t read_u16(std::uint16_t address) noexcept {
    std::uint8_t b[2]{};
    read(address, b);
    return load_le<std::uint16_t>(b);
  }
  std::uint32_t read_u32(std::uint16_t address) noexcept {
    std::uint8_t b[4]{};
    read(address, b);
    return load_le<std::uint32_t>(b);
  }
  void write_u8(std::uint16_t address, std::uint8_t v) noexcept {
    std::uint8_t b[1]{v};
    write(address, b);
  }
  void write_u16(std::uint16_t address, std::uint16_t v) noexcept {
    std::uint8_t b[2];
    store_le(b, v);
    write(address, b);
  }
  void write_u32(std::uint16_t address, std::uint32_t v) noexcept {
    std::uint8_t b[4];
    store_le(b, v);
    write(address, b);
  }
};

}  // namespace ecat::esc
