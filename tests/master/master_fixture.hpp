// Master + FakeEsc over the in-memory transport, recording every frame sent.
#pragma once

#include <gtest/gtest.h>

#include <vector>

#include "common/frame_parser.hpp"
#include "fake_esc.hpp"
#include "master/master.hpp"
#include "test_sii_image.hpp"
#include "transport/in_memory_transport.hpp"

namespace ecat::master::test {

struct SentDatagram {
  Command command;
  std::uint16_t adp;
  std::uint16_t ado;
  std::vector<std::uint8_t> data;
};

class MasterFixture : public ::testing::Test {
 protected:
  MasterFixture() : transport_([this](Bytes f) {
                      fake.process(f);
                      clock.advance(std::chrono::microseconds(10));
                    }),
                    master(transport_, clock) {
    fake.sii = test_sii_image();
    transport_.record_sent(true);
  }

  // Every datagram of every frame sent so far, in order.
  std::vector<SentDatagram> sent() const {
    std::vector<SentDatagram> out;
    for (auto f : transport_.sent_frames()) {
      auto v = parse_frame(f);
      if (!v) continue;
      v->for_each([&](DatagramView d) {
        out.push_back({d.command(), d.adp(), d.ado(), std::vector<std::uint8_t>(d.data().begin(), d.data().end())});
      });
    }
    return out;
  }
  std::vector<SentDatagram> sent(Command c, std::uint16_t ado) const {
    std::vector<SentDatagram> out;
    for (auto& d : sent()) {
      if (d.command == c && d.ado == ado) out.push_back(d);
    }
    return out;
  }
  void clear_sent() { transport_.clear_sent_frames(); }
  const std::vector<std::vector<std::uint8_t>>& frames() const { return transport_.sent_frames(); }

  void scan_and_mailbox() {
    ASSERT_EQ(master.scan().value_or(0), 1u);
    ASSERT_TRUE(master.configure_mailbox(0).has_value());
  }

  ManualClock clock;
  FakeEsc fake;
  transport::InMemoryTransport transport_;
  Master master;
};

}  // namespace ecat::master::test
