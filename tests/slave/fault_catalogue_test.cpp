// The fault catalogue (slave::FaultCatalogue, issue 26 item 2, docs/faults.md):
// each fault engaged and cleared on a running chain of generic servos, with
// the exact registers, codes and frames the project's master then sees; bad
// requests refused with a message and nothing changed.
#include <gtest/gtest.h>

#include <array>
#include <cstring>
#include <map>
#include <optional>
#include <set>
#include <string>
#include <utility>
#include <vector>

#include "common/le.hpp"
#include "ds402/faults.hpp"
#include "master/coe_client.hpp"
#include "master/mailbox.hpp"
#include "slave/fault_catalogue.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

using slave::FaultCatalogue;
using slave::FaultId;
using slave::FaultRequest;

constexpr std::uint16_t kDlStatus = 0x0110;
constexpr std::uint16_t kRxErrorCounters = 0x0300;  // 0x0300-0x0313
constexpr std::uint16_t kLostLinkCounters = 0x0310;
constexpr std::uint16_t kWatchdogStatusPd = 0x0440, kWatchdogCounterPd = 0x0442;
// AL status 0x0130 values: state | ErrInd (bit 4).
constexpr std::uint16_t kInit = 0x01, kPreOp = 0x02, kSafeOp = 0x04, kOp = 0x08, kErrInd = 0x10;
constexpr Nanoseconds kCycle = std::chrono::milliseconds(1);

FaultRequest request(std::string kind, std::optional<std::size_t> slave = std::nullopt,
                     std::optional<unsigned> port = std::nullopt, std::map<std::string, std::int64_t> params = {}) {
  return FaultRequest{std::move(kind), slave, port, std::move(params)};
}

// A line of `n` generic servos whose frames pass the catalogue; a frame
// that does not come back (lost, dropped, corrupted) is lost to the master.
struct Rig : InProcess {
  FaultCatalogue faults{chain};
  std::vector<std::pair<FaultId, bool>> events;  // what the observer heard

  explicit Rig(std::size_t n = 3) {
    add_default(n);
    wire.set_processor([this](Bytes frame) {
      clock.advance(kWireTime);
      if (!faults.process_frame(frame, clock.now())) wire.drop_next(1);
    });
    faults.set_observer([this](const slave::EngagedFault& f, bool on) { events.emplace_back(f.id, on); });
  }
  std::uint16_t station(std::size_t i) { return master.slave(i).station_address; }
  std::uint16_t reg16(std::size_t i, std::uint16_t reg) {
    auto v = master.fprd_u16(station(i), reg);
    EXPECT_TRUE(v) << "slave " << i << " reg " << std::hex << reg;
    return v ? *v : 0xDEAD;
  }
  std::uint8_t reg8(std::size_t i, std::uint16_t reg) {
    auto v = master.fprd_u8(station(i), reg);
    EXPECT_TRUE(v) << "slave " << i << " reg " << std::hex << reg;
    return v ? *v : 0xEE;
  }
  FaultId engage(const FaultRequest& r) {
    auto id = faults.engage(r);
    EXPECT_TRUE(id) << (id ? "" : id.error());
    return id ? *id : 0;
  }
  master::AlStatus al(std::size_t i) {
    auto s = master.read_al_status(i);
    EXPECT_TRUE(s);
    return s ? *s : master::AlStatus{};
  }
};

TEST(FaultCatalogue, ListsExactlyTheImplementedKinds) {
  std::set<std::string> names;
  for (const slave::FaultKind& k : FaultCatalogue::kinds()) {
    EXPECT_FALSE(k.description.empty()) << k.name;
    EXPECT_EQ(FaultCatalogue::find_kind(k.name), &k);
    names.emplace(k.name);
  }
  EXPECT_EQ(names, (std::set<std::string>{"link_cut", "corrupt_frames", "drop_frames", "wkc_offset", "al_error",
                                          "refuse_transition", "watchdog_expiry", "power_cycle",
                                          "sii_bad_checksum", "sii_busy_stuck", "mailbox_counter_frozen",
                                          "mailbox_held", "drive_fault", "mailbox_error_replies",
                                          "mailbox_reply_limit", "emergency_storm", "sdo_upload_truncated",
                                          "sdo_toggle_wrong", "unplug", "delay_frames", "duplicate_frames", "replay_frames",
                                          "dc_drift", "dc_time_jump", "sync0_stopped", "limit_switch",
                                          "quick_stop_input", "sto", "brake_stuck"}));
  EXPECT_EQ(FaultCatalogue::find_kind("melt"), nullptr);
}

// Bad input: a message that names the problem, nothing engaged, nothing
// changed on the network, the slaves still answering.
TEST(FaultCatalogue, RefusesBadRequestsAndChangesNothing) {
  Rig r;
  ASSERT_EQ(r.master.scan().value_or(0), 3u);
  const std::pair<FaultRequest, std::string> bad[] = {
      {request("melt", 0), "unknown fault kind 'melt'"},
      {request("link_cut", 3, 1), "link_cut: no slave 3 (0-based; the chain has 3)"},
      {request("link_cut", 0), "link_cut: needs a port"},
      {request("link_cut", std::nullopt, 1), "link_cut: needs a slave"},
      {request("link_cut", 0, 4), "link_cut: no port 4 (ports are 0..3)"},
      {request("link_cut", 2, 1), "link_cut: nothing is cabled on port 1 of slave 2"},
      {request("drop_frames", std::nullopt, std::nullopt, {{"cnt", 1}}),
       "drop_frames: unknown parameter 'cnt' (takes: count, after)"},
      {request("drop_frames", std::nullopt, std::nullopt, {{"count", -1}}), "drop_frames: count = -1 is out of range"},
      {request("wkc_offset", std::nullopt, std::nullopt, {{"command", 15}, {"offset", 1}}),
       "wkc_offset: command = 15 is out of range (1..14)"},
      {request("wkc_offset", std::nullopt, std::nullopt, {{"command", 12}, {"offset", 0}}),
       "wkc_offset: offset 0 changes nothing"},
      {request("al_error", 1), "al_error: parameter 'code' is required"},
      {request("al_error", 1, std::nullopt, {{"code", 0x10000}}), "al_error: code = 65536 is out of range"},
      {request("al_error", 1, std::nullopt, {{"code", 0x1A}, {"state", 8}}), "al_error: state 8 is not"},
      {request("refuse_transition", 1, std::nullopt, {{"code", 0x11}, {"state", 1}}),
       "refuse_transition: state 1 is not an upward target"},
      {request("drive_fault", 0, 1, {{"code", 0x2310}}), "drive_fault: takes no port"},
      {request("drive_fault", 0, std::nullopt, {{"code", 0x2310}, {"axis", 1}}),
       "drive_fault: slave 0 runs no CiA 402 drive with an axis 1"},
      {request("watchdog_expiry", 0), "watchdog_expiry: the process-data watchdog of slave 0 is not running"},
  };
  for (const auto& [req, message] : bad) {
    auto id = r.faults.engage(req);
    ASSERT_FALSE(id) << req.kind;
    EXPECT_EQ(id.error().substr(0, message.size()), message);
  }
  EXPECT_TRUE(r.faults.engaged().empty());
  EXPECT_TRUE(r.events.empty());
  auto c = r.faults.clear(99);
  ASSERT_FALSE(c);
  EXPECT_EQ(c.error(), "no engaged fault 99");
  EXPECT_EQ(r.master.count_slaves().value_or(0), 3u);
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(r.al(i).raw, kInit);
}

// Idle, the catalogue changes nothing: the same requests through it and
// straight into an equal chain come back byte for byte the same.
TEST(FaultCatalogue, IdleFramePathIsTheChains) {
  Rig through;
  InProcess direct;
  direct.add_default(3);
  std::vector<std::vector<std::uint8_t>> replies[2];
  through.wire.set_processor([&](Bytes f) {
    through.clock.advance(kWireTime);
    if (!through.faults.process_frame(f, through.clock.now())) through.wire.drop_next(1);
    replies[0].emplace_back(f.begin(), f.end());
  });
  direct.wire.set_processor([&](Bytes f) {
    direct.clock.advance(kWireTime);
    if (!direct.chain.process_frame(f, direct.clock.now())) direct.wire.drop_next(1);
    replies[1].emplace_back(f.begin(), f.end());
  });
  ASSERT_EQ(through.bring_up(kCycle), "");
  ASSERT_EQ(direct.bring_up(kCycle), "");
  for (int i = 0; i < 20; ++i) {
    ASSERT_TRUE(through.cycle_once(kCycle));
    ASSERT_TRUE(direct.cycle_once(kCycle));
  }
  ASSERT_GT(replies[0].size(), 100u);
  EXPECT_EQ(replies[0], replies[1]);
  EXPECT_EQ(through.chain.stats().wkc_total, direct.chain.stats().wkc_total);
  for (std::size_t i = 0; i < 3; ++i) {
    EXPECT_EQ(0, std::memcmp(through.chain[i].esc().memory(), direct.chain[i].esc().memory(), 0x1000)) << i;
  }
}

// Destroying the catalogue clears what it engaged.
TEST(FaultCatalogue, DestructorClearsEverything) {
  InProcess p;
  p.add_default(2);
  {
    FaultCatalogue faults(p.chain);
    ASSERT_TRUE(faults.engage(request("link_cut", 0, 1)));
    ASSERT_TRUE(faults.engage(request("sii_busy_stuck", 1)));
    EXPECT_FALSE(p.chain.segment().link_up(0, 1));
  }
  EXPECT_TRUE(p.chain.segment().link_up(0, 1));
  ASSERT_EQ(p.master.scan().value_or(0), 2u);  // reads both SIIs: not stuck
}

// link_cut (Section I §3.4, §14; Section II 0x0110, 0x0310): the cable
// slave 1 port 1 - slave 2 port 0 is cut and restored.
TEST(FaultCatalogue, LinkCutAndRestore) {
  Rig r;
  ASSERT_EQ(r.master.scan().value_or(0), 3u);
  // Slave 1: EEPROM loaded + PDI watchdog (bits 0-1), links on ports 0 and 1
  // (bits 4, 5), ports 0 and 1 open with communication (bits 9, 11), ports
  // 2 and 3 closed (bits 12, 14).
  constexpr std::uint16_t kBothLinks = 0x5A33;
  EXPECT_EQ(r.reg16(1, kDlStatus), kBothLinks);
  const FaultId id = r.engage(request("link_cut", 1, 1));
  EXPECT_EQ(r.master.count_slaves().value_or(0), 2u);  // BRD: slave 2 is gone
  // Port 1: no link (bit 5 clear), loop closed (bit 10), no communication (bit 11 clear).
  EXPECT_EQ(r.reg16(1, kDlStatus), 0x5613);
  EXPECT_EQ(r.reg8(1, kLostLinkCounters + 1), 1);
  EXPECT_FALSE(r.master.fprd_u16(r.station(2), kDlStatus));
  ASSERT_EQ(r.faults.engaged().size(), 1u);
  EXPECT_EQ(r.faults.engaged()[0].request.kind, "link_cut");
  auto again = r.faults.engage(request("link_cut", 2, 0));  // the same cable from its other end
  ASSERT_FALSE(again);
  EXPECT_EQ(again.error(), "link_cut: the cable on port 0 of slave 2 is already down");

  ASSERT_TRUE(r.faults.clear(id));
  EXPECT_EQ(r.master.count_slaves().value_or(0), 3u);
  EXPECT_EQ(r.reg16(1, kDlStatus), kBothLinks);
  EXPECT_EQ(r.reg8(2, kLostLinkCounters + 0), 1);  // slave 2 lost its port 0 link once
  EXPECT_EQ(r.reg8(1, kLostLinkCounters + 1), 1);
  EXPECT_EQ(r.events, (std::vector<std::pair<FaultId, bool>>{{id, true}, {id, false}}));
  EXPECT_TRUE(r.faults.engaged().empty());
}

// corrupt_frames (Section I §14.2): the cable slave 1 port 1 - slave 2
// port 0 corrupts two frames; slave 2 counts them as its own invalid frames
// at port 0 (0x0300) and in its processing unit (0x030C), slaves 1 and 0
// as forwarded errors at port 1 (0x0309); the master loses both.
TEST(FaultCatalogue, CorruptFramesCountedAsSiliconCounts) {
  for (const bool rx_error : {false, true}) {
    Rig r;
    ASSERT_EQ(r.master.scan().value_or(0), 3u);
    const std::uint64_t lost = r.chain.stats().frames_lost;
    const FaultId id = r.engage(request("corrupt_frames", 1, 1, {{"count", 2}, {"rx_error", rx_error ? 1 : 0}}));
    EXPECT_TRUE(r.al(0).is(master::AlState::Init));  // two tries lost, the third comes back
    EXPECT_EQ(r.chain.stats().frames_lost - lost, 2u);
    EXPECT_EQ(r.events, (std::vector<std::pair<FaultId, bool>>{{id, true}, {id, false}}));  // spent: cleared
    EXPECT_TRUE(r.faults.engaged().empty());
    std::array<std::array<std::uint8_t, 0x14>, 3> got{};
    for (std::size_t i = 0; i < 3; ++i) ASSERT_TRUE(r.master.fprd(r.station(i), kRxErrorCounters, got[i]));
    std::array<std::uint8_t, 0x14> slave2{}, forwarded{};
    slave2[0x00] = 2;                   // 0x0300 invalid frame port 0
    slave2[0x01] = rx_error ? 2 : 0;    // 0x0301 RX error port 0
    slave2[0x0C] = 2;                   // 0x030C processing unit
    forwarded[0x09] = 2;                // 0x0309 forwarded error port 1
    EXPECT_EQ(got[2], slave2) << rx_error;
    EXPECT_EQ(got[1], forwarded) << rx_error;
    EXPECT_EQ(got[0], forwarded) << rx_error;
  }
}

// drop_frames before the slaves: two frames never reach them; the master's
// third try gets through.
TEST(FaultCatalogue, DropFramesBeforeTheSlaves) {
  Rig r;
  ASSERT_EQ(r.master.scan().value_or(0), 3u);
  const std::size_t sent = r.wire.frames_sent();
  const std::uint64_t received = r.chain.stats().frames_received;
  const FaultId id = r.engage(request("drop_frames", std::nullopt, std::nullopt, {{"count", 2}}));
  EXPECT_EQ(r.al(1).raw, kInit);
  EXPECT_EQ(r.wire.frames_sent() - sent, 3u);
  EXPECT_EQ(r.chain.stats().frames_received - received, 1u);  // the slaves saw only the third
  EXPECT_EQ(r.events, (std::vector<std::pair<FaultId, bool>>{{id, true}, {id, false}}));
}

// drop_frames after: the slaves process the frame, the reply is lost (an
// FPWR that took effect although the master saw no reply).
TEST(FaultCatalogue, DropFramesAfterTheSlavesProcessedThem) {
  Rig r;
  ASSERT_EQ(r.master.scan().value_or(0), 3u);
  const std::uint64_t received = r.chain.stats().frames_received;
  r.engage(request("drop_frames", std::nullopt, std::nullopt, {{"count", 1}, {"after", 1}}));
  constexpr std::uint16_t kUserRam = 0x0F80;  // Section II 0x0F80-0x0FFF
  EXPECT_TRUE(r.master.fpwr_u16(r.station(0), kUserRam, 0x1234));  // first try lost, second answered
  EXPECT_EQ(r.chain.stats().frames_received - received, 2u);
  EXPECT_EQ(r.reg16(0, kUserRam), 0x1234);
}

// drop_frames for one slave: every frame carrying a datagram for slave 1
// is lost after it, until cleared; frames for the others pass.
TEST(FaultCatalogue, DropTheRepliesOfOneSlave) {
  Rig r;
  ASSERT_EQ(r.master.scan().value_or(0), 3u);
  const std::uint64_t received = r.chain.stats().frames_received;
  const FaultId id = r.engage(request("drop_frames", 1, std::nullopt, {{"count", 0}}));
  auto s = r.master.read_al_status(1);
  ASSERT_FALSE(s);
  EXPECT_EQ(s.error(), master::MasterError::Timeout);
  EXPECT_EQ(r.chain.stats().frames_received - received, 4u);  // the first try and 3 retries, all processed
  EXPECT_EQ(r.al(0).raw, kInit);
  EXPECT_EQ(r.al(2).raw, kInit);
  ASSERT_TRUE(r.faults.clear(id));
  EXPECT_EQ(r.al(1).raw, kInit);
}

// wkc_offset: the cyclic LRW comes back one short; an FPRD two high.
TEST(FaultCatalogue, WorkingCounterOffsetPerCommand) {
  Rig r;
  ASSERT_EQ(r.bring_up(kCycle), "");
  ASSERT_TRUE(r.master.uses_lrw());
  auto ok = r.cycle_once(kCycle);
  ASSERT_TRUE(ok && ok->ok());
  const std::uint16_t expected = r.master.expected_wkc();
  EXPECT_EQ(expected, 9u);  // 3 slaves x (2 for outputs + 1 for inputs)
  const FaultId id =
      r.engage(request("wkc_offset", std::nullopt, std::nullopt, {{"command", 12}, {"offset", -1}}));
  for (int i = 0; i < 3; ++i) {
    auto c = r.cycle_once(kCycle);
    ASSERT_TRUE(c);
    EXPECT_EQ(c->wkc, expected - 1);
    EXPECT_EQ(c->datagrams_wrong, 1u);
  }
  EXPECT_EQ(r.al(0).raw, kOp);  // FPRD untouched
  ASSERT_TRUE(r.faults.clear(id));
  auto c = r.cycle_once(kCycle);
  ASSERT_TRUE(c && c->ok());

  r.engage(request("wkc_offset", std::nullopt, std::nullopt, {{"command", 4}, {"offset", 2}, {"count", 1}}));
  std::array<std::uint8_t, 2> dl{};
  auto wkc = r.master.transact(Command::Fprd, (std::uint32_t{kDlStatus} << 16) | r.station(1), dl);
  ASSERT_TRUE(wkc);
  EXPECT_EQ(*wkc, 3u);
  EXPECT_TRUE(r.faults.engaged().empty());  // spent after one frame
  wkc = r.master.transact(Command::Fprd, (std::uint32_t{kDlStatus} << 16) | r.station(1), dl);
  EXPECT_EQ(wkc.value_or(0), 1u);
}

// al_error (ETG.1000.6 §6.4.1.3; esm-al-codes.md §4): 001Ah forces SafeOp
// with ErrInd; while engaged the master's acknowledge + Op is refused with
// the same code; cleared, it works.
TEST(FaultCatalogue, AlErrorLatchesTheCodeAndTheStateItForces) {
  Rig r;
  ASSERT_EQ(r.bring_up(kCycle), "");
  EXPECT_FALSE(r.chain.firmware_kept_serial());
  const FaultId id = r.engage(request("al_error", 1, std::nullopt, {{"code", 0x001A}}));
  // Its ESM guard calls back into the catalogue from the firmware: no
  // firmware on helper threads from now on (Chain::set_firmware_threads).
  EXPECT_TRUE(r.chain.firmware_kept_serial());
  master::AlStatus s = r.al(1);
  EXPECT_EQ(s.raw, kSafeOp | kErrInd);
  EXPECT_EQ(s.code, 0x001A);
  EXPECT_EQ(r.al(0).raw, kOp);
  EXPECT_EQ(r.al(2).raw, kOp);
  (void)r.cycle_once(kCycle);
  auto st = r.master.request_state(1, master::AlState::Op, true);
  ASSERT_TRUE(st);
  EXPECT_EQ(st->raw, kSafeOp | kErrInd);
  EXPECT_EQ(st->code, 0x001A);
  ASSERT_TRUE(r.faults.clear(id));
  EXPECT_EQ(r.al(1).raw, kSafeOp | kErrInd);  // latched until the master acknowledges
  (void)r.cycle_once(kCycle);
  st = r.master.request_state(1, master::AlState::Op, true);
  ASSERT_TRUE(st);
  EXPECT_EQ(st->raw, kOp);
  EXPECT_EQ(st->code, 0);

  // A vendor code with a chosen state.
  r.engage(request("al_error", 2, std::nullopt, {{"code", 0x8001}, {"state", 2}}));
  s = r.al(2);
  EXPECT_EQ(s.raw, kPreOp | kErrInd);
  EXPECT_EQ(s.code, 0x8001);
  // 001Bh defaults to SafeOp, 001Eh to PreOp (the table's resulting states).
  r.engage(request("al_error", 0, std::nullopt, {{"code", 0x001E}}));
  EXPECT_EQ(r.al(0).raw, kPreOp | kErrInd);
}

// refuse_transition: the next upward transition is refused with the code;
// spent, it clears itself and the next request works.
TEST(FaultCatalogue, RefuseTheNextTransition) {
  Rig r(1);
  ASSERT_EQ(r.master.scan().value_or(0), 1u);
  ASSERT_TRUE(r.master.configure_mailbox(0));
  const FaultId id = r.engage(request("refuse_transition", 0, std::nullopt, {{"code", 0x8123}, {"state", 2}}));
  auto st = r.master.request_state(0, master::AlState::PreOp);
  ASSERT_TRUE(st);
  EXPECT_EQ(st->raw, kInit | kErrInd);
  EXPECT_EQ(st->code, 0x8123);
  EXPECT_EQ(r.events, (std::vector<std::pair<FaultId, bool>>{{id, true}, {id, false}}));
  st = r.master.request_state(0, master::AlState::PreOp, true);
  ASSERT_TRUE(st);
  EXPECT_EQ(st->raw, kPreOp);
  EXPECT_EQ(st->code, 0);
}

// watchdog_expiry (Section II 0x0440/0x0442; ETG.1000.6: SafeOp + 001Bh).
TEST(FaultCatalogue, WatchdogExpiry) {
  Rig r;
  ASSERT_EQ(r.bring_up(kCycle), "");
  EXPECT_EQ(r.reg16(0, kWatchdogStatusPd), 1);
  const FaultId id = r.engage(request("watchdog_expiry", 0));
  EXPECT_EQ(r.reg16(0, kWatchdogStatusPd), 0);
  EXPECT_EQ(r.reg8(0, kWatchdogCounterPd), 1);
  master::AlStatus s = r.al(0);
  EXPECT_EQ(s.raw, kSafeOp | kErrInd);
  EXPECT_EQ(s.code, 0x001B);
  EXPECT_EQ(r.al(1).raw, kOp);
  (void)r.cycle_once(kCycle);  // outputs again: the watchdog runs
  EXPECT_EQ(r.reg16(0, kWatchdogStatusPd), 1);
  auto st = r.master.request_state(0, master::AlState::Op, true);
  ASSERT_TRUE(st);
  EXPECT_EQ(st->raw, kSafeOp | kErrInd);
  EXPECT_EQ(st->code, 0x001B);
  ASSERT_TRUE(r.faults.clear(id));
  (void)r.cycle_once(kCycle);
  st = r.master.request_state(0, master::AlState::Op, true);
  ASSERT_TRUE(st);
  EXPECT_EQ(st->raw, kOp);
}

// power_cycle: slave 1 of 3 loses power in Op; the master finds it back
// at Init with the power-up registers (hot connect).
TEST(FaultCatalogue, PowerCycle) {
  Rig r;
  ASSERT_EQ(r.bring_up(kCycle), "");
  constexpr std::uint16_t kStationAddress = 0x0010, kAlStatus = 0x0130, kAlStatusCode = 0x0134;
  constexpr std::uint16_t kPdiControl = 0x0140;
  const std::uint16_t pdi_control = r.reg16(1, kPdiControl);
  EXPECT_EQ(r.reg16(1, kStationAddress), r.station(1));
  auto refused = r.faults.engage(request("al_error", 1, std::nullopt, {{"code", 0x1A}}));
  ASSERT_TRUE(refused);
  auto busy = r.faults.engage(request("power_cycle", 1));
  ASSERT_FALSE(busy);
  EXPECT_EQ(busy.error(), "power_cycle: slave 1 has fault 1 (al_error) engaged on its firmware: clear it first");
  ASSERT_TRUE(r.faults.clear(*refused));

  const FaultId id = r.engage(request("power_cycle", 1));
  EXPECT_EQ(r.master.count_slaves().value_or(0), 1u);  // slave 1 and the one behind it are gone
  EXPECT_EQ(r.reg8(0, kLostLinkCounters + 1), 1);
  auto off = r.faults.engage(request("al_error", 1, std::nullopt, {{"code", 0x1A}}));
  ASSERT_FALSE(off);
  EXPECT_EQ(off.error(), "al_error: slave 1 is powered off (fault 2)");

  ASSERT_TRUE(r.faults.clear(id));
  EXPECT_EQ(r.master.count_slaves().value_or(0), 3u);
  // Position 1 by auto-increment (ADP = -1): the master's address is gone.
  std::array<std::uint8_t, 2> v{};
  auto aprd = [&](std::uint16_t reg) {
    auto w = r.master.transact(Command::Aprd, (std::uint32_t{reg} << 16) | 0xFFFFu, v);
    EXPECT_EQ(w.value_or(0), 1u) << std::hex << reg;
    return load_le<std::uint16_t>(v.data());
  };
  EXPECT_EQ(aprd(kStationAddress), 0u);
  EXPECT_EQ(aprd(kAlStatus), kInit);
  EXPECT_EQ(aprd(kAlStatusCode), 0u);
  EXPECT_EQ(aprd(kPdiControl), pdi_control);  // loaded from the SII again
  EXPECT_EQ(aprd(kDlStatus) & 0x0001u, 1u);    // EEPROM loaded
  EXPECT_EQ(r.al(0).raw, kOp);
  // The master brings it up again from scratch.
  ASSERT_EQ(r.master.scan().value_or(0), 3u);
  ASSERT_TRUE(r.master.configure_mailbox(1));
  auto st = r.master.request_state(1, master::AlState::PreOp);
  ASSERT_TRUE(st);
  EXPECT_EQ(st->raw, kPreOp);
}

// sii_bad_checksum (ETG.1000.6 §5.4; Section II 0x0502, 0x0110).
TEST(FaultCatalogue, SiiBadChecksum) {
  Rig r;
  ASSERT_EQ(r.master.scan().value_or(0), 3u);
  constexpr std::uint16_t kSiiControl = 0x0502, kChecksumError = 0x0800, kNotLoaded = 0x1000;
  constexpr std::uint16_t kChecksumWord = 7;
  std::array<std::uint8_t, 8> before{}, after{};
  ASSERT_TRUE(r.master.sii_read(r.station(1), kChecksumWord, before));
  EXPECT_EQ(r.reg16(1, kSiiControl) & (kChecksumError | kNotLoaded), 0);
  EXPECT_EQ(r.reg16(1, kDlStatus) & 0x0001, 1);
  const FaultId id = r.engage(request("sii_bad_checksum", 1));
  EXPECT_EQ(r.reg16(1, kSiiControl) & (kChecksumError | kNotLoaded), kChecksumError | kNotLoaded);
  EXPECT_EQ(r.reg16(1, kDlStatus) & 0x0001, 0);  // EEPROM not loaded
  EXPECT_EQ(r.reg16(0, kSiiControl) & kChecksumError, 0);  // the others keep theirs (a shared image is copied)
  ASSERT_TRUE(r.master.sii_read(r.station(1), kChecksumWord, after));
  EXPECT_EQ(after[0], before[0] ^ 0xFF);  // the CRC byte, every bit wrong
  EXPECT_EQ(after[1], before[1]);
  ASSERT_TRUE(r.master.sii_read(r.station(0), kChecksumWord, after));
  EXPECT_EQ(after, before);
  ASSERT_TRUE(r.faults.clear(id));
  EXPECT_EQ(r.reg16(1, kSiiControl) & (kChecksumError | kNotLoaded), 0);
  EXPECT_EQ(r.reg16(1, kDlStatus) & 0x0001, 1);
  ASSERT_TRUE(r.master.sii_read(r.station(1), kChecksumWord, after));
  EXPECT_EQ(after, before);
}

// sii_busy_stuck: the master's EEPROM reads time out with busy set.
TEST(FaultCatalogue, SiiBusyStuck) {
  Rig r;
  ASSERT_EQ(r.master.scan().value_or(0), 3u);
  constexpr std::uint16_t kSiiControl = 0x0502, kBusy = 0x8000;
  std::array<std::uint8_t, 8> word{};
  const FaultId id = r.engage(request("sii_busy_stuck", 2));
  auto got = r.master.sii_read(r.station(2), 0, word);
  ASSERT_FALSE(got);
  EXPECT_EQ(got.error(), master::MasterError::SiiTimeout);
  EXPECT_EQ(r.reg16(2, kSiiControl) & kBusy, kBusy);
  EXPECT_TRUE(r.master.sii_read(r.station(1), 0, word));  // its neighbour reads fine
  ASSERT_TRUE(r.faults.clear(id));
  EXPECT_EQ(r.reg16(2, kSiiControl) & kBusy, 0);
  std::array<std::uint8_t, 8> mine{}, neighbour{};
  ASSERT_TRUE(r.master.sii_read(r.station(2), 0, mine));
  ASSERT_TRUE(r.master.sii_read(r.station(1), 0, neighbour));
  EXPECT_EQ(mine, neighbour);  // the same device
}

// mailbox_counter_frozen (ETG.1000.4 §5.6 mailbox header, counter in byte
// 5 bits 4-6): two SDO replies in a row carry the same counter.
TEST(FaultCatalogue, MailboxCounterFrozen) {
  Rig r(1);
  ASSERT_EQ(r.master.scan().value_or(0), 1u);
  ASSERT_TRUE(r.master.configure_mailbox(0));
  ASSERT_TRUE(r.master.request_state(0, master::AlState::PreOp));
  const auto upload = master::CoeClient::upload_request(0x1000, 0, false);  // device type
  auto counter_of_reply = [&]() -> int {
    if (!r.master.mailbox_send(0, master::mbx::kTypeCoe, upload)) return -1;
    auto m = r.master.mailbox_receive(0, std::chrono::milliseconds(100));
    return m ? m->header.counter : -1;
  };
  const int first = counter_of_reply();
  ASSERT_GE(first, 1);
  const int second = counter_of_reply();
  EXPECT_EQ(second, first % 7 + 1);  // 1..7 rotating
  const FaultId id = r.engage(request("mailbox_counter_frozen", 0));
  EXPECT_EQ(counter_of_reply(), second);
  EXPECT_EQ(counter_of_reply(), second);
  ASSERT_TRUE(r.faults.clear(id));
  EXPECT_EQ(counter_of_reply(), second % 7 + 1);
}

// mailbox_held: the request is taken (SM0 emptied), the reply stays out of
// SM1 (0x080D bit 3 clear) until the fault clears, then comes in order.
TEST(FaultCatalogue, MailboxRepliesHeldPending) {
  Rig r(1);
  ASSERT_EQ(r.master.scan().value_or(0), 1u);
  ASSERT_TRUE(r.master.configure_mailbox(0));
  ASSERT_TRUE(r.master.request_state(0, master::AlState::PreOp));
  constexpr std::uint16_t kSm0Status = 0x0805, kSm1Status = 0x080D, kMailboxFull = 0x08;
  const FaultId id = r.engage(request("mailbox_held", 0));
  master::CoeClient coe(r.master, 0);
  auto v = coe.upload_value(0x1000, 0);
  ASSERT_FALSE(v);
  EXPECT_EQ(r.reg8(0, kSm0Status) & kMailboxFull, 0);  // the slave took the request
  EXPECT_EQ(r.reg8(0, kSm1Status) & kMailboxFull, 0);  // no reply
  ASSERT_TRUE(r.faults.clear(id));
  r.advance(std::chrono::milliseconds(1));
  EXPECT_EQ(r.reg8(0, kSm1Status) & kMailboxFull, kMailboxFull);  // the held reply
  auto m = r.master.mailbox_receive(0, std::chrono::milliseconds(100));
  ASSERT_TRUE(m);
  ASSERT_GE(m->payload.size(), 10u);
  // CoE header (SDO response), SDO upload expedited response for 1000h:00.
  EXPECT_EQ(m->payload[2] & 0xE0, 0x40);
  EXPECT_EQ(load_le<std::uint16_t>(m->payload.data() + 3), 0x1000);
  EXPECT_TRUE(coe.upload_value(0x1000, 0));  // the mailbox works again
}

// drive_fault (CiA 402-2 §8.1.3, CiA 301 §7.2.7): over-current 2310h.
TEST(FaultCatalogue, DriveFaultAndFaultReset) {
  Rig r(1);
  ASSERT_EQ(r.bring_up(kCycle), "");
  master::CoeClient coe(r.master, 0);
  constexpr std::uint16_t kControlword = 0x6040, kStatusword = 0x6041, kErrorCode = 0x603F, kErrorRegister = 0x1001;
  constexpr std::uint16_t kFaultMask = 0x004F, kFaultState = 0x0008, kSwitchOnDisabled = 0x0040;
  // Where 6040h sits in the outputs (the first RxPDO's entries in order).
  std::size_t cw_offset = 0;
  {
    auto pdos = coe.read_pdo_assignment(0x1C12);
    ASSERT_TRUE(pdos && !pdos->empty());
    auto entries = coe.read_pdo_mapping(pdos->front());
    ASSERT_TRUE(entries);
    bool found = false;
    for (std::uint32_t e : *entries) {
      if ((e >> 16) == kControlword) {
        found = true;
        break;
      }
      cw_offset += (e & 0xFFu) / 8;
    }
    ASSERT_TRUE(found);
  }
  auto command = [&](std::uint16_t cw) { store_le(r.master.outputs(0).data() + cw_offset, cw); };
  auto statusword = [&] { return coe.upload_value(kStatusword, 0).value_or(0xFFFF); };
  auto cycles = [&](int n) {
    for (int i = 0; i < n; ++i) ASSERT_TRUE(r.cycle_once(kCycle));
  };
  command(0);
  cycles(3);
  EXPECT_EQ(statusword() & kFaultMask, kSwitchOnDisabled);

  const FaultId id = r.engage(request("drive_fault", 0, std::nullopt, {{"code", 0x2310}}));
  cycles(3);
  EXPECT_EQ(statusword() & kFaultMask, kFaultState);
  EXPECT_EQ(coe.upload_value(kErrorCode, 0).value_or(0), 0x2310u);
  EXPECT_EQ(coe.upload_value(kErrorRegister, 0).value_or(0), 0x03u);  // generic + current
  ASSERT_FALSE(coe.emergencies().empty());
  EXPECT_EQ(coe.emergencies().back().error_code, 0x2310);
  EXPECT_EQ(coe.emergencies().back().error_register, 0x03);
  const std::size_t emcys = coe.emergencies().size();

  command(0x0080);  // fault reset while the cause persists: still Fault
  cycles(3);
  EXPECT_EQ(statusword() & kFaultMask, kFaultState);
  EXPECT_EQ(coe.upload_value(kErrorCode, 0).value_or(0), 0x2310u);
  EXPECT_EQ(coe.emergencies().size(), emcys);

  ASSERT_TRUE(r.faults.clear(id));
  command(0);
  cycles(2);
  command(0x0080);
  cycles(3);
  EXPECT_EQ(statusword() & kFaultMask, kSwitchOnDisabled);
  EXPECT_EQ(coe.upload_value(kErrorCode, 0).value_or(1), 0u);
  ASSERT_GT(coe.emergencies().size(), emcys);
  EXPECT_EQ(coe.emergencies().back().error_code, 0x0000);  // error reset
}

// The error register follows the code's class unless given.
TEST(FaultCatalogue, DriveFaultErrorRegisterByCodeClass) {
  EXPECT_EQ(ds402::error_register_for(0x2310), ds402::error_register::kCurrent);
  EXPECT_EQ(ds402::error_register_for(0x3210), ds402::error_register::kVoltage);
  EXPECT_EQ(ds402::error_register_for(0x8611), ds402::error_register::kDeviceProfile);
  EXPECT_EQ(ds402::error_register_for(0x7305), ds402::error_register::kDeviceProfile);
  EXPECT_EQ(ds402::error_register_for(0x8130), ds402::error_register::kCommunication);
  EXPECT_EQ(ds402::error_register_for(0xFF01), ds402::error_register::kManufacturer);
}

}  // namespace
}  // namespace ecat::test
