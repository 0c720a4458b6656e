// Issue 15: the dual-axis Welcon (xml/devices/welcon-servo-dual.xml) through
// the whole stack (master -> wire -> ESC -> CoE -> two ds402 axes). Both axes
// run the seed-drive sequence at once - enable, homing, PP, a CSP ramp, quick
// stop, fault and reset - each through its own objects (axis 2 at +800h,
// CiA 402-1 §6) and its own PDOs (1618h/1A18h); one axis faults while the
// other keeps moving, and only the faulted axis reports 603Fh(+800h) and an
// EMCY (byte 3 = the axis number, docs/ds402.md "Several axes").
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <optional>
#include <sstream>
#include <string>

#include "common/le.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

constexpr Nanoseconds kCycle = std::chrono::milliseconds(1);
constexpr std::uint16_t kAxisOffset = 0x800;  // Welcon manual §7.1.5

// Objects of axis 1 (CiA 402-2); axis 2 adds kAxisOffset.
constexpr std::uint16_t kErrorRegister = 0x1001, kErrorCode = 0x603F, kControlword = 0x6040, kStatusword = 0x6041;
constexpr std::uint16_t kQuickStopOption = 0x605A, kModes = 0x6060, kModesDisplay = 0x6061;
constexpr std::uint16_t kActualPosition = 0x6064, kFollowingWindow = 0x6065, kFollowingTime = 0x6066;
constexpr std::uint16_t kPositionWindow = 0x6067, kActualVelocity = 0x606C, kTargetPosition = 0x607A;
constexpr std::uint16_t kHomeOffset = 0x607C, kMaxProfileVelocity = 0x607F, kProfileVelocity = 0x6081;
constexpr std::uint16_t kProfileAcceleration = 0x6083, kProfileDeceleration = 0x6084, kQuickStopDecel = 0x6085;
constexpr std::uint16_t kHomingMethod = 0x6098;
constexpr std::uint16_t kRxAssign = 0x1C12, kTxAssign = 0x1C13;

constexpr std::uint16_t kShutdown = 0x0006, kSwitchOn = 0x0007, kEnableOperation = 0x000F;
constexpr std::uint16_t kQuickStop = 0x000B, kFaultReset = 0x0080, kNewSetPoint = 0x0010;
constexpr std::uint16_t kStateMask = 0x027F;
constexpr std::uint16_t kSwitchOnDisabled = 0x0250, kReadyToSwitchOn = 0x0231, kSwitchedOn = 0x0233;
constexpr std::uint16_t kOperationEnabled = 0x0237, kQuickStopActive = 0x0217, kFault = 0x0218;
constexpr std::uint16_t kTargetReached = 1u << 10, kBit12 = 1u << 12, kBit13 = 1u << 13;
constexpr std::uint16_t kFollowingErrorCode = 0x8611, kEmcyErrorReset = 0x0000;
constexpr std::uint8_t kGenericError = 0x01, kDeviceProfileError = 0x20;
constexpr std::int8_t kPp = 1, kHm = 6, kCsp = 8;
constexpr std::int16_t kWelconQuickStopOption = 6;  // Welcon default: ramp on 6085h, stay in Quick stop active

// The Welcon's default PDOs, 1608h+1618h / 1A08h+1A18h, in bytes (manual §7.2.23/7.2.38).
constexpr std::size_t kRxBytesPerAxis = 2 + 4 + 4 + 2 + 4 + 1;
constexpr std::size_t kTxBytesPerAxis = 2 + 4 + 4 + 2 + 4 + 1;
// LRW of one slave with outputs and inputs: read +1, write +2 (ETG.1000.4 §5.4.3.2).
constexpr std::uint16_t kExpectedWkc = 3;

struct PdoEntry {
  std::size_t offset;
  unsigned bits;
};

class DualRig {
 public:
  explicit DualRig(bool trace = false) {
    auto d = esi::load_device_file(std::string(ECAT_SOURCE_DIR) + "/xml/devices/welcon-servo-dual.xml");
    if (!d) throw std::runtime_error(d.error().to_string());
    slave::SlaveOptions o;
    o.motion_trace = trace;
    p.add(std::move(*d), o);
  }

  std::string start() {
    if (auto e = p.bring_up(kCycle); !e.empty()) return e;
    if (!layout(kRxAssign, rx) || !layout(kTxAssign, tx)) return "pdo layout";
    return "";
  }

  bool cycle() {
    auto r = p.cycle_once(kCycle);
    return r && r->wkc == kExpectedWkc && p.master.expected_wkc() == kExpectedWkc;
  }
  bool cycles(int n) {
    for (int i = 0; i < n; ++i)
      if (!cycle()) return false;
    return true;
  }

  // Object `index` of axis `axis` (1 or 2), a CiA 402 object (common ones
  // such as 1001h are read with axis 1): through the process image when
  // mapped, else by SDO.
  static std::uint16_t at(int axis, std::uint16_t index) {
    return static_cast<std::uint16_t>(index + (axis - 1) * kAxisOffset);
  }
  bool set(int axis, std::uint16_t index, std::int64_t value, std::size_t size, std::uint8_t sub = 0) {
    const std::uint16_t i = at(axis, index);
    if (auto it = rx.find(i); sub == 0 && it != rx.end()) {
      std::uint8_t* out = p.master.outputs(0).data() + it->second.offset;
      const auto v = static_cast<std::uint64_t>(value);
      for (unsigned b = 0; b < it->second.bits / 8; ++b) out[b] = static_cast<std::uint8_t>(v >> (8 * b));
      return true;
    }
    return static_cast<bool>(coe.download_value(i, sub, static_cast<std::uint32_t>(value), size));
  }
  std::optional<std::int64_t> get(int axis, std::uint16_t index, std::size_t size, std::uint8_t sub = 0) {
    const std::uint16_t i = at(axis, index);
    std::uint64_t raw = 0;
    if (auto it = tx.find(i); sub == 0 && it != tx.end()) {
      const std::uint8_t* in = p.master.inputs(0).data() + it->second.offset;
      for (unsigned b = 0; b < it->second.bits / 8; ++b) raw |= std::uint64_t{in[b]} << (8 * b);
    } else {
      auto v = coe.upload_value(i, sub);
      if (!v) return std::nullopt;
      raw = *v;
    }
    const unsigned shift = static_cast<unsigned>(64 - 8 * size);
    return static_cast<std::int64_t>(raw << shift) >> shift;
  }
  std::uint16_t status(int axis) {
    return load_le<std::uint16_t>(p.master.inputs(0).data() + tx.at(at(axis, kStatusword)).offset);
  }
  std::int64_t position(int axis) { return get(axis, kActualPosition, 4).value_or(INT64_MIN); }
  void command(int axis, std::uint16_t cw) { set(axis, kControlword, cw, 2); }
  // Both statuswords masked, until both match; the cycles it took or -1.
  int until(std::uint16_t mask, std::array<std::uint16_t, 2> value, int limit) {
    for (int i = 0; i < limit; ++i) {
      if (!cycle()) return -1;
      if ((status(1) & mask) == value[0] && (status(2) & mask) == value[1]) return i;
    }
    return -1;
  }
  // The EMCYs the master has collected so far (a mailbox exchange fetches them).
  std::vector<master::Emergency> emergencies() {
    (void)coe.upload_value(kStatusword, 0);
    return coe.emergencies();
  }

  InProcess p;
  master::CoeClient coe{p.master, 0};
  std::map<std::uint16_t, PdoEntry> rx, tx;
  std::size_t rx_bytes = 0, tx_bytes = 0;

 private:
  bool layout(std::uint16_t assign, std::map<std::uint16_t, PdoEntry>& l) {
    auto pdos = coe.read_pdo_assignment(assign);
    if (!pdos) return false;
    std::size_t offset = 0;
    for (std::uint16_t pdo : *pdos) {
      auto entries = coe.read_pdo_mapping(pdo);
      if (!entries) return false;
      for (std::uint32_t e : *entries) {
        const auto index = static_cast<std::uint16_t>(e >> 16);
        if (index != 0) l.emplace(index, PdoEntry{offset, e & 0xFFu});
        offset += (e & 0xFFu) / 8;
      }
    }
    (assign == kRxAssign ? rx_bytes : tx_bytes) = offset;
    return true;
  }
};

std::int64_t dist(std::int64_t a) { return a < 0 ? -a : a; }

TEST(DualAxisWelcon, ReachesOpWithBothAxesInTheProcessImage) {
  DualRig r;
  ASSERT_EQ(r.start(), "");
  auto st = r.p.master.request_state(0, master::AlState::Op);
  ASSERT_TRUE(st);
  EXPECT_FALSE(st->error());
  auto assigned = r.coe.read_pdo_assignment(kRxAssign);
  ASSERT_TRUE(assigned);
  EXPECT_EQ(*assigned, (std::vector<std::uint16_t>{0x1608, 0x1618}));
  assigned = r.coe.read_pdo_assignment(kTxAssign);
  ASSERT_TRUE(assigned);
  EXPECT_EQ(*assigned, (std::vector<std::uint16_t>{0x1A08, 0x1A18}));
  EXPECT_EQ(r.rx_bytes, 2 * kRxBytesPerAxis);
  EXPECT_EQ(r.tx_bytes, 2 * kTxBytesPerAxis);
  EXPECT_EQ(r.p.master.outputs(0).size(), 2 * kRxBytesPerAxis);
  EXPECT_EQ(r.p.master.inputs(0).size(), 2 * kTxBytesPerAxis);
  // Axis 2's entries follow axis 1's, at +800h.
  EXPECT_EQ(r.rx.at(0x6040).offset, 0u);
  EXPECT_EQ(r.rx.at(0x6840).offset, kRxBytesPerAxis);
  EXPECT_EQ(r.rx.at(0x6860).offset, 2 * kRxBytesPerAxis - 1);
  EXPECT_EQ(r.tx.at(0x6041).offset, 0u);
  EXPECT_EQ(r.tx.at(0x6841).offset, kTxBytesPerAxis);
  EXPECT_EQ(r.tx.at(0x6861).offset, 2 * kTxBytesPerAxis - 1);
  ASSERT_TRUE(r.cycles(5));
  EXPECT_EQ(r.p.master.expected_wkc(), kExpectedWkc);
  EXPECT_EQ(r.status(1), kSwitchOnDisabled);
  EXPECT_EQ(r.status(2), kSwitchOnDisabled);
  // Each axis answers its own 6502h (the file's Drive/modes, published per
  // axis: PP VL PV HM CSP CSV CST) and commands only itself.
  EXPECT_EQ(r.get(1, 0x6502, 4), 0x03A7);
  EXPECT_EQ(r.get(2, 0x6502, 4), 0x03A7);
  r.command(2, kShutdown);
  ASSERT_TRUE(r.cycles(3));
  EXPECT_EQ(r.status(1), kSwitchOnDisabled);
  EXPECT_EQ(r.status(2) & kStateMask, kReadyToSwitchOn);
  // The SDO checks guard each axis' own 6060h (6502h has no IP, 7).
  EXPECT_FALSE(r.coe.download_value(0x6860, 0, 7, 1));
  EXPECT_FALSE(r.coe.download_value(0x6060, 0, 7, 1));
  EXPECT_TRUE(r.coe.download_value(0x6860, 0, 8, 1));
}

::testing::AssertionResult select_mode(DualRig& r, std::int8_t mode) {
  for (int a : {1, 2}) {
    if (!r.set(a, kModes, mode, 1)) return ::testing::AssertionFailure() << "6060h refused on axis " << a;
  }
  for (int i = 0; i < 20; ++i) {
    if (!r.cycle()) return ::testing::AssertionFailure() << "WKC";
    if (r.get(1, kModesDisplay, 1) == mode && r.get(2, kModesDisplay, 1) == mode) return ::testing::AssertionSuccess();
  }
  return ::testing::AssertionFailure() << "6061h/6861h never showed " << int{mode};
}

void enable(DualRig& r, int axis) {
  const std::uint16_t cw[] = {kShutdown, kSwitchOn, kEnableOperation};
  const std::uint16_t sw[] = {kReadyToSwitchOn, kSwitchedOn, kOperationEnabled};
  for (std::size_t k = 0; k < 3; ++k) {
    r.command(axis, cw[k]);
    ASSERT_TRUE(r.cycles(3));
    EXPECT_EQ(r.status(axis) & kStateMask, sw[k]) << "axis " << axis << " step " << k;
  }
}

// Per-axis parameters: the two axes move differently, so a mix-up shows.
struct AxisPlan {
  std::int8_t homing_method;
  std::int32_t home_offset;
  std::int32_t pp_distance, pp_velocity;
  std::int32_t csp_step;  // per 1 ms cycle
};
constexpr std::array<AxisPlan, 2> kPlan = {{{37, 5000, 20000, 40000, 40}, {37, -3000, -12000, 30000, -25}}};

TEST(DualAxisWelcon, SeedSequenceOnBothAxesAtOnceOneFaultsWhileTheOtherMoves) {
  DualRig r(true);
  ASSERT_EQ(r.start(), "");
  ASSERT_TRUE(r.cycles(5));
  EXPECT_EQ(r.status(1) & kStateMask, kSwitchOnDisabled);
  EXPECT_EQ(r.status(2) & kStateMask, kSwitchOnDisabled);
  for (int a : {1, 2}) {
    ASSERT_TRUE(r.set(a, kMaxProfileVelocity, 40000, 4));
    ASSERT_TRUE(r.set(a, kProfileAcceleration, 400000, 4));
    ASSERT_TRUE(r.set(a, kProfileDeceleration, 400000, 4));
    ASSERT_TRUE(r.set(a, kQuickStopDecel, 1000000, 4));
    EXPECT_EQ(r.get(a, kQuickStopOption, 2), kWelconQuickStopOption);
    EXPECT_EQ(r.get(a, kPositionWindow, 4), 5);
  }
  ASSERT_TRUE(select_mode(r, kPp));
  // Enable: both axes' transitions 2, 3, 4 in the same cycles.
  const std::uint16_t cw[] = {kShutdown, kSwitchOn, kEnableOperation};
  const std::uint16_t sw[] = {kReadyToSwitchOn, kSwitchedOn, kOperationEnabled};
  for (std::size_t k = 0; k < 3; ++k) {
    r.command(1, cw[k]);
    r.command(2, cw[k]);
    ASSERT_TRUE(r.cycles(3));
    EXPECT_EQ(r.status(1) & kStateMask, sw[k]);
    EXPECT_EQ(r.status(2) & kStateMask, sw[k]);
  }

  // Homing on the current position (37): 6064h/6864h become exactly 607Ch/687Ch.
  for (int a : {1, 2}) {
    ASSERT_TRUE(r.set(a, kHomeOffset, kPlan[a - 1].home_offset, 4));
    ASSERT_TRUE(r.set(a, kHomingMethod, kPlan[a - 1].homing_method, 1));
  }
  ASSERT_TRUE(select_mode(r, kHm));
  r.command(1, kEnableOperation | kNewSetPoint);
  r.command(2, kEnableOperation | kNewSetPoint);
  const std::uint16_t attained = kTargetReached | kBit12;
  ASSERT_GE(r.until(kTargetReached | kBit12 | kBit13, {attained, attained}, 100), 0);
  r.command(1, kEnableOperation);
  r.command(2, kEnableOperation);
  ASSERT_TRUE(r.cycles(5));
  EXPECT_EQ(r.position(1), 5000);
  EXPECT_EQ(r.position(2), -3000);

  // PP: both axes move at once, each to its own target, at its own speed.
  ASSERT_TRUE(select_mode(r, kPp));
  std::array<std::int64_t, 2> target{};
  for (int a : {1, 2}) {
    target[a - 1] = r.position(a) + kPlan[a - 1].pp_distance;
    ASSERT_TRUE(r.set(a, kProfileVelocity, kPlan[a - 1].pp_velocity, 4));
    ASSERT_TRUE(r.set(a, kTargetPosition, target[a - 1], 4));
    r.command(a, kEnableOperation | kNewSetPoint);
  }
  ASSERT_GE(r.until(kBit12, {kBit12, kBit12}, 10), 0) << "set-points not acknowledged";
  r.command(1, kEnableOperation);
  r.command(2, kEnableOperation);
  ASSERT_GE(r.until(kBit12, {0, 0}, 10), 0);
  // Halfway through axis 2's move (12000 at 30000/s: 0.4 s + ramps) both run.
  ASSERT_TRUE(r.cycles(200));
  EXPECT_GT(dist(r.get(1, kActualVelocity, 4).value_or(0)), 30000);
  EXPECT_GT(dist(r.get(2, kActualVelocity, 4).value_or(0)), 20000);
  EXPECT_LT(r.get(2, kActualVelocity, 4).value_or(0), 0);  // axis 2 runs negative
  ASSERT_GE(r.until(kTargetReached, {kTargetReached, kTargetReached}, 3000), 0);
  EXPECT_LE(dist(r.position(1) - target[0]), 5);
  EXPECT_LE(dist(r.position(2) - target[1]), 5);

  // CSP ramp on both axes, each with its own slope; the lag is v/Kp.
  for (int a : {1, 2}) ASSERT_TRUE(r.set(a, kTargetPosition, r.position(a), 4));
  ASSERT_TRUE(select_mode(r, kCsp));
  const std::array<std::int64_t, 2> here{r.position(1), r.position(2)};
  constexpr int kRamp = 500;
  std::array<std::int64_t, 2> worst_lag{};
  for (int c = 1; c <= kRamp + 300; ++c) {
    for (int a : {1, 2}) r.set(a, kTargetPosition, here[a - 1] + kPlan[a - 1].csp_step * std::min(c, kRamp), 4);
    ASSERT_TRUE(r.cycle());
    for (int a : {1, 2}) {
      const std::int64_t t = here[a - 1] + kPlan[a - 1].csp_step * std::min(c, kRamp);
      worst_lag[a - 1] = std::max(worst_lag[a - 1], dist(t - r.position(a)));
    }
  }
  for (int a : {1, 2}) {
    EXPECT_GT(worst_lag[a - 1], 0);
    EXPECT_LT(worst_lag[a - 1], 50 * dist(kPlan[a - 1].csp_step));
    EXPECT_LE(dist(r.position(a) - (here[a - 1] + kPlan[a - 1].csp_step * kRamp)), 5) << "axis " << a;
    EXPECT_EQ(r.status(a) & (kStateMask | kTargetReached | kBit12 | kBit13), kOperationEnabled | kTargetReached | kBit12);
  }

  // Quick stop of axis 1 in a PP move while axis 2 keeps ramping in CSP.
  ASSERT_TRUE(r.set(1, kTargetPosition, r.position(1), 4));
  ASSERT_TRUE(r.set(1, kModes, kPp, 1));
  ASSERT_TRUE(r.set(1, kTargetPosition, r.position(1) + 200000, 4));
  ASSERT_TRUE(r.cycles(3));
  r.command(1, kEnableOperation | kNewSetPoint);
  std::int64_t axis2_target = r.position(2);
  auto ramp_axis2 = [&](int n) {
    for (int c = 0; c < n; ++c) {
      axis2_target += kPlan[1].csp_step;
      r.set(2, kTargetPosition, axis2_target, 4);
      if (!r.cycle()) return false;
    }
    return true;
  };
  ASSERT_TRUE(ramp_axis2(300));
  r.command(1, kEnableOperation);
  ASSERT_TRUE(ramp_axis2(1));
  const std::int64_t speed = dist(r.get(1, kActualVelocity, 4).value_or(0));
  ASSERT_GT(speed, 30000);
  const std::int64_t braking_from = r.position(1);
  r.command(1, kQuickStop);
  ASSERT_TRUE(ramp_axis2(2));
  EXPECT_EQ(r.status(1) & kStateMask, kQuickStopActive);
  EXPECT_EQ(r.status(2) & kStateMask, kOperationEnabled);
  ASSERT_TRUE(ramp_axis2(200));  // 605Ah = 6: stays in Quick stop active, at rest
  EXPECT_EQ(r.status(1) & kStateMask, kQuickStopActive);
  EXPECT_EQ(r.get(1, kActualVelocity, 4), 0);
  const double braking = static_cast<double>(speed * speed) / (2.0 * 1000000);
  EXPECT_NEAR(static_cast<double>(dist(r.position(1) - braking_from)), braking, 0.1 * braking + 30.0);
  EXPECT_EQ(r.status(2) & kStateMask, kOperationEnabled);
  EXPECT_LT(dist(axis2_target - r.position(2)), 50 * dist(kPlan[1].csp_step)) << "axis 2 stopped following";
  EXPECT_GT(dist(r.get(2, kActualVelocity, 4).value_or(0)), 20000);
  r.command(1, kEnableOperation);  // transition 16
  ASSERT_TRUE(ramp_axis2(3));
  EXPECT_EQ(r.status(1) & kStateMask, kOperationEnabled);

  // Axis 2 faults (following error in CSP) while axis 1 moves in PP: only
  // 683Fh and an EMCY of axis 2; 1001h is the device's.
  const std::size_t emcy_before = r.emergencies().size();
  ASSERT_TRUE(r.set(1, kTargetPosition, r.position(1) - 30000, 4));
  r.command(1, kEnableOperation | kNewSetPoint);
  ASSERT_TRUE(ramp_axis2(3));
  r.command(1, kEnableOperation);
  ASSERT_TRUE(ramp_axis2(150));  // axis 1 at its profile velocity
  ASSERT_TRUE(r.set(2, kFollowingWindow, 10, 4));
  ASSERT_TRUE(r.set(2, kFollowingTime, 0, 2));
  ASSERT_TRUE(r.set(2, kTargetPosition, r.position(2) + 50000, 4));
  int faulted = -1;
  for (int c = 0; c < 100 && faulted < 0; ++c) {
    ASSERT_TRUE(r.cycle());
    if ((r.status(2) & kStateMask) == kFault) faulted = c;
  }
  ASSERT_GE(faulted, 0) << std::hex << r.status(2);
  EXPECT_EQ(r.get(2, kErrorCode, 2).value_or(-1) & 0xFFFF, kFollowingErrorCode);
  EXPECT_EQ(r.get(1, kErrorCode, 2), 0);
  EXPECT_EQ(r.get(1, kErrorRegister, 1), kGenericError | kDeviceProfileError);
  EXPECT_EQ(r.status(1) & kStateMask, kOperationEnabled);
  EXPECT_GT(dist(r.get(1, kActualVelocity, 4).value_or(0)), 1000) << "axis 1 stopped with axis 2's fault";
  auto emcy = r.emergencies();
  ASSERT_EQ(emcy.size(), emcy_before + 1);
  EXPECT_EQ(emcy.back().error_code, kFollowingErrorCode);
  EXPECT_EQ(emcy.back().error_register, kGenericError | kDeviceProfileError);
  EXPECT_EQ(emcy.back().data, (std::array<std::uint8_t, 5>{2, 0, 0, 0, 0}));
  int reached = -1;  // axis 1 finishes its move with axis 2 in Fault
  for (int c = 0; c < 3000 && reached < 0; ++c) {
    ASSERT_TRUE(r.cycle());
    if (r.status(1) & kTargetReached) reached = c;
  }
  ASSERT_GE(reached, 0);
  EXPECT_EQ(r.status(1) & kStateMask, kOperationEnabled);
  EXPECT_EQ(r.status(2) & kStateMask, kFault);

  // Reset axis 2: EMCY 0000h from axis 2, 683Fh and 1001h cleared.
  ASSERT_TRUE(r.set(2, kTargetPosition, r.position(2), 4));
  ASSERT_TRUE(r.set(2, kFollowingWindow, 100000, 4));
  r.command(2, 0);
  ASSERT_TRUE(r.cycles(2));
  r.command(2, kFaultReset);
  ASSERT_TRUE(r.cycles(3));
  EXPECT_EQ(r.status(2) & kStateMask, kSwitchOnDisabled);
  EXPECT_EQ(r.get(2, kErrorCode, 2), 0);
  EXPECT_EQ(r.get(1, kErrorRegister, 1), 0);
  emcy = r.emergencies();
  ASSERT_EQ(emcy.size(), emcy_before + 2);
  EXPECT_EQ(emcy.back().error_code, kEmcyErrorReset);
  EXPECT_EQ(emcy.back().error_register, 0);
  EXPECT_EQ(emcy.back().data[0], 2);
  r.command(2, 0);
  ASSERT_TRUE(r.cycles(2));
  ASSERT_NO_FATAL_FAILURE(enable(r, 2));

  // And the other way round: axis 1 faults while axis 2 ramps in CSP.
  ASSERT_TRUE(r.set(1, kTargetPosition, r.position(1), 4));
  ASSERT_TRUE(r.set(1, kModes, kCsp, 1));
  axis2_target = r.position(2);
  ASSERT_TRUE(ramp_axis2(20));
  ASSERT_TRUE(r.set(1, kFollowingWindow, 10, 4));
  ASSERT_TRUE(r.set(1, kFollowingTime, 0, 2));
  ASSERT_TRUE(r.set(1, kTargetPosition, r.position(1) + 50000, 4));
  faulted = -1;
  for (int c = 0; c < 100 && faulted < 0; ++c) {
    ASSERT_TRUE(ramp_axis2(1));
    if ((r.status(1) & kStateMask) == kFault) faulted = c;
  }
  ASSERT_GE(faulted, 0);
  ASSERT_TRUE(ramp_axis2(100));
  EXPECT_EQ(r.get(1, kErrorCode, 2).value_or(-1) & 0xFFFF, kFollowingErrorCode);
  EXPECT_EQ(r.get(2, kErrorCode, 2), 0);
  EXPECT_EQ(r.status(2) & kStateMask, kOperationEnabled);
  EXPECT_LT(dist(axis2_target - r.position(2)), 50 * dist(kPlan[1].csp_step));
  emcy = r.emergencies();
  ASSERT_EQ(emcy.size(), emcy_before + 3);
  EXPECT_EQ(emcy.back().error_code, kFollowingErrorCode);
  EXPECT_EQ(emcy.back().data[0], 1);
  ASSERT_TRUE(r.set(1, kTargetPosition, r.position(1), 4));
  ASSERT_TRUE(r.set(1, kFollowingWindow, 100000, 4));
  r.command(1, 0);
  ASSERT_TRUE(ramp_axis2(2));
  r.command(1, kFaultReset);
  ASSERT_TRUE(ramp_axis2(3));
  EXPECT_EQ(r.status(1) & kStateMask, kSwitchOnDisabled);
  EXPECT_EQ(r.get(1, kErrorCode, 2), 0);
  EXPECT_EQ(r.get(1, kErrorRegister, 1), 0);  // 1001h is common
  emcy = r.emergencies();
  ASSERT_EQ(emcy.size(), emcy_before + 4);
  EXPECT_EQ(emcy.back().error_code, kEmcyErrorReset);
  EXPECT_EQ(emcy.back().data[0], 1);

  // The plot: two traces, one per axis.
  const std::string path = (std::filesystem::temp_directory_path() / "ecat-dual-axis-test.svg").string();
  ASSERT_TRUE(r.p.chain.write_plot(path));
  std::ifstream f(path);
  std::stringstream svg;
  svg << f.rdbuf();
  const std::string s = svg.str();
  EXPECT_NE(s.find("<title>axis 1 actual</title>"), std::string::npos);
  EXPECT_NE(s.find("<title>axis 2 actual</title>"), std::string::npos);
  EXPECT_NE(s.find("Quick stop"), std::string::npos);
  EXPECT_NE(s.find("Fault"), std::string::npos);
  std::filesystem::remove(path);
  if (const char* update = std::getenv("ECAT_UPDATE_DOCS"); update && std::string(update) == "1") {
    ASSERT_TRUE(r.p.chain.write_plot(std::string(ECAT_SOURCE_DIR) + "/docs/ds402-dual-axis.svg"));
  }
}

}  // namespace
}  // namespace ecat::test
