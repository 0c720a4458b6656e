// A line of FakeEsc slaves closed to a ring between two master ports, for
// tests of cable redundancy (master/redundant_transport.hpp) independent of
// the emulated segment. As ESCs forward (ESC datasheet Section I): a frame
// sent out of the primary port enters slave 0 on port 0 and is processed by
// every slave in position order; with the ring intact it leaves the last
// slave's port 1 into the secondary port. A frame sent out of the secondary
// port enters the last slave on port 1 and passes every slave unprocessed
// (port 1 -> port 2 -> port 0) to the primary port. A cut after slave k
// closes the loop at both ends of the cable: the primary frame is processed
// by slaves 0..k and comes back on the primary port; a secondary frame runs
// down to slave k+1, turns at its closed port 0, is processed by slaves
// k+1..N-1 in position order and comes back on the secondary port. A
// processed frame gets bit 1 of its first source MAC byte set.
#pragma once

#include <deque>
#include <optional>
#include <vector>

#include "fake_esc.hpp"
#include "test_sii_image.hpp"
#include "transport/transport.hpp"
#include "tests/support/frame_queue.hpp"

namespace ecat::master::test {

class FakeRing {
 public:
  // One master port: frames sent here enter the ring at its end.
  class Port final : public transport::Transport {
   public:
    Port(FakeRing& ring, bool primary) : ring_(ring), primary_(primary) {}
    Expected<void, transport::TransportError> send(ConstBytes frame) override {
      ++sent;
      ring_.carry(std::vector<std::uint8_t>(frame.begin(), frame.end()), primary_);
      return {};
    }
    Expected<std::size_t, transport::TransportError> receive(Bytes buffer, Nanoseconds) override {
      ++polls;
      auto got = queue.pop(buffer);
      if (!primary_) ring_.release_late_primary_returns();
      return got;
    }
    ecat::test::FrameQueue queue;
    std::size_t sent = 0;
    std::size_t polls = 0;  // receive() calls

   private:
    FakeRing& ring_;
    bool primary_;
  };

  explicit FakeRing(std::size_t slaves) : escs(slaves), primary(*this, true), secondary(*this, false) {
    for (auto& e : escs) e.sii = test_sii_image();
  }

  // Cut the cable after slave `k` (k = -1: between the primary port and slave
  // 0; k = N-1: between the last slave and the secondary port); empty = intact.
  void cut_after(std::optional<long> k) { cut_ = k; }

  // A host held up: the next `n` frames the primary side returns are lost.
  void lose_primary_returns(std::size_t n) { lose_primary_returns_ = n; }
  // The primary side's returns come in only while the master waits on the
  // secondary port (after its next receive there): a host slower on one side.
  void late_primary_returns(bool late) { late_primary_returns_ = late; }

  std::vector<FakeEsc> escs;
  Port primary;
  Port secondary;
  std::size_t processed_by_secondary_side = 0;  // processings by slaves reached from the secondary port

 private:
  void process(std::vector<std::uint8_t>& f, std::size_t from, std::size_t to) {
    for (std::size_t i = from; i < to; ++i) {
      escs[i].process(Bytes(f.data(), f.size()));
      f[kMacSize] |= kSourceMacProcessedBit;
    }
  }
  void carry(std::vector<std::uint8_t> f, bool from_primary) {
    const long n = static_cast<long>(escs.size());
    if (!cut_) {
      if (from_primary) process(f, 0, escs.size());
      (from_primary ? secondary : primary).queue.push_back(std::move(f));
      return;
    }
    const long k = *cut_;
    if (from_primary) {
      if (k < 0) return;  // no link on the primary port: lost
      process(f, 0, static_cast<std::size_t>(k + 1));
      if (lose_primary_returns_ > 0) {
        --lose_primary_returns_;
        return;
      }
      if (late_primary_returns_) {
        held_.push_back(std::move(f));
      } else {
        primary.queue.push_back(std::move(f));
      }
    } else {
      if (k >= n - 1) return;  // no link on the secondary port: lost
      processed_by_secondary_side += static_cast<std::size_t>(n - 1 - k);
      process(f, static_cast<std::size_t>(k + 1), escs.size());
      secondary.queue.push_back(std::move(f));
    }
  }

  void release_late_primary_returns() {
    while (!held_.empty()) {
      primary.queue.push_back(std::move(held_.front()));
      held_.pop_front();
    }
  }

  std::optional<long> cut_;
  std::size_t lose_primary_returns_ = 0;
  bool late_primary_returns_ = false;
  std::deque<std::vector<std::uint8_t>> held_;
};

}  // namespace ecat::master::test
