// ecat-master's way to Op (app::Session::bring_up): every slave is asked at
// once and the cycle runs until all are in Op, so that each slave's SM
// watchdog (100 ms by the ESC's defaults) is fed while the others take their
// time. Against in-process drives on simulated time, with the master held up
// after each frame that asks for or reads an AL state - a busy host - the
// way the later of 250 drives refused Op with 001Bh when the master asked
// them one at a time without cycling (docs/e2e.md "Op with the cycle
// running").
#include <gtest/gtest.h>

#include <csignal>
#include <cstdint>
#include <string>

#include "apps/ecat-master/session.hpp"
#include "common/frame_parser.hpp"
#include "common/le.hpp"
#include "esc/al_status_code.hpp"
#include "esc/register_bits.hpp"
#include "esc/registers.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

using std::chrono::milliseconds;

constexpr std::size_t kDrives = 8;
// The SM watchdog's default time: divider 0x0400 = 2498 (100 us), 0x0420 = 1000.
constexpr Nanoseconds kSmWatchdog = milliseconds(100);
// How long the master is held up after each AL control or AL status frame:
// four of them span more than the watchdog.
constexpr Nanoseconds kHeldUp = milliseconds(30);
constexpr std::uint16_t kAlStatusCodeSmWatchdog = 0x001B;
constexpr auto kOp = static_cast<std::uint8_t>(esc::AlState::Op);
constexpr auto kSafeOp = static_cast<std::uint8_t>(esc::AlState::SafeOp);
constexpr std::uint16_t kSafeOpWithErrInd = kSafeOp | esc::bits::kAlErrorInd;

struct SlowMaster : InProcess {
  Nanoseconds held_up{0};          // after each frame with an AL control or status datagram
  Nanoseconds stall_after_op{0};  // once, after the first request for Op reached the slaves
  // Until then a BRD of AL status comes back showing SafeOp (0x04) in place
  // of Op: slaves that take this long to report Op.
  Nanoseconds op_shown_from{0};
  // The BWR of Op comes back with its WKC one short: as if a slave had not
  // taken it (its µC had not read the previous request yet).
  bool op_broadcast_short = false;
  std::uint32_t op_fpwr_frames = 0;  // frames that write Op to one slave's AL control
  std::uint32_t op_request_frames = 0;  // frames that write Op to AL control
  bool op_broadcast = false;            // ... as a BWR

  SlowMaster() {
    add_default(kDrives);
    wire.set_processor([this](Bytes frame) {
      bool state = false;  // an AL control or status datagram
      bool op = false;     // a write of Op to AL control
      auto view = parse_frame(frame);
      if (view) {
        view->for_each([&](DatagramView d) {
          state = state || d.ado() == esc::reg::kAlControl || d.ado() == esc::reg::kAlStatus;
          if (d.ado() != esc::reg::kAlControl || d.data().empty() || d.data()[0] != kOp) return;
          op = true;
          op_broadcast = op_broadcast || d.command() == Command::Bwr;
          if (d.command() == Command::Fpwr) ++op_fpwr_frames;
        });
      }
      clock.advance(kWireTime);
      (void)chain.process_frame(frame, clock.now());
      // The reply as the test wants it: the BWR of Op one short, a BRD of AL status without Op yet.
      const bool hide_op = clock.now() < op_shown_from;
      if (view && ((op && op_broadcast_short) || hide_op)) {
        view->for_each([&](DatagramView d) {
          if (d.command() == Command::Bwr && d.ado() == esc::reg::kAlControl && op && op_broadcast_short) {
            d.set_wkc(static_cast<std::uint16_t>(d.wkc() - 1));
          }
          if (d.command() == Command::Brd && d.ado() == esc::reg::kAlStatus && hide_op && !d.data().empty() &&
              d.data()[0] == kOp) {
            d.data()[0] = kSafeOp;
          }
        });
      }
      if (state) advance(held_up);
      if (op) {
        ++op_request_frames;
        advance(std::exchange(stall_after_op, Nanoseconds{0}));
      }
    });
  }

  app::Session session(Nanoseconds period = milliseconds(1)) {
    app::SessionOptions o;
    o.expect_slaves = kDrives;
    o.verbose = false;
    o.period = period;
    return app::Session(
        master, clock,
        [this](Nanoseconds at) {
          if (at > clock.now()) advance(at - clock.now());
        },
        o);
  }
  std::uint16_t read_u16(std::size_t i, std::uint16_t reg) {
    std::uint8_t b[2]{};
    chain[i].esc().read(reg, b);
    return load_le<std::uint16_t>(b);
  }
};

TEST(SessionOp, EveryDriveReachesOpWhenEachStateFrameHoldsTheMasterUp) {
  SlowMaster m;
  m.held_up = kHeldUp;
  // Asked one by one, the eight drives' requests alone would take longer
  // than the watchdog.
  ASSERT_GT(kHeldUp * static_cast<std::int64_t>(kDrives), kSmWatchdog);
  app::Session s = m.session();
  const auto ok = s.bring_up();
  ASSERT_TRUE(ok) << ok.error();
  for (std::size_t i = 0; i < kDrives; ++i) {
    EXPECT_EQ(m.read_u16(i, esc::reg::kAlStatus), kOp) << "slave " << i + 1;
    EXPECT_EQ(m.read_u16(i, esc::reg::kAlStatusCode), 0x0000) << "slave " << i + 1;
  }
  EXPECT_EQ(m.op_request_frames, 1u);
  EXPECT_TRUE(m.op_broadcast);
}

// A slave that does not stay in Op is named with its AL status code: the
// master held up longer than the watchdog right after asking for Op, so
// every drive's watchdog expires in Op and it goes back to SafeOp with
// ErrInd and 001Bh (ETG.1000.6 Table 11); the BRD of the next cycle shows
// ErrInd, and the slaves are read one by one.
TEST(SessionOp, ADriveThatLeavesOpIsNamedWithItsCode) {
  SlowMaster m;
  m.stall_after_op = kSmWatchdog + milliseconds(10);
  app::Session s = m.session();
  const auto ok = s.bring_up();
  ASSERT_FALSE(ok);
  EXPECT_EQ(ok.error(), "slave 1: Op refused, AL status code 0x001B");
  for (std::size_t i = 0; i < kDrives; ++i) {
    EXPECT_EQ(m.read_u16(i, esc::reg::kAlStatus), kSafeOpWithErrInd) << "slave " << i + 1;
    EXPECT_EQ(m.read_u16(i, esc::reg::kAlStatusCode), kAlStatusCodeSmWatchdog) << "slave " << i + 1;
  }
}

// At a short period the 3000 cycles Op is waited for at least are 0.3 s;
// slaves that report Op only after a second still get there: the wait is
// also at least the master's state timeout (5 s, what one slave's
// request_state waits).
TEST(SessionOp, OpIsWaitedForAsLongAsTheStateTimeoutAtAShortPeriod) {
  SlowMaster m;
  const Nanoseconds period = std::chrono::microseconds(100);
  app::Session s = m.session(period);
  // The start-up reaches the Op request within 10 ms of simulated time.
  m.op_shown_from = std::chrono::seconds(1);
  ASSERT_LT(period * 3000, m.op_shown_from);
  ASSERT_LT(m.op_shown_from, m.master.config().state_timeout);
  const auto ok = s.bring_up();
  ASSERT_TRUE(ok) << ok.error();
  EXPECT_GE(m.clock.now(), m.op_shown_from);
  EXPECT_EQ(m.op_request_frames, 1u);
}

// A BWR of Op that not every slave took (WKC short) is followed by an FPWR
// of Op to each slave, one a cycle, before the state is read.
TEST(SessionOp, ABroadcastNotTakenByEverySlaveIsFollowedByOneWriteEach) {
  SlowMaster m;
  m.op_broadcast_short = true;
  app::Session s = m.session();
  const auto ok = s.bring_up();
  ASSERT_TRUE(ok) << ok.error();
  EXPECT_EQ(m.op_fpwr_frames, kDrives);
  EXPECT_EQ(m.op_request_frames, 1 + kDrives);
  for (std::size_t i = 0; i < kDrives; ++i) EXPECT_EQ(m.read_u16(i, esc::reg::kAlStatus), kOp) << "slave " << i + 1;
}

// ecat-master's SIGINT/SIGTERM (apps/ecat-master/main.cpp): the handler
// sets the flag SessionOptions::stop points to, and the run ends before its
// next cycle with the report of the cycles run so far; the drives stay in Op.
// The flag is set here from the wait of the 100th cycle.
TEST(SessionRun, AStopRequestEndsTheRunBeforeItsNextCycle) {
  for (const bool stop : {true, false}) {
    SCOPED_TRACE(stop);
    SlowMaster m;
    volatile std::sig_atomic_t flag = 0;
    std::uint64_t waits = 0;
    bool counting = false;
    app::SessionOptions o;
    o.expect_slaves = kDrives;
    o.verbose = false;
    o.cycles = 1000;
    o.stop = &flag;
    app::Session s(
        m.master, m.clock,
        [&](Nanoseconds at) {
          if (at > m.clock.now()) m.advance(at - m.clock.now());
          if (counting && ++waits == 100 && stop) flag = 1;
        },
        o);
    const auto up = s.bring_up();
    ASSERT_TRUE(up) << up.error();
    counting = true;
    const auto r = s.run();
    ASSERT_TRUE(r) << r.error();
    EXPECT_EQ(r->stopped, stop);
    EXPECT_EQ(r->cycles, stop ? 100u : 1000u);
    EXPECT_EQ(r->lost_frames, 0u);
    EXPECT_EQ(r->wkc_errors, 0u);
    for (std::size_t i = 0; i < kDrives; ++i) EXPECT_EQ(m.read_u16(i, esc::reg::kAlStatus), kOp) << "slave " << i + 1;
  }
}

}  // namespace
}  // namespace ecat::test
