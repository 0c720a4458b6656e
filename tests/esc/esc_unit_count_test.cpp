// An ESC has the FMMUs and SyncManagers its type has (0x0004 / 0x0005,
// Section II "FMMUs supported" / "SyncManagers supported"; an ET1100 has
// 8 and 8, an ET1200 3 and 4) and keeps state for those only (issue 16
// item 5: memory per slave). The registers of a unit it lacks behave as they
// always did here: they read 0 - except an SM's status byte, which reads
// 0x30 as that of an idle 3-buffer SM (control 0) after reset -, an ECAT or
// PDI write stores nothing there (it still counts for the WKC, as a write
// to any register of the block does), and such a unit maps, guards and
// signals nothing.
#include <gtest/gtest.h>

#include "esc_fixture.hpp"

namespace ecat::esc::test {
namespace {

constexpr std::uint16_t kStation = 0x1001;
constexpr std::uint8_t kRead = 1;
constexpr std::uint8_t kWrite = 2;
constexpr std::uint8_t kControlBuffered = 0x24;   // 3-buffer, ECAT writes, AL event on
constexpr std::uint8_t kControlMailboxIn = 0x26;  // mailbox, ECAT writes, AL event on
constexpr std::uint32_t kAlEventSmActivation = 1u << 4;

EscConfig with_units(std::uint8_t fmmus, std::uint8_t sms) {
  EscConfig c = make_config();
  c.fmmu_count = fmmus;
  c.sync_manager_count = sms;
  return c;
}

std::uint32_t al_event(Esc& e) {
  return e.register_u16(reg::kAlEventRequest) | (static_cast<std::uint32_t>(e.register_u16(reg::kAlEventRequest + 2)) << 16);
}

TEST(EscUnitCount, ReportsTheUnitsOfItsType) {
  Line et1200(1, with_units(3, 4));
  assign_stations(et1200);
  auto r = transact(et1200.segment, Command::Fprd, fp(kStation, reg::kFmmusSupported), 2);
  EXPECT_EQ(r.wkc, 1);
  EXPECT_EQ(r.data, (Data{3, 4}));
  Line et1100(1);  // the default: 8 and 8
  EXPECT_EQ(et1100[0].register_u16(reg::kFmmusSupported), 0x0808u);
  Line beyond(1, with_units(20, 17));  // clamped to the 16 the register block has room for
  EXPECT_EQ(beyond[0].register_u16(reg::kFmmusSupported), 0x1010u);
}

TEST(EscUnitCount, RegistersOfAMissingSyncManagerReadZeroAndIgnoreWrites) {
  Line line(1, with_units(3, 4));
  assign_stations(line);
  Esc& esc = line[0];
  // Start, length, control, status 0x30 (3-buffer, no buffer written), activate, PDI control.
  const Data absent{0x00, 0x00, 0x00, 0x00, 0x00, 0x30, 0x00, 0x00};
  const Data sm_bytes{0x00, 0x11, 0x04, 0x00, kControlBuffered, 0x00, 0x01, 0x00};  // 0x1100, 4 bytes, enabled
  for (unsigned n : {4u, 7u, 15u}) {
    SCOPED_TRACE(n);
    auto r = transact(line.segment, Command::Fpwr, fp(kStation, reg::sync_manager(n)), sm_bytes);
    EXPECT_EQ(r.wkc, 1);
    r = transact(line.segment, Command::Fprd, fp(kStation, reg::sync_manager(n)), Data(8, 0xEE));
    EXPECT_EQ(r.wkc, 1);
    EXPECT_EQ(r.data, absent);
    // PDI control (0x0807) from the PDI side: not stored either.
    const std::uint8_t deactivate = 1;
    esc.write(static_cast<std::uint16_t>(reg::sync_manager(n) + reg::sm::kPdiControl), std::span(&deactivate, 1));
    std::array<std::uint8_t, 8> pdi{};
    pdi.fill(0xEE);
    esc.read(reg::sync_manager(n), pdi);
    EXPECT_EQ(Data(pdi.begin(), pdi.end()), absent);
  }
  for (unsigned n : {4u, 15u}) {
    const SyncManager& sm = esc.sync_manager(n);
    EXPECT_FALSE(sm.enabled());
    EXPECT_EQ(sm.start(), 0u);
    EXPECT_EQ(sm.length(), 0u);
    EXPECT_EQ(sm.control(), 0u);
  }
  // Activating a missing SM raised no SM activation event (Section II
  // 0x0220 bit 4), which the last present SM does.
  EXPECT_EQ(al_event(esc) & kAlEventSmActivation, 0u);
  // Its area is plain memory, not a buffer: bytes written there read back
  // at once, as often as asked, with no buffer exchange or event.
  auto r = transact(line.segment, Command::Fpwr, fp(kStation, 0x1100), Data{1, 2, 3, 4});
  EXPECT_EQ(r.wkc, 1);
  for (int i = 0; i < 2; ++i) {
    r = transact(line.segment, Command::Fprd, fp(kStation, 0x1100), Data(4, 0));
    EXPECT_EQ(r.wkc, 1);
    EXPECT_EQ(r.data, (Data{1, 2, 3, 4}));
  }
  EXPECT_EQ(al_event(esc), 0u);
  // SM 3, the last one the ESC has, over the same bytes: a mailbox now.
  config_sm(line.segment, kStation, 3, 0x1100, 4, kControlMailboxIn);
  EXPECT_NE(al_event(esc) & kAlEventSmActivation, 0u);
  r = transact(line.segment, Command::Fpwr, fp(kStation, 0x1100), Data{5, 6, 7, 8});
  EXPECT_EQ(r.wkc, 1);
  r = transact(line.segment, Command::Fpwr, fp(kStation, 0x1100), Data{9, 9, 9, 9});
  EXPECT_EQ(r.wkc, 0);  // full until the PDI reads it
  EXPECT_EQ(al_event(esc) & (1u << (8 + 3)), 1u << (8 + 3));
  // After an ESC reset (0x0040 'R', 'E', 'S', Section II 0x0040) the same.
  for (const char c : {'R', 'E', 'S'}) {
    transact(line.segment, Command::Apwr, ap(0, reg::kEscResetEcat), Data{static_cast<std::uint8_t>(c)});
  }
  EXPECT_EQ(esc.register_u16(reg::kConfiguredStationAddress), 0u);  // the reset happened
  for (unsigned n : {3u, 4u}) {
    r = transact(line.segment, Command::Aprd, ap(0, reg::sync_manager(n)), Data(8, 0xEE));
    EXPECT_EQ(r.wkc, 1);
    EXPECT_EQ(r.data, absent);  // SM 3 too: reset to control 0
  }
}

TEST(EscUnitCount, AMissingFmmuMapsNothing) {
  Line line(1, with_units(3, 4));
  assign_stations(line);
  config_fmmu(line.segment, kStation, 3, 0x00010000, 4, 0, 7, 0x1000, 0, kRead | kWrite);
  config_fmmu(line.segment, kStation, 15, 0x00010000, 4, 0, 7, 0x1000, 0, kRead | kWrite);
  auto r = transact(line.segment, Command::Fprd, fp(kStation, reg::fmmu(3)), Data(16, 0xEE));
  EXPECT_EQ(r.wkc, 1);
  EXPECT_EQ(r.data, Data(16, 0));
  r = transact(line.segment, Command::Lwr, 0x00010000, Data{1, 2, 3, 4});
  EXPECT_EQ(r.wkc, 0);
  r = transact(line.segment, Command::Lrd, 0x00010000, Data{7, 7, 7, 7});
  EXPECT_EQ(r.wkc, 0);
  EXPECT_EQ(r.data, (Data{7, 7, 7, 7}));
  EXPECT_EQ(line[0].register_u16(0x1000), 0u);
  // FMMU 2, the last one the ESC has, maps the same bytes.
  config_fmmu(line.segment, kStation, 2, 0x00010000, 4, 0, 7, 0x1000, 0, kRead | kWrite);
  r = transact(line.segment, Command::Lwr, 0x00010000, Data{1, 2, 3, 4});
  EXPECT_EQ(r.wkc, 1);
  r = transact(line.segment, Command::Lrd, 0x00010000, Data(4, 0));
  EXPECT_EQ(r.wkc, 1);
  EXPECT_EQ(r.data, (Data{1, 2, 3, 4}));
}

// The other end: 16 of each, the last SM behind the last FMMU, both directions.
TEST(EscUnitCount, SixteenUnitsWorkUpToTheLast) {
  Line line(1, with_units(16, 16));
  assign_stations(line);
  config_sm(line.segment, kStation, 15, 0x1800, 4, kControlBuffered);
  config_sm(line.segment, kStation, 14, 0x1900, 2, 0x20);  // 3-buffer, ECAT reads, AL event on
  config_fmmu(line.segment, kStation, 15, 0x00020000, 4, 0, 7, 0x1800, 0, kWrite);
  config_fmmu(line.segment, kStation, 14, 0x00020004, 2, 0, 7, 0x1900, 0, kRead);
  const std::array<std::uint8_t, 2> inputs{0x5A, 0xA5};
  line[0].write(0x1900, inputs);
  auto r = transact(line.segment, Command::Lrw, 0x00020000, Data{1, 2, 3, 4, 0, 0});
  EXPECT_EQ(r.wkc, 3);
  EXPECT_EQ(r.data, (Data{1, 2, 3, 4, 0x5A, 0xA5}));
  EXPECT_EQ(al_event(line[0]) & (1u << (8 + 15)), 1u << (8 + 15));
  std::array<std::uint8_t, 4> outputs{};
  line[0].read(0x1800, outputs);
  EXPECT_EQ(Data(outputs.begin(), outputs.end()), (Data{1, 2, 3, 4}));
}

// No FMMU and no SM at all (an ESC used for register access only).
TEST(EscUnitCount, NoUnitsAtAll) {
  Line line(1, with_units(0, 0));
  assign_stations(line);
  EXPECT_EQ(line[0].register_u16(reg::kFmmusSupported), 0u);
  config_sm(line.segment, kStation, 0, 0x1000, 4, kControlBuffered);
  config_fmmu(line.segment, kStation, 0, 0x00010000, 4, 0, 7, 0x1000, 0, kRead | kWrite);
  auto r = transact(line.segment, Command::Lrw, 0x00010000, Data{1, 2, 3, 4});
  EXPECT_EQ(r.wkc, 0);
  EXPECT_EQ(r.data, (Data{1, 2, 3, 4}));
  r = transact(line.segment, Command::Fpwr, fp(kStation, 0x1000), Data{1, 2});
  EXPECT_EQ(r.wkc, 1);
  EXPECT_EQ(line[0].register_u16(0x1000), 0x0201u);
}

}  // namespace
}  // namespace ecat::esc::test
