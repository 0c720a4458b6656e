// DC over real ESCs in a Segment, set up with datagrams the way masters do it
// (shared/spec/masters.md: ethercrab/TwinCAT delay measurement, offsets in one
// FPWR 0920:12 as IgH, ARMW burst, FRMW per cycle, SOEM's Sync0 start), then
// SYNC0 programmed on every slave with one start time fires at the same true
// instant on all of them.
#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "dc_fixture.hpp"
#include "esc_fixture.hpp"

namespace ecat::esc::test {
namespace {

using namespace dcreg;

constexpr std::size_t kSlaves = 3;
constexpr std::uint64_t kSystemStart = 0x0A00'0000'0000'0000ull;
constexpr std::int64_t kLimitNs = 100;

std::uint64_t u64_of(const Data& d, std::size_t at = 0) { return load_le<std::uint64_t>(d.data() + at); }
std::uint32_t u32_of(const Data& d, std::size_t at = 0) { return load_le<std::uint32_t>(d.data() + at); }
std::uint16_t station(std::size_t k) { return static_cast<std::uint16_t>(0x1001 + k); }
std::uint16_t dc_reg(std::uint16_t offset) { return static_cast<std::uint16_t>(reg::kDcBase + offset); }

struct Edges : DcObserver {
  std::vector<Nanoseconds> rising;
  void on_sync(unsigned signal, bool level, Nanoseconds t) noexcept override {
    if (signal == 0 && level) rising.push_back(t);
  }
};

class DcSegmentTest : public ::testing::Test {
 protected:
  DcSegmentTest() : line(kSlaves) {
    const std::array<double, kSlaves> ppm{+100.0, -100.0, +60.0};
    const std::array<std::uint64_t, kSlaves> start{1'000'000'000ull, 5'000'000'000'000ull, 123'456ull};
    for (std::size_t k = 0; k < kSlaves; ++k) line[k].dc().set_clock(ppm[k], start[k]);
    assign_stations(line);
  }
  Nanoseconds now() const { return line.clock.now(); }
  void advance(Nanoseconds d) {
    line.clock.advance(d);
    line.segment.poll(now());
  }
  std::int64_t difference(std::size_t k) {
    const std::uint32_t raw = u32_of(transact(line.segment, Command::Fprd, fp(station(k), dc_reg(kSystemTimeDifference)), 4, now()).data);
    const std::int64_t magnitude = raw & 0x7FFF'FFFFu;
    return (raw & 0x8000'0000u) != 0 ? -magnitude : magnitude;
  }

  // Delay measurement and offsets; returns the per-slave delays.
  std::array<std::uint32_t, kSlaves> configure() {
    const Reply latch = transact(line.segment, Command::Bwr, device_address(0, dc_reg(kReceiveTimePort0)), 4, now());
    EXPECT_EQ(latch.wkc, kSlaves);
    advance(std::chrono::microseconds(100));
    std::array<std::uint32_t, kSlaves> loop{};
    std::array<std::uint64_t, kSlaves> rx{};
    for (std::size_t k = 0; k < kSlaves; ++k) {
      const Data ports = transact(line.segment, Command::Fprd, fp(station(k), dc_reg(kReceiveTimePort0)), 16, now()).data;
      loop[k] = k + 1 < kSlaves ? u32_of(ports, 4) - u32_of(ports, 0) : 0;
      rx[k] = u64_of(transact(line.segment, Command::Fprd, fp(station(k), dc_reg(kReceiveTimeProcessingUnit)), 8, now()).data);
    }
    std::array<std::uint32_t, kSlaves> delays{};
    for (std::size_t k = 1; k < kSlaves; ++k) delays[k] = delays[k - 1] + (loop[k - 1] - loop[k]) / 2;
    for (std::size_t k = 0; k < kSlaves; ++k) {
      Data d(12, 0);
      store_le(d.data(), kSystemStart + delays[k] - rx[k]);  // reference rx[0] = kSystemStart
      store_le(d.data() + 8, delays[k]);
      EXPECT_EQ(transact(line.segment, Command::Fpwr, fp(station(k), dc_reg(kSystemTimeOffset)), d, now()).wkc, 1);
      transact(line.segment, Command::Fpwr, fp(station(k), dc_reg(kSpeedCounterStart)), le16(0x1000), now());
    }
    return delays;
  }

  Line line;
};

TEST_F(DcSegmentTest, PropagationDelaysFollowTheHopDelay) {
  const auto delays = configure();
  EXPECT_EQ(delays[0], 0u);
  EXPECT_NEAR(delays[1], 1000.0, 1.0);  // Segment::kDefaultHopDelay per slave
  EXPECT_NEAR(delays[2], 2000.0, 1.0);
}

TEST_F(DcSegmentTest, ArmwBurstThenFrmwCyclesConvergeAndSync0FiresTogether) {
  configure();
  // Static drift compensation: ARMW 0910:8 at the first slave, 100 µs apart.
  int converged = -1;
  for (int n = 0; n < 15000; ++n) {
    const Reply r = transact(line.segment, Command::Armw, device_address(0, dc_reg(kSystemTime)), 8, now());
    ASSERT_EQ(r.wkc, kSlaves);  // +1 for the read at the reference and for each write
    advance(std::chrono::microseconds(100));
    if (n % 100 == 99) {
      const bool ok = std::abs(difference(1)) < kLimitNs && std::abs(difference(2)) < kLimitNs;
      if (!ok) converged = -1;
      else if (converged < 0) converged = n + 1;
    }
  }
  ASSERT_GT(converged, 0);
  // SOEM's ecx_dcsync0: read the reference's time, start 10 ms later, 1 ms cycle.
  const std::uint64_t ref_time = u64_of(transact(line.segment, Command::Fprd, fp(station(0), dc_reg(kSystemTime)), 8, now()).data);
  const std::uint64_t start = ref_time + 10'000'000;
  std::array<Edges, kSlaves> edges;
  for (std::size_t k = 0; k < kSlaves; ++k) {
    line[k].dc().set_observer(&edges[k]);
    const std::uint32_t address = fp(station(k), dc_reg(kActivation));
    transact(line.segment, Command::Fpwr, address, Data{0}, now());
    Data s(8, 0);
    store_le(s.data(), start);
    transact(line.segment, Command::Fpwr, fp(station(k), dc_reg(kStartTimeCyclicOperation)), s, now());
    transact(line.segment, Command::Fpwr, fp(station(k), dc_reg(kSync0CycleTime)), le32(1'000'000), now());
    transact(line.segment, Command::Fpwr, address, Data{kActivateSyncUnit | kActivateSync0}, now());
  }
  // Cyclic: one FRMW 0910:8 per 1 ms cycle, the ESCs polled at every deadline.
  std::int64_t steady = 0;
  const Nanoseconds end = now() + std::chrono::seconds(2);
  Nanoseconds next_frame = now();
  while (now() < end) {
    if (now() >= next_frame) {
      transact(line.segment, Command::Frmw, fp(station(0), dc_reg(kSystemTime)), 8, now());
      steady = std::max({steady, std::abs(difference(1)), std::abs(difference(2))});
      next_frame += std::chrono::milliseconds(1);
    }
    const std::optional<Nanoseconds> deadline = line.segment.poll(now());
    const Nanoseconds step = deadline && *deadline > now() ? std::min(*deadline, next_frame) : next_frame;
    line.clock.set(std::max(step, now() + Nanoseconds{1}));
  }
  line.segment.poll(now());
  EXPECT_LT(steady, kLimitNs);
  ASSERT_GE(edges[0].rising.size(), 1900u);
  std::int64_t skew = 0;
  for (std::size_t k = 1; k < kSlaves; ++k) {
    ASSERT_EQ(edges[k].rising.size(), edges[0].rising.size());
    std::int64_t worst = 0;
    for (std::size_t i = 0; i < edges[0].rising.size(); ++i) {
      worst = std::max(worst, std::abs((edges[k].rising[i] - edges[0].rising[i]).count()));
    }
    EXPECT_LT(worst, kLimitNs) << "slave " << k;
    skew = std::max(skew, worst);
  }
  // The application sees SYNC0 as AL event 0x0220 bit 2 and acknowledges it.
  EXPECT_NE(line[1].read_u32(reg::kAlEventRequest) & kAlEventSync0, 0u);
  (void)line[1].read_u8(dc_reg(kSync0Status));
  EXPECT_EQ(line[1].read_u32(reg::kAlEventRequest) & kAlEventSync0, 0u);
  std::cout << "[dc] segment: |0x092C| < 100 ns after " << converged << " ARMW; 1 ms FRMW cycles: max |0x092C| "
            << steady << " ns; SYNC0 skew between slaves <= " << skew << " ns over " << edges[0].rising.size()
            << " pulses\n";
}

}  // namespace
}  // namespace ecat::esc::test
