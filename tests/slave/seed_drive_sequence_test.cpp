// Issue 7 "Done when": each seed drive (and the generic servo), through the
// whole stack (master -> wire -> ESC -> CoE -> ds402), is enabled, homed,
// moved in PP, moved in a cyclic (or its own) mode, quick-stopped, faulted
// and reset. Objects in the device's default PDOs are written through the
// process image; the rest by SDO, as a master would (CiA 402-2 §8, §11, §12).
#include <gtest/gtest.h>

#include <cstdint>
#include <algorithm>
#include <map>
#include <optional>
#include <string>
#include <vector>

#include "common/le.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

constexpr Nanoseconds kCycle = std::chrono::milliseconds(1);
constexpr int kSettleCycles = 200;

// Objects (CiA 402-2).
constexpr std::uint16_t kErrorRegister = 0x1001, kErrorCode = 0x603F, kControlword = 0x6040, kStatusword = 0x6041;
constexpr std::uint16_t kQuickStopOption = 0x605A, kModes = 0x6060, kModesDisplay = 0x6061;
constexpr std::uint16_t kActualPosition = 0x6064, kFollowingWindow = 0x6065, kFollowingTime = 0x6066;
constexpr std::uint16_t kPositionWindow = 0x6067, kActualVelocity = 0x606C, kTargetPosition = 0x607A;
constexpr std::uint16_t kMaxProfileVelocity = 0x607F;
constexpr std::uint16_t kHomeOffset = 0x607C, kSoftwareLimit = 0x607D, kProfileVelocity = 0x6081;
constexpr std::uint16_t kProfileAcceleration = 0x6083, kProfileDeceleration = 0x6084, kQuickStopDecel = 0x6085;
constexpr std::uint16_t kHomingMethod = 0x6098, kHomingSpeeds = 0x6099, kHomingAcceleration = 0x609A;
constexpr std::uint16_t kTargetVelocity = 0x60FF;
constexpr std::uint16_t kRxAssign = 0x1C12, kTxAssign = 0x1C13;

// Controlword commands (Table 30) and bits.
constexpr std::uint16_t kShutdown = 0x0006, kSwitchOn = 0x0007, kEnableOperation = 0x000F;
constexpr std::uint16_t kQuickStop = 0x000B, kFaultReset = 0x0080, kNewSetPoint = 0x0010;
// Statusword: state bits + voltage enabled + remote (docs/ds402.md).
constexpr std::uint16_t kStateMask = 0x027F;
constexpr std::uint16_t kSwitchOnDisabled = 0x0250, kReadyToSwitchOn = 0x0231, kSwitchedOn = 0x0233;
constexpr std::uint16_t kOperationEnabled = 0x0237, kQuickStopActive = 0x0217, kFault = 0x0218;
constexpr std::uint16_t kTargetReached = 1u << 10, kBit12 = 1u << 12, kBit13 = 1u << 13;
constexpr std::uint16_t kHomeFound = 1u << 15;  // SIMTACH/Leadshine manufacturer bit (docs/ds402.md)
constexpr std::uint16_t kFaultStateMask = 0x004F, kFaultStateValue = 0x0008;  // Table 28: Fault
constexpr std::uint16_t kEmcyErrorReset = 0x0000;
constexpr std::uint8_t kGenericError = 0x01;

// Modes of operation (6060h).
constexpr std::int8_t kPp = 1, kPv = 3, kHm = 6, kCsp = 8;

enum class FaultPlan { FollowingErrorInCsp, SoftwareLimitInPv };

struct Seed {
  const char* file;
  std::int8_t homing_method;
  std::int8_t cyclic_mode;  // CSP, or PV where 6502h has no cyclic mode
  FaultPlan fault;
  std::uint16_t error_code;  // 603Fh the drive reports
  std::uint16_t emcy_code;   // EMCY code the master receives
  bool home_found_bit;       // statusword bit 15 once homed
  slave::PdiKind pdi = slave::PdiKind::Direct;  // issue 18: firmware over SPI to an emulated chip
};

std::ostream& operator<<(std::ostream& os, const Seed& s) { return os << s.file; }

// Where an object sits in the process image, from the PDOs the slave reports.
struct PdoEntry {
  std::size_t offset;
  unsigned bits;
};
using PdoLayout = std::map<std::uint16_t, PdoEntry>;

class Rig {
 public:
  explicit Rig(const Seed& seed) {
    auto d = esi::load_device_file(std::string(ECAT_SOURCE_DIR) + "/xml/devices/" + seed.file);
    if (!d) throw std::runtime_error(d.error().to_string());
    slave::SlaveOptions o;
    o.pdi = seed.pdi;
    p.add(std::move(*d), o);
  }

  std::string start() {
    if (auto e = p.bring_up(kCycle); !e.empty()) return e;
    if (!layout(kRxAssign, rx) || !layout(kTxAssign, tx)) return "pdo layout";
    if (!rx.contains(kControlword) || !tx.contains(kStatusword)) return "no controlword/statusword in the PDOs";
    return "";
  }

  // One cycle; false when the working counter is wrong.
  bool cycle() {
    auto r = p.cycle_once(kCycle);
    return r && r->wkc == p.master.expected_wkc();
  }
  bool cycles(int n) {
    for (int i = 0; i < n; ++i)
      if (!cycle()) return false;
    return true;
  }

  // Writes an object: through the outputs when mapped, else by SDO.
  bool set(std::uint16_t index, std::int64_t value, std::size_t size, std::uint8_t sub = 0) {
    if (auto it = rx.find(index); sub == 0 && it != rx.end()) {
      std::uint8_t* out = p.master.outputs(0).data() + it->second.offset;
      const auto v = static_cast<std::uint64_t>(value);
      for (unsigned b = 0; b < it->second.bits / 8; ++b) out[b] = static_cast<std::uint8_t>(v >> (8 * b));
      return true;
    }
    return static_cast<bool>(coe.download_value(index, sub, static_cast<std::uint32_t>(value), size));
  }
  // Reads a signed object: from the inputs when mapped, else by SDO.
  std::optional<std::int64_t> get(std::uint16_t index, std::size_t size, std::uint8_t sub = 0) {
    std::uint64_t raw = 0;
    if (auto it = tx.find(index); sub == 0 && it != tx.end()) {
      const std::uint8_t* in = p.master.inputs(0).data() + it->second.offset;
      for (unsigned b = 0; b < it->second.bits / 8; ++b) raw |= std::uint64_t{in[b]} << (8 * b);
    } else {
      auto v = coe.upload_value(index, sub);
      if (!v) return std::nullopt;
      raw = *v;
    }
    const unsigned shift = static_cast<unsigned>(64 - 8 * size);
    return static_cast<std::int64_t>(raw << shift) >> shift;  // sign-extend
  }
  std::uint16_t status() {
    const std::uint8_t* in = p.master.inputs(0).data() + tx.at(kStatusword).offset;
    return load_le<std::uint16_t>(in);
  }
  std::int64_t position() { return get(kActualPosition, 4).value_or(INT64_MIN); }
  void command(std::uint16_t cw) { set(kControlword, cw, 2); }

  // Runs cycles until (statusword & mask) == value; the cycles it took, or -1.
  int until(std::uint16_t mask, std::uint16_t value, int limit) {
    for (int i = 0; i < limit; ++i) {
      if (!cycle()) return -1;
      if ((status() & mask) == value) return i;
    }
    return -1;
  }

  InProcess p;
  master::CoeClient coe{p.master, 0};
  PdoLayout rx, tx;

 private:
  bool layout(std::uint16_t assign, PdoLayout& l) {
    auto pdos = coe.read_pdo_assignment(assign);
    if (!pdos) return false;
    std::size_t offset = 0;
    for (std::uint16_t pdo : *pdos) {
      auto entries = coe.read_pdo_mapping(pdo);
      if (!entries) return false;
      for (std::uint32_t e : *entries) {
        const auto index = static_cast<std::uint16_t>(e >> 16);
        const unsigned bits = e & 0xFFu;
        if (index != 0) l.emplace(index, PdoEntry{offset, bits});
        offset += bits / 8;
      }
    }
    return true;
  }
};

std::int64_t dist(std::int64_t a) { return a < 0 ? -a : a; }

class SeedDriveSequence : public ::testing::TestWithParam<Seed> {};

// Selects a mode and waits until 6061h shows it.
::testing::AssertionResult select_mode(Rig& r, std::int8_t mode) {
  if (!r.set(kModes, mode, 1)) return ::testing::AssertionFailure() << "6060h refused " << int{mode};
  for (int i = 0; i < 20; ++i) {
    if (!r.cycle()) return ::testing::AssertionFailure() << "WKC";
    if (r.get(kModesDisplay, 1) == mode) return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << "6061h never showed " << int{mode};
}

// Transitions 2, 3, 4 with the exact statusword after each.
void enable(Rig& r) {
  const std::uint16_t cw[] = {kShutdown, kSwitchOn, kEnableOperation};
  const std::uint16_t sw[] = {kReadyToSwitchOn, kSwitchedOn, kOperationEnabled};
  for (std::size_t k = 0; k < 3; ++k) {
    r.command(cw[k]);
    ASSERT_TRUE(r.cycles(3));
    EXPECT_EQ(r.status() & kStateMask, sw[k]) << std::hex << "step " << k << " sw " << r.status();
  }
}

constexpr std::int32_t kOffset = 5000;     // 607Ch
constexpr std::int32_t kDistance = 20000;  // of the PP move

// Homing (CiA 402-2 §11): 607Ch becomes the home point's position.
void home(Rig& r, const Seed& seed) {
  ASSERT_TRUE(r.set(kHomeOffset, kOffset, 4));
  ASSERT_TRUE(r.set(kHomingMethod, seed.homing_method, 1));
  ASSERT_TRUE(r.set(kHomingAcceleration, 2000000, 4));
  ASSERT_TRUE(r.set(kHomingSpeeds, 500000, 4, 1));
  ASSERT_TRUE(r.set(kHomingSpeeds, 200000, 4, 2));
  ASSERT_TRUE(select_mode(r, kHm));
  r.command(kEnableOperation | kNewSetPoint);
  const int homing = r.until(kTargetReached | kBit12 | kBit13, kTargetReached | kBit12, 20000);
  ASSERT_GE(homing, 0) << "homing did not attain, sw " << std::hex << r.status();
  r.command(kEnableOperation);
  ASSERT_TRUE(r.cycles(5));
  const std::int64_t window = r.get(kPositionWindow, 4).value_or(100) & 0xFFFFFFFF;  // 6067h, ds402 default if absent
  // The drive reports "attained" once its demand is at the home point; the
  // actual position then settles into the window as the loops decide.
  int settle = 0;
  while (dist(r.position() - kOffset) > window && settle < kSettleCycles) {
    ASSERT_TRUE(r.cycle());
    ++settle;
  }
  EXPECT_LE(dist(r.position() - kOffset), window) << "6064h after homing, " << settle << " ms settling";
  if (seed.homing_method == 35 || seed.homing_method == 37) {
    EXPECT_EQ(r.position(), kOffset);
  }
  EXPECT_EQ(r.status() & kHomeFound, seed.home_found_bit ? kHomeFound : 0) << std::hex << r.status();
}

// Profile Position (§12.3): set-point handshake, target reached in 6067h.
void pp_move(Rig& r) {
  const std::int64_t window = r.get(kPositionWindow, 4).value_or(100) & 0xFFFFFFFF;
  const std::int64_t pp_target = r.position() + kDistance;
  ASSERT_TRUE(select_mode(r, kPp));
  // 6081h is capped by the drive's 607Fh (max profile velocity).
  const std::int64_t velocity = std::min<std::int64_t>(40000, r.get(kMaxProfileVelocity, 4).value_or(40000) & 0xFFFFFFFF);
  ASSERT_TRUE(r.set(kProfileVelocity, velocity, 4));
  ASSERT_TRUE(r.set(kProfileAcceleration, 400000, 4));
  ASSERT_TRUE(r.set(kProfileDeceleration, 400000, 4));
  ASSERT_TRUE(r.set(kTargetPosition, pp_target, 4));
  r.command(kEnableOperation | kNewSetPoint);
  ASSERT_GE(r.until(kBit12, kBit12, 10), 0) << "set-point not acknowledged";
  r.command(kEnableOperation);
  ASSERT_GE(r.until(kBit12, 0, 10), 0) << "acknowledge not cleared";
  const int move_ms = static_cast<int>(kDistance * 1000 / velocity);
  const int pp_cycles = r.until(kTargetReached, kTargetReached, move_ms + 2000);
  ASSERT_GE(pp_cycles, 0) << "target not reached, sw " << std::hex << r.status() << std::dec << " 6064h "
                          << r.position() << " target " << pp_target << " window " << window;
  EXPECT_GE(pp_cycles + 20, move_ms);  // never faster than distance / velocity (cycles before the ack uncounted)
  EXPECT_LE(dist(r.position() - pp_target), window) << "6064h after PP";
}

// Cyclic motion (CSP), or PV where 6502h has no cyclic mode.
void cyclic_motion(Rig& r, const Seed& seed) {
  const std::int64_t window = r.get(kPositionWindow, 4).value_or(100) & 0xFFFFFFFF;
  const std::int64_t here = r.position();
  if (seed.cyclic_mode == kCsp) {
    ASSERT_TRUE(r.set(kTargetPosition, here, 4));
    ASSERT_TRUE(select_mode(r, kCsp));
    constexpr int kRamp = 500;
    constexpr std::int64_t kStep = 40;  // per 1 ms cycle: 40000 units/s
    std::int64_t worst_lag = 0;
    for (int c = 1; c <= kRamp + 300; ++c) {
      const std::int64_t target = here + kStep * std::min(c, kRamp);
      r.set(kTargetPosition, target, 4);
      ASSERT_TRUE(r.cycle());
      worst_lag = std::max(worst_lag, dist(target - r.position()));
    }
    // Position loop Kp = 100/s: lag about v/Kp = 400 units, never a runaway.
    EXPECT_GT(worst_lag, 0);
    EXPECT_LT(worst_lag, 50 * kStep);
    EXPECT_LE(dist(r.position() - (here + kStep * kRamp)), window) << "6064h after the CSP ramp";
    EXPECT_EQ(r.status() & (kTargetReached | kBit12 | kBit13), kTargetReached | kBit12) << std::hex << r.status();
  } else {
    ASSERT_TRUE(r.set(kTargetVelocity, 20000, 4));
    ASSERT_TRUE(select_mode(r, kPv));
    ASSERT_GE(r.until(kTargetReached, kTargetReached, 3000), 0) << "PV velocity not reached";
    EXPECT_NEAR(static_cast<double>(r.get(kActualVelocity, 4).value_or(0)), 20000.0, 1000.0);
    ASSERT_TRUE(r.set(kTargetVelocity, 0, 4));
    ASSERT_GE(r.until(kBit12, kBit12, 3000), 0) << "PV speed zero not reached";
  }
  EXPECT_EQ(r.status() & kStateMask, kOperationEnabled) << std::hex << r.status();
}

// Quick stop during a PP move (§8.1 transition 11, 605Ah), then enabled again.
void quick_stop(Rig& r) {
  const std::int64_t here = r.position();
  ASSERT_TRUE(r.set(kTargetPosition, here, 4));
  ASSERT_TRUE(select_mode(r, kPp));
  ASSERT_TRUE(r.set(kTargetPosition, here + 10 * kDistance, 4));
  r.command(kEnableOperation | kNewSetPoint);
  ASSERT_TRUE(r.cycles(300));
  r.command(kEnableOperation);
  ASSERT_TRUE(r.cycle());
  const std::int64_t speed = dist(r.get(kActualVelocity, 4).value_or(0));
  ASSERT_GT(speed, 1000) << "not moving before the quick stop";
  const std::int64_t braking_from = r.position();
  const std::int64_t option = r.get(kQuickStopOption, 2).value_or(2);
  // Some defaults stop over many seconds (Yaskawa PnB54 = 1000 units/s^2): a
  // master sets the ramp it wants.
  constexpr std::int64_t kQuickStopRamp = 1000000;
  ASSERT_TRUE(r.set(kQuickStopDecel, kQuickStopRamp, 4));
  r.command(kQuickStop);
  ASSERT_TRUE(r.cycles(2));  // the statusword in a frame is that of the previous application cycle
  if (option != 0) {
    EXPECT_EQ(r.status() & kStateMask, kQuickStopActive) << std::hex << r.status();
  }
  const std::uint16_t final_state = option >= 5 ? kQuickStopActive : kSwitchOnDisabled;
  ASSERT_GE(r.until(kStateMask, final_state, 5000), 0) << "quick stop, 605Ah " << option << " sw " << std::hex << r.status();
  std::int64_t stopped = r.position();
  for (int c = 0; c < 5000; c += 20) {  // at rest: 20 ms without motion
    ASSERT_TRUE(r.cycles(20));
    if (dist(r.position() - stopped) <= 2) break;
    stopped = r.position();
  }
  EXPECT_LE(dist(r.position() - stopped), 2) << "axis still moving after the quick stop";
  EXPECT_LT(dist(stopped - here), 10 * kDistance) << "quick stop did not cut the move short";
  // Braking distance v^2 / (2 * 6085h), plus the loop lag at that speed.
  const double braking = static_cast<double>(speed * speed) / (2.0 * kQuickStopRamp);
  EXPECT_NEAR(static_cast<double>(dist(stopped - braking_from)), braking, 0.1 * braking + 30.0) << "speed " << speed;
  if (option >= 5) {
    r.command(kEnableOperation);  // transition 16
    ASSERT_TRUE(r.cycles(3));
    EXPECT_EQ(r.status() & kStateMask, kOperationEnabled) << std::hex << r.status();
  } else {
    enable(r);
  }
}

// A fault (§12.4): statusword, 603Fh, 1001h and the EMCY; then fault reset
// (transition 15) back to Switch on disabled.
void fault_and_reset(Rig& r, const Seed& seed) {
  const std::int64_t here = r.position();
  std::int64_t saved = 0;
  if (seed.fault == FaultPlan::FollowingErrorInCsp) {
    ASSERT_TRUE(r.set(kTargetPosition, here, 4));
    ASSERT_TRUE(select_mode(r, kCsp));
    saved = r.get(kFollowingWindow, 4).value_or(0);
    ASSERT_TRUE(r.set(kFollowingWindow, 10, 4));
    (void)r.set(kFollowingTime, 0, 2);  // absent on some drives: their timeout is 0 already
    ASSERT_TRUE(r.set(kTargetPosition, here + 50000, 4));
  } else {
    ASSERT_TRUE(r.set(kSoftwareLimit, static_cast<std::uint32_t>(here - 100000), 4, 1));
    ASSERT_TRUE(r.set(kSoftwareLimit, static_cast<std::uint32_t>(here + 2000), 4, 2));
    ASSERT_TRUE(r.set(kTargetVelocity, 20000, 4));
    ASSERT_TRUE(select_mode(r, kPv));
  }
  ASSERT_GE(r.until(kFaultStateMask, kFaultStateValue, 3000), 0) << "no fault, sw " << std::hex << r.status();
  EXPECT_EQ(r.status() & kStateMask, kFault) << std::hex << r.status();
  EXPECT_EQ(r.get(kErrorCode, 2).value_or(-1) & 0xFFFF, seed.error_code);
  ASSERT_TRUE(r.coe.upload_value(kStatusword, 0));  // a mailbox exchange collects pending EMCYs
  if (auto reg = r.get(kErrorRegister, 1)) {
    EXPECT_EQ(*reg & kGenericError, kGenericError);
  }
  bool got_emcy = false;
  for (const auto& e : r.coe.emergencies()) {
    if (e.error_code != seed.emcy_code) continue;
    got_emcy = true;
    EXPECT_EQ(e.error_register & kGenericError, kGenericError);
    if (seed.emcy_code != seed.error_code) {  // alarm number in EMCY bytes 4-5
      EXPECT_EQ(e.data[1] | (e.data[2] << 8), seed.error_code);
    }
  }
  EXPECT_TRUE(got_emcy) << "no EMCY " << std::hex << seed.emcy_code << " among " << r.coe.emergencies().size();

  // Undo the cause, then the rising edge of bit 7.
  if (seed.fault == FaultPlan::FollowingErrorInCsp) {
    ASSERT_TRUE(r.set(kTargetPosition, r.position(), 4));
    ASSERT_TRUE(r.set(kFollowingWindow, saved, 4));
  } else {
    ASSERT_TRUE(r.set(kTargetVelocity, 0, 4));
    ASSERT_TRUE(r.set(kSoftwareLimit, 0, 4, 1));
    ASSERT_TRUE(r.set(kSoftwareLimit, 0, 4, 2));
  }
  r.command(0);
  ASSERT_TRUE(r.cycles(2));
  r.command(kFaultReset);
  ASSERT_TRUE(r.cycles(3));
  EXPECT_EQ(r.status() & kStateMask, kSwitchOnDisabled) << std::hex << r.status();
  EXPECT_EQ(r.get(kErrorCode, 2).value_or(-1), 0);
  ASSERT_TRUE(r.coe.upload_value(kStatusword, 0));  // a mailbox exchange collects pending EMCYs
  bool got_reset = false;
  for (const auto& e : r.coe.emergencies()) got_reset |= e.error_code == kEmcyErrorReset;
  EXPECT_TRUE(got_reset) << "no error-reset EMCY";
  r.command(0);
  ASSERT_TRUE(r.cycles(2));
  enable(r);  // usable again
}

TEST_P(SeedDriveSequence, EnableHomingPpCyclicQuickStopFaultReset) {
  const Seed& seed = GetParam();
  Rig r(seed);
  ASSERT_EQ(r.start(), "");
  ASSERT_TRUE(r.cycles(5));
  EXPECT_EQ(r.status() & kStateMask, kSwitchOnDisabled) << std::hex << r.status();
  ASSERT_TRUE(select_mode(r, kPp));
  ASSERT_NO_FATAL_FAILURE(enable(r));  // transitions 2, 3, 4
  ASSERT_NO_FATAL_FAILURE(home(r, seed));
  ASSERT_NO_FATAL_FAILURE(pp_move(r));
  ASSERT_NO_FATAL_FAILURE(cyclic_motion(r, seed));
  ASSERT_NO_FATAL_FAILURE(quick_stop(r));
  ASSERT_NO_FATAL_FAILURE(fault_and_reset(r, seed));
  if (seed.pdi != slave::PdiKind::Direct) {
    slave::VirtualSlave& s = r.p.chain[0];
    EXPECT_FALSE(s.spi_pdi()->failed()) << s.spi_pdi()->error();
    EXPECT_EQ(s.spi_chip()->violations(), 0u);
  }
}

// Homing methods from each drive's list (docs/ds402.md): an index pulse
// (33/34), the home switch edge (19), or the current position (35/37).
// Leadshine has no 6065h (following error) and no cyclic mode (6502h = 2Dh):
// PV and a software limit (8612h) stand in.
constexpr Seed kSeeds[] = {
    {"generic-servo.xml", 34, kCsp, FaultPlan::FollowingErrorInCsp, 0x8611, 0x8611, false},
    {"simtach-rse.xml", 19, kCsp, FaultPlan::FollowingErrorInCsp, 0x8611, 0x8611, true},
    {"yaskawa-sigma5-sd.xml", 33, kCsp, FaultPlan::FollowingErrorInCsp, 0x0D00, 0xFF00, false},
    {"welcon-servo.xml", 37, kCsp, FaultPlan::FollowingErrorInCsp, 0x8611, 0x8611, false},
    {"leadshine-isv2-can.xml", 35, kPv, FaultPlan::SoftwareLimitInPv, 0x8612, 0x8612, true}};

std::vector<Seed> seeds_over(slave::PdiKind pdi) {
  std::vector<Seed> v(std::begin(kSeeds), std::end(kSeeds));
  for (Seed& s : v) s.pdi = pdi;
  return v;
}

std::string seed_name(const ::testing::TestParamInfo<Seed>& param) {
  std::string n = param.param.file;
  n = n.substr(0, n.find('.'));
  for (char& ch : n)
    if (ch == '-') ch = '_';
  if (param.param.pdi == slave::PdiKind::Lan9252) n += "_over_lan9252";
  if (param.param.pdi == slave::PdiKind::Et1100Spi) n += "_over_et1100_spi";
  return n;
}

INSTANTIATE_TEST_SUITE_P(Seeds, SeedDriveSequence, ::testing::ValuesIn(seeds_over(slave::PdiKind::Direct)), seed_name);
// Issue 18: the same sequences with the firmware on SPI framing to an
// emulated LAN9252 and an emulated ET1100 SPI slave.
INSTANTIATE_TEST_SUITE_P(SeedsOverSpi, SeedDriveSequence,
                         ::testing::ValuesIn([] {
                           auto v = seeds_over(slave::PdiKind::Lan9252);
                           auto e = seeds_over(slave::PdiKind::Et1100Spi);
                           v.insert(v.end(), e.begin(), e.end());
                           return v;
                         }()),
                         seed_name);

}  // namespace
}  // namespace ecat::test
