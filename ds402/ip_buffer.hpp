// The interpolation data buffer of interpolated position mode (CiA 402-2,
// 60C4h "interpolation data configuration"): records written to 60C1h:01
// queue here and the drive takes one per interpolation period.
//   60C4h:01 maximum buffer size (kMaxSize records, ro)
//   60C4h:02 actual buffer size (1..kMaxSize; a change clears the buffer)
//   60C4h:03 buffer organisation: 0 FIFO, 1 ring buffer (a change clears it)
//   60C4h:04 buffer position: ring buffer: where the next record is written
//            (0-based; the drive advances it after each record)
//   60C4h:05 size of data record (bytes; 4: one INTEGER32, checked by the
//            dictionary's range)
//   60C4h:06 buffer clear: 0 clears the buffer and disables access to it,
//            1 enables access
// FIFO: a record arriving while the buffer is full is dropped (counted, and
// the statusword warning bit is set in that cycle). Ring buffer: a record
// always goes to the buffer position and overwrites what was there; a record
// not yet taken that is overwritten is lost the same way. docs/ds402.md
// "Interpolation data buffer (60C4h)" has the choices made.
#pragma once

#include <array>
#include <cstdint>
#include <optional>

namespace ecat::ds402 {

class IpBuffer {
 public:
  static constexpr std::uint32_t kMaxSize = 16;     // 60C4h:01
  static constexpr std::uint8_t kRecordBytes = 4;   // 60C4h:05: 60C1h:01, INTEGER32
  static constexpr std::uint8_t kFifo = 0;          // 60C4h:03
  static constexpr std::uint8_t kRing = 1;
  static constexpr std::uint8_t kClear = 0;         // 60C4h:06
  static constexpr std::uint8_t kEnableAccess = 1;

  struct Config {
    std::uint32_t actual_size = kMaxSize;  // 60C4h:02
    std::uint8_t organisation = kFifo;     // 60C4h:03
    std::uint16_t position = 0;            // 60C4h:04
    std::uint8_t access = kClear;          // 60C4h:06
    bool operator==(const Config&) const = default;
  };

  // Applies the objects when they changed since the last call.
  void configure(const Config& c) noexcept;
  // A record arrived (a write of 60C1h:01). False when it was not taken:
  // access disabled, or the FIFO is full (then it is counted as lost).
  bool push(std::int32_t record) noexcept;
  // The next record for the interpolator, if any.
  std::optional<std::int32_t> pop() noexcept;

  bool enabled() const noexcept { return enabled_; }
  std::uint32_t count() const noexcept { return count_; }
  std::uint32_t size() const noexcept { return size_; }
  std::uint32_t lost() const noexcept { return lost_; }
  bool ring() const noexcept { return ring_; }
  // The ring buffer's next write position (60C4h:04 as the drive reports it).
  std::uint16_t position() const noexcept { return static_cast<std::uint16_t>(write_); }

 private:
  void clear() noexcept;

  // What a drive's cycle reads of a buffer that is off (Drive::step,
  // Drive::fill), first: it then shares a line with the drive's cycle state
  // (issue 30 item 1).
  bool enabled_ = false;
  bool ring_ = false;
  std::array<std::int32_t, kMaxSize> records_{};
  Config config_{};
  bool configured_ = false;
  std::uint32_t size_ = kMaxSize;
  std::uint32_t read_ = 0, write_ = 0, count_ = 0;
  std::uint32_t lost_ = 0;
};

}  // namespace ecat::ds402
