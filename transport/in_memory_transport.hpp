// In-process transport (STYLE lessons 8 and 12): send() copies the frame,
// hands it to a frame processor that changes it in place as a segment of
// slaves would (e.g. esc::Segment::process_frame plus the slaves' poll), and
// queues the result for receive(). Nothing blocks: receive() on an empty queue
// times out at once. Set-up and test code, not the stack's cyclic path, so the
// std::function and the queue's allocations are fine here.
#pragma once

#include <cstdint>
#include <deque>
#include <functional>
#include <vector>

#include "transport/transport.hpp"

namespace ecat::transport {

class InMemoryTransport final : public Transport {
 public:
  // Processes a frame in place. Return nothing: a processor that "loses" the
  // frame can be modelled with drop_next().
  using FrameProcessor = std::function<void(Bytes)>;

  explicit InMemoryTransport(FrameProcessor processor = {}) : processor_(std::move(processor)) {}

  void set_processor(FrameProcessor processor) { processor_ = std::move(processor); }

  Expected<void, TransportError> send(ConstBytes frame) override;
  Expected<std::size_t, TransportError> receive(Bytes buffer, Nanoseconds timeout) override;

  // The next `count` frames are processed but never come back (lost reply).
  void drop_next(std::size_t count) noexcept { drop_ = count; }
  // A frame for receive() that no send() produced (a late or repeated
  // reply); queued now, so from inside the processor it comes before the
  // reply to the frame being processed.
  void inject(ConstBytes frame) { queue_.emplace_back(frame.begin(), frame.end()); }
  std::size_t frames_sent() const noexcept { return sent_; }
  std::size_t pending() const noexcept { return queue_.size(); }
  // Every frame as sent (before processing), when recording is on; for tests
  // that assert the exact bytes a master put on the wire.
  void record_sent(bool on) noexcept { record_ = on; }
  const std::vector<std::vector<std::uint8_t>>& sent_frames() const noexcept { return sent_frames_; }
  void clear_sent_frames() noexcept { sent_frames_.clear(); }

 private:
  FrameProcessor processor_;
  std::deque<std::vector<std::uint8_t>> queue_;
  std::vector<std::vector<std::uint8_t>> sent_frames_;
  std::size_t drop_ = 0;
  std::size_t sent_ = 0;
  bool record_ = false;
};

}  // namespace ecat::transport
