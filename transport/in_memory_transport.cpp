#include "transport/in_memory_transport.hpp"

#include <algorithm>

namespace ecat::transport {

Expected<void, TransportError> InMemoryTransport::send(ConstBytes frame) {
  if (frame.size() > kMaxFrameSize) return fail(TransportError::FrameTooLarge);
  ++sent_;
  if (record_) sent_frames_.emplace_back(frame.begin(), frame.end());
  std::vector<std::uint8_t> copy(frame.begin(), frame.end());
  if (processor_) processor_(Bytes(copy));
  if (drop_ > 0) {
    --drop_;
    return {};
  }
  queue_.push_back(std::move(copy));
  return {};
}

Expected<std::size_t, TransportError> InMemoryTransport::receive(Bytes buffer, Nanoseconds timeout) {
  (void)timeout;  // nothing arrives later than now
  if (queue_.empty()) return fail(TransportError::Timeout);
  std::vector<std::uint8_t> frame = std::move(queue_.front());
  queue_.pop_front();
  if (frame.size() > buffer.size()) return fail(TransportError::BufferTooSmall);
  std::copy(frame.begin(), frame.end(), buffer.begin());
  return frame.size();
}

}  // namespace ecat::transport
