// Frames waiting on a test's fake master port: what the emulated segment
// returned, handed out in order by Transport::receive (a timeout when none).
#pragma once

#include <algorithm>
#include <cstdint>
#include <deque>
#include <vector>

#include "common/expected.hpp"
#include "transport/transport.hpp"

namespace ecat::test {

struct FrameQueue {
  std::deque<std::vector<std::uint8_t>> frames;

  bool empty() const noexcept { return frames.empty(); }
  void push_back(std::vector<std::uint8_t> f) { frames.push_back(std::move(f)); }
  void clear() noexcept { frames.clear(); }
  std::size_t size() const noexcept { return frames.size(); }

  Expected<std::size_t, transport::TransportError> pop(Bytes buffer) {
    if (frames.empty()) return fail(transport::TransportError::Timeout);
    auto f = std::move(frames.front());
    frames.pop_front();
    if (f.size() > buffer.size()) return fail(transport::TransportError::BufferTooSmall);
    std::copy(f.begin(), f.end(), buffer.begin());
    return f.size();
  }
};

}  // namespace ecat::test
