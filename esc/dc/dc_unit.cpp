// Register storage only; see dc_unit.hpp.
#include "esc/dc/dc_unit.hpp"

#include <algorithm>

#include "common/le.hpp"

namespace ecat::esc {

namespace {
constexpr std::uint16_t kSyncPulseLength = 0x0082;  // 0x0982 - 0x0900
}

void DcUnit::read(std::uint16_t offset, std::span<std::uint8_t> out, Nanoseconds local_time,
                  Side side) noexcept {
  (void)local_time;
  (void)side;
  if (offset >= kSize) return;
  std::size_t n = std::min<std::size_t>(out.size(), kSize - offset);
  std::copy_n(regs_.begin() + offset, n, out.begin());
}

void DcUnit::write(std::uint16_t offset, std::span<const std::uint8_t> in, Nanoseconds local_time,
                   Side side) noexcept {
  (void)local_time;
  (void)side;
  if (offset >= kSize) return;
  std::size_t n = std::min<std::size_t>(in.size(), kSize - offset);
  std::copy_n(in.begin(), n, regs_.begin() + offset);
}

void DcUnit::on_frame_arrival(int port, Nanoseconds t) noexcept {
  (void)port;
  (void)t;
}

std::optional<Nanoseconds> DcUnit::poll(Nanoseconds now) noexcept {
  (void)now;
  return std::nullopt;
}

void DcUnit::reset(std::uint16_t sync_pulse_length) noexcept {
  regs_.fill(0);
  al_events_ = 0;
  ecat_events_ = 0;
  store_le(regs_.data() + kSyncPulseLength, sync_pulse_length);
}

}  // namespace ecat::esc
