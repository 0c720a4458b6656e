#include "ds402/ip_buffer.hpp"

#include <algorithm>

namespace ecat::ds402 {

void IpBuffer::clear() noexcept {
  read_ = write_ = count_ = 0;
}

void IpBuffer::configure(const Config& c) noexcept {
  if (configured_ && c == config_) return;
  const std::uint32_t size = std::clamp<std::uint32_t>(c.actual_size, 1, kMaxSize);
  const bool ring = c.organisation == kRing;
  if (!configured_ || size != size_ || ring != ring_) {
    size_ = size;
    ring_ = ring;
    clear();
  }
  if (c.access != config_.access || !configured_) {
    if (c.access == kClear) clear();
    enabled_ = c.access == kEnableAccess;
  }
  if (ring_ && (!configured_ || c.position != config_.position)) {
    write_ = c.position % size_;
    if (count_ == 0) read_ = write_;  // an empty ring is read from where it is written
  }
  config_ = c;
  configured_ = true;
}

bool IpBuffer::push(std::int32_t record) noexcept {
  if (!enabled_) return false;
  if (!ring_ && count_ == size_) {
    ++lost_;
    return false;
  }
  if (ring_ && count_ == size_) {
    ++lost_;  // the oldest record not yet taken is overwritten
    read_ = (read_ + 1) % size_;
    --count_;
  }
  records_[write_] = record;
  write_ = (write_ + 1) % size_;
  ++count_;
  if (ring_) config_.position = static_cast<std::uint16_t>(write_);  // the drive's own advance is no change
  return true;
}

std::optional<std::int32_t> IpBuffer::pop() noexcept {
  if (!enabled_ || count_ == 0) return std::nullopt;
  const std::int32_t r = records_[read_];
  read_ = (read_ + 1) % size_;
  --count_;
  return r;
}

}  // namespace ecat::ds402
