// The cyclic exchange does not allocate (STYLE lesson 11): counted with a
// replaced global operator new over a transport that does not allocate either.
#include <gtest/gtest.h>

#include <array>
#include <atomic>
#include <cstdlib>
#include <new>

#include "fake_esc.hpp"
#include "master/master.hpp"
#include "test_sii_image.hpp"
#include "tests/support/alloc_counter.hpp"

namespace ecat::master::test {
namespace {

// One frame in flight, fixed buffer, processed by the FakeEsc in place.
class FixedLoopback final : public transport::Transport {
 public:
  explicit FixedLoopback(FakeEsc& esc) : esc_(esc) {}
  Expected<void, transport::TransportError> send(ConstBytes frame) override {
    std::copy(frame.begin(), frame.end(), buf_.begin());
    size_ = frame.size();
    esc_.process(Bytes(buf_.data(), size_));
    return {};
  }
  Expected<std::size_t, transport::TransportError> receive(Bytes out, Nanoseconds) override {
    if (size_ == 0) return fail(transport::TransportError::Timeout);
    std::copy(buf_.begin(), buf_.begin() + static_cast<std::ptrdiff_t>(size_), out.begin());
    const std::size_t n = size_;
    size_ = 0;
    return n;
  }

 private:
  FakeEsc& esc_;
  std::array<std::uint8_t, transport::kMaxFrameSize> buf_{};
  std::size_t size_ = 0;
};

TEST(CyclicExchange, DoesNotAllocate) {
  FakeEsc esc;
  esc.sii = test_sii_image();
  FixedLoopback loop(esc);
  ManualClock clock;
  Master master(loop, clock);
  ASSERT_EQ(master.scan().value_or(0), 1u);
  master.slave(0).pd.output_bytes = 8;
  master.slave(0).pd.input_bytes = 8;
  ASSERT_TRUE(master.configure_process_data().has_value());
  ASSERT_TRUE(master.exchange_process_data().has_value());  // warm-up
  {
    const ecat::test::AllocCounter counter;
    for (int i = 0; i < 1000; ++i) {
      master.outputs(0)[0] = static_cast<std::uint8_t>(i);
      auto r = master.exchange_process_data();
      if (!r || !r->ok()) break;
    }
    EXPECT_EQ(counter.count(), 0u);
  }
  EXPECT_EQ(master.cyclic_stats().cycles, 1001u);
  EXPECT_EQ(master.cyclic_stats().wkc_errors, 0u);
}

// An image of several datagrams and frames (issue 16 item 5): still no allocation per cycle.
TEST(CyclicExchange, SeveralFramesDoNotAllocate) {
  FakeEsc esc;
  esc.sii = test_sii_image();
  FixedLoopback loop(esc);
  ManualClock clock;
  MasterConfig cfg;
  cfg.max_process_datagram = 700;
  Master master(loop, clock, cfg);
  ASSERT_EQ(master.scan().value_or(0), 1u);
  master.slave(0).pd.output_bytes = 2000;
  master.slave(0).pd.input_bytes = 1000;
  ASSERT_TRUE(master.configure_process_data().has_value());
  ASSERT_GE(master.process_data_frames(), 3u);
  ASSERT_GE(master.process_data_plan().size(), 5u);
  ASSERT_TRUE(master.exchange_process_data().has_value());  // warm-up
  std::size_t frames = 0;
  {
    const ecat::test::AllocCounter counter;
    for (int i = 0; i < 100; ++i) {
      master.outputs(0)[1999] = static_cast<std::uint8_t>(i);
      auto r = master.exchange_process_data();
      if (!r) break;
      frames += r->frames;
    }
    EXPECT_EQ(counter.count(), 0u);
  }
  EXPECT_EQ(frames, 100 * master.process_data_frames());
  EXPECT_EQ(master.cyclic_stats().cycles, 101u);
}

}  // namespace
}  // namespace ecat::master::test
