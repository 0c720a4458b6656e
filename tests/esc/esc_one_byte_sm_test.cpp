// A 1-byte process-data SM (SOES's raspberry_lan9252demo: SM2 at 1100h, 1
// byte, control 24h = 3-buffer, ECAT writes, AL event, no watchdog trigger;
// six 1-bit LEDs and 2 bits of padding). ESC datasheet Section II 0x0802:
// the length "shall be greater 1, otherwise SyncManager is not activated. If
// set to 1, only Watchdog Trigger is generated if available"
// (shared/spec/esc-registers.md §7, B-II p.68). So an ECAT write to that byte
// - FPWR, a byte FMMU or a bit-granular FMMU - writes plain RAM: no buffer,
// no AL event bit 8+2, no write event in 0x0805; with control bit 6 the
// process-data watchdog restarts (esc_watchdog_test.cpp). A 2-byte SM2 with
// the same control byte raises both. This is why that sample never sees its
// SM2 event through the PDI host (docs/pdi-host.md).
#include <gtest/gtest.h>

#include "esc/register_bits.hpp"
#include "esc_fixture.hpp"

namespace ecat::esc::test {
namespace {

constexpr std::uint16_t kStation = 0x1001;
constexpr std::uint16_t kOutputs = 0x1100;
constexpr std::uint32_t kLogical = 0x00010000;
constexpr std::uint8_t kFmmuWrite = 2;
constexpr std::uint8_t kFmmuRead = 1;
constexpr std::uint8_t kSoesOutputsControl = 0x24;  // SOES slave.xml: 3-buffer, write, AL event
constexpr std::uint32_t kSm2AlEvent = 1u << (bits::kAlEventSmShift + 2);

struct OneByteSmTest : ::testing::Test {
  OneByteSmTest() : line(1) { assign_stations(line); }
  Line line;
  Esc& esc() { return line[0]; }
  Segment& seg() { return line.segment; }
  std::uint8_t sm2_status() { return esc().memory()[reg::sync_manager(2) + reg::sm::kStatus]; }
  std::uint32_t al_event() { return esc().memory()[reg::kAlEventRequest] | esc().memory()[reg::kAlEventRequest + 1] << 8u; }
};

TEST_F(OneByteSmTest, BitGranularLrwIntoOneByteSmWritesRamAndRaisesNoEvent) {
  config_sm(seg(), kStation, 2, kOutputs, 1, kSoesOutputsControl);
  // The six LED bits (logical 0x10000.0-.5) onto 1100h.0-.5, and the inputs
  // byte read from 1180h right behind, as a bit-packing master maps them.
  config_fmmu(seg(), kStation, 0, kLogical, 1, 0, 5, kOutputs, 0, kFmmuWrite);
  config_fmmu(seg(), kStation, 1, kLogical + 1, 1, 0, 7, 0x1180, 0, kFmmuRead);
  const std::uint32_t before = al_event();
  auto r = transact(seg(), Command::Lrw, kLogical, Data{0xFF, 0x00});
  EXPECT_EQ(r.wkc, 3);
  EXPECT_EQ(esc().memory()[kOutputs], 0x3F);           // in place: no buffer redirection
  EXPECT_EQ(al_event(), before);                        // no SM2 AL event
  EXPECT_EQ(al_event() & kSm2AlEvent, 0u);
  EXPECT_EQ(sm2_status() & sm_bits::kStatusWriteEvent, 0);
  EXPECT_EQ(esc().memory()[reg::kWatchdogStatusProcessData], 1);  // never triggered, not expired
  // The PDI reads the byte as RAM, whatever was written last.
  Data got(1);
  esc().read(kOutputs, got);
  EXPECT_EQ(got, Data{0x3F});
}

TEST_F(OneByteSmTest, ByteFmmuIntoOneByteSmRaisesNoEvent) {
  config_sm(seg(), kStation, 2, kOutputs, 1, kSoesOutputsControl);
  config_fmmu(seg(), kStation, 0, kLogical, 1, 0, 7, kOutputs, 0, kFmmuWrite);
  EXPECT_EQ(transact(seg(), Command::Lwr, kLogical, Data{0x15}).wkc, 1);
  EXPECT_EQ(esc().memory()[kOutputs], 0x15);
  EXPECT_EQ(al_event() & kSm2AlEvent, 0u);
  EXPECT_EQ(sm2_status() & sm_bits::kStatusWriteEvent, 0);
}

TEST_F(OneByteSmTest, TwoByteSmWithTheSameControlRaisesTheEvent) {
  config_sm(seg(), kStation, 2, kOutputs, 2, kSoesOutputsControl);
  config_fmmu(seg(), kStation, 0, kLogical, 2, 0, 7, kOutputs, 0, kFmmuWrite);
  EXPECT_EQ(transact(seg(), Command::Lwr, kLogical, Data{0x15, 0x00}).wkc, 1);
  EXPECT_EQ(al_event() & kSm2AlEvent, kSm2AlEvent);
  EXPECT_EQ(sm2_status() & sm_bits::kStatusWriteEvent, sm_bits::kStatusWriteEvent);
  // The PDI reads the buffer: the event is acknowledged.
  Data got(2);
  esc().read(kOutputs, got);
  EXPECT_EQ(got, (Data{0x15, 0x00}));
  EXPECT_EQ(al_event() & kSm2AlEvent, 0u);
}

}  // namespace
}  // namespace ecat::esc::test
