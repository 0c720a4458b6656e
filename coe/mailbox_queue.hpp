// Fixed-capacity FIFO of complete mailbox frames waiting for the read
// mailbox (SM1). Slots are allocated once; push/pop copy bytes, never
// allocate. push_front is for the repeat protocol, which must put a reply
// that was displaced back at the head so nothing is lost or reordered.
#pragma once

#include <cstdint>
#include <cstring>
#include <vector>

#include "common/le.hpp"

namespace ecat::coe {

class MailboxQueue {
 public:
  MailboxQueue(std::size_t capacity, std::size_t frame_bytes)
      : frame_bytes_(frame_bytes), storage_(capacity * frame_bytes), lengths_(capacity, 0) {}

  std::size_t capacity() const noexcept { return lengths_.size(); }
  std::size_t size() const noexcept { return size_; }
  bool empty() const noexcept { return size_ == 0; }
  bool full() const noexcept { return size_ == capacity(); }
  std::size_t frame_bytes() const noexcept { return frame_bytes_; }

  bool push_back(ConstBytes frame) noexcept {
    if (full() || frame.size() > frame_bytes_) return false;
    store((head_ + size_) % capacity(), frame);
    ++size_;
    return true;
  }
  bool push_front(ConstBytes frame) noexcept {
    if (full() || frame.size() > frame_bytes_) return false;
    head_ = (head_ + capacity() - 1) % capacity();
    store(head_, frame);
    ++size_;
    return true;
  }
  ConstBytes front() const noexcept {
    return {storage_.data() + head_ * frame_bytes_, lengths_[head_]};
  }
  void pop_front() noexcept {
    if (empty()) return;
    head_ = (head_ + 1) % capacity();
    --size_;
  }
  void clear() noexcept { head_ = size_ = 0; }

 private:
  void store(std::size_t slot, ConstBytes frame) noexcept {
    if (!frame.empty()) std::memcpy(storage_.data() + slot * frame_bytes_, frame.data(), frame.size());
    lengths_[slot] = frame.size();
  }

  // size_ first: MailboxServer::has_output, asked at every firmware poll,
  // reads only it and finds it on the server's first cache line.
  std::size_t size_ = 0;
  std::size_t head_ = 0;
  std::size_t frame_bytes_;
  std::vector<std::uint8_t> storage_;
  std::vector<std::size_t> lengths_;
};

}  // namespace ecat::coe
