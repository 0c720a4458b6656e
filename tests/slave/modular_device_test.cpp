// Issue 15 item 3: the modular I/O coupler (xml/devices/mdp-coupler.xml,
// ETG.5001.1 Modular Device Profile) through the whole stack: the project's
// master brings it to Op with its configured modules' PDOs in the process
// image (WKC 3 every cycle), the output bits reach the DO module's 7010h and
// the inputs of 6000h/6020h reach the master; a configured module ident list
// (F030h) the master writes in PreOp that does not match the detected list
// (F050h) is refused on PreOp -> SafeOp with AL status code 0070h, a matching
// one is accepted (docs/esi-sii.md "Modular devices").
#include <gtest/gtest.h>

#include <array>
#include <cstdint>
#include <string>

#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

constexpr Nanoseconds kCycle = std::chrono::milliseconds(1);
constexpr std::uint16_t kConfiguredIdents = 0xF030, kDetectedIdents = 0xF050;
constexpr std::uint32_t kDi8 = 0x00010001, kDo8 = 0x00010002, kAi2 = 0x00010003;
constexpr std::uint16_t kModuleIdentMismatch = 0x0070;  // ETG.1000.6 Table 11
// LRW of one slave with outputs and inputs: read +1, write +2 (ETG.1000.4 §5.4.3.2).
constexpr std::uint16_t kExpectedWkc = 3;
// Slot 1 DO8 (1601h: 8 bits); slot 0 DI8 (1A00h: 8 bits) + slot 2 AI2 (1A02h: 2 x 16 bits).
constexpr std::size_t kOutputBytes = 1, kInputBytes = 5;

class Coupler {
 public:
  Coupler() {
    auto d = esi::load_device_file(std::string(ECAT_SOURCE_DIR) + "/xml/devices/mdp-coupler.xml");
    if (!d) throw std::runtime_error(d.error().to_string());
    p.add(std::move(*d));
  }

  // Scan, mailbox, PreOp, PDO sizes, process data: the start-up up to PreOp.
  std::string to_preop() {
    auto n = p.master.scan();
    if (!n || *n != 1) return "scan";
    if (!p.master.configure_mailbox(0)) return "mailbox";
    auto st = p.master.request_state(0, master::AlState::PreOp);
    if (!st || st->error()) return "preop";
    if (!coe().read_pdo_sizes()) return "pdo sizes";
    if (!p.master.configure_process_data()) return "process data";
    return "";
  }

  // F030h the way a master writes a list: sub 0 = 0, the entries, sub 0 = n.
  void write_configured(const std::vector<std::uint32_t>& idents) {
    ASSERT_TRUE(coe().download_value(kConfiguredIdents, 0, 0, 1));
    for (std::size_t i = 0; i < idents.size(); ++i) {
      ASSERT_TRUE(coe().download_value(kConfiguredIdents, static_cast<std::uint8_t>(i + 1), idents[i], 4));
    }
    ASSERT_TRUE(coe().download_value(kConfiguredIdents, 0, static_cast<std::uint32_t>(idents.size()), 1));
  }

  Expected<master::AlStatus, master::MasterError> safeop() {
    return p.master.request_state(0, master::AlState::SafeOp);
  }

  std::string safeop_to_op() {
    for (int c = 0; c < 10; ++c) p.cycle_once(kCycle);
    auto st = p.master.request_state(0, master::AlState::Op);
    if (!st || st->error()) return "op";
    return "";
  }

  coe::ObjectStore& store() { return p.chain[0].firmware().coe().objects(); }
  master::CoeClient coe() { return master::CoeClient(p.master, 0); }

  InProcess p;
};

TEST(ModularDevice, ToOpWithTheConfiguredModulesInTheProcessImage) {
  Coupler c;
  ASSERT_EQ(c.to_preop(), "");
  auto st = c.safeop();
  ASSERT_TRUE(st);
  EXPECT_FALSE(st->error());
  ASSERT_EQ(c.safeop_to_op(), "");
  ASSERT_EQ(c.p.master.outputs(0).size(), kOutputBytes);
  ASSERT_EQ(c.p.master.inputs(0).size(), kInputBytes);

  // Inputs the modules' application would set: DI8 in slot 0 (6000h), AI2 in slot 2 (6020h).
  ASSERT_TRUE(c.store().set<std::uint8_t>(0x6000, 1, 1));
  ASSERT_TRUE(c.store().set<std::uint8_t>(0x6000, 8, 1));
  ASSERT_TRUE(c.store().set<std::int16_t>(0x6020, 1, -2));
  ASSERT_TRUE(c.store().set<std::int16_t>(0x6020, 2, 0x1234));
  c.p.master.outputs(0)[0] = 0x05;  // DO8 in slot 1: outputs 1 and 3
  for (int cycle = 0; cycle < 20; ++cycle) {
    auto r = c.p.cycle_once(kCycle);
    ASSERT_TRUE(r);
    ASSERT_EQ(r->wkc, kExpectedWkc) << "cycle " << cycle;
  }
  const auto in = c.p.master.inputs(0);
  EXPECT_EQ(in[0], 0x81);  // 6000h:01 and :08
  EXPECT_EQ(in[1], 0xFE);  // 6020h:01 = -2, little-endian
  EXPECT_EQ(in[2], 0xFF);
  EXPECT_EQ(in[3], 0x34);  // 6020h:02 = 1234h
  EXPECT_EQ(in[4], 0x12);
  EXPECT_EQ(c.store().get<std::uint8_t>(0x7010, 1), 1);
  EXPECT_EQ(c.store().get<std::uint8_t>(0x7010, 2), 0);
  EXPECT_EQ(c.store().get<std::uint8_t>(0x7010, 3), 1);
}

TEST(ModularDevice, DetectedListOverSdo) {
  Coupler c;
  ASSERT_EQ(c.to_preop(), "");
  EXPECT_EQ(c.coe().upload_value(kDetectedIdents, 0).value_or(0xFFFF), 3u);
  EXPECT_EQ(c.coe().upload_value(kDetectedIdents, 1).value_or(0), kDi8);
  EXPECT_EQ(c.coe().upload_value(kDetectedIdents, 2).value_or(0), kDo8);
  EXPECT_EQ(c.coe().upload_value(kDetectedIdents, 3).value_or(0), kAi2);
  EXPECT_EQ(c.coe().upload_value(0xF000, 1).value_or(0), 0x10u);  // module index distance
  EXPECT_EQ(c.coe().upload_value(0xF000, 2).value_or(0), 8u);     // maximum number of modules
  EXPECT_EQ(c.coe().upload_value(kConfiguredIdents, 0).value_or(0xFFFF), 0u);
  // F050h is the slave's: not writable.
  auto w = c.coe().download_value(kDetectedIdents, 1, kAi2, 4);
  ASSERT_FALSE(w);
  EXPECT_EQ(static_cast<std::uint32_t>(w.error().code), 0x06010002u);  // attempt to write a read-only object
}

TEST(ModularDevice, MatchingConfiguredListIsAccepted) {
  Coupler c;
  ASSERT_EQ(c.to_preop(), "");
  c.write_configured({kDi8, kDo8, kAi2});
  auto st = c.safeop();
  ASSERT_TRUE(st);
  EXPECT_FALSE(st->error());
  EXPECT_TRUE(st->is(master::AlState::SafeOp));
  EXPECT_EQ(st->code, 0u);
  EXPECT_EQ(c.safeop_to_op(), "");
}

TEST(ModularDevice, MismatchingConfiguredListIsRefusedWith0070h) {
  Coupler c;
  ASSERT_EQ(c.to_preop(), "");
  c.write_configured({kDi8, kAi2, kDo8});  // slots 1 and 2 swapped
  auto st = c.safeop();
  ASSERT_TRUE(st);
  EXPECT_TRUE(st->error());
  EXPECT_TRUE(st->is(master::AlState::PreOp));
  EXPECT_EQ(st->code, kModuleIdentMismatch);
  EXPECT_EQ(c.p.chain[0].status().code, esc::AlStatusCode::DetectedModuleIdentListMismatch);

  // A list of another length is refused the same way.
  ASSERT_TRUE(c.p.master.acknowledge_error(0));
  c.write_configured({kDi8, kDo8});
  st = c.safeop();
  ASSERT_TRUE(st);
  EXPECT_TRUE(st->error());
  EXPECT_EQ(st->code, kModuleIdentMismatch);

  // The master corrects its list: SafeOp and Op follow.
  ASSERT_TRUE(c.p.master.acknowledge_error(0));
  c.write_configured({kDi8, kDo8, kAi2});
  st = c.safeop();
  ASSERT_TRUE(st);
  EXPECT_FALSE(st->error());
  EXPECT_TRUE(st->is(master::AlState::SafeOp));
  EXPECT_EQ(c.safeop_to_op(), "");
}

TEST(ModularDevice, ConfiguredListIsWritableInPreOpOnly) {
  Coupler c;
  ASSERT_EQ(c.to_preop(), "");
  ASSERT_TRUE(c.safeop());
  auto w = c.coe().download_value(kConfiguredIdents, 1, kDi8, 4);
  ASSERT_FALSE(w);
  EXPECT_EQ(static_cast<std::uint32_t>(w.error().code), 0x08000022u);  // not in the present device state
  // More entries than slots: sub 0 above 8 is out of range.
  ASSERT_TRUE(c.p.master.request_state(0, master::AlState::PreOp));
  w = c.coe().download_value(kConfiguredIdents, 0, 9, 1);
  ASSERT_FALSE(w);
  EXPECT_EQ(static_cast<std::uint32_t>(w.error().code), 0x06090031u);  // value too high
}

}  // namespace
}  // namespace ecat::test
