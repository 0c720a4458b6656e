// Issue 16 item 5: an ESC stores its registers 0x0000-0x0FFF and its
// configured process RAM, nothing more. Addresses beyond the RAM answer as
// on silicon - "not present" (Section II 0x0006 RAM size; ETG.1000.4 §5.4.3:
// only accessible memory counts for the WKC): a read leaves the frame's data
// untouched and does not count, a write changes nothing and does not count,
// from either side and through an FMMU as well.
#include <gtest/gtest.h>

#include "esc_fixture.hpp"

namespace ecat::esc::test {
namespace {

constexpr std::uint32_t kOneKiB = 1024;
constexpr std::uint16_t kStation = 0x1001;

EscConfig config_with_ram(std::uint32_t bytes) {
  EscConfig c = make_config();
  c.process_ram_size = bytes;
  return c;
}

TEST(EscMemorySize, BacksRegistersAndConfiguredRamOnly) {
  Line small(1, config_with_ram(kOneKiB));
  EXPECT_EQ(small[0].memory_size(), reg::kProcessRam + kOneKiB);
  Line standard(1);  // ET1100 default: 8 KiB
  EXPECT_EQ(standard[0].memory_size(), reg::kProcessRam + 8 * kOneKiB);
  Line largest(1, config_with_ram(kMaxProcessRam + kOneKiB));  // clamped to 60 KiB
  EXPECT_EQ(largest[0].memory_size(), kAddressSpace);
  EXPECT_EQ(largest[0].memory()[reg::kRamSize], 60u);  // 0x0006: RAM size in KiB
}

// EscConfig::memory_colour: the block starts colour x 64 bytes into its
// (page-aligned) mapping, colours taken modulo 8, and the mapping has the
// same size whatever the colour; the memory behaves the same (zero at
// power-on, registers and RAM as without a colour).
TEST(EscMemorySize, ColourOffsetsTheBlockByCacheLines) {
  constexpr std::uintptr_t kPage = 4096;
  for (unsigned colour : {0u, 1u, 3u, 7u, 8u, 13u}) {
    EscConfig c = make_config();
    c.memory_colour = static_cast<std::uint8_t>(colour);
    Line line(1, c);
    const auto at = reinterpret_cast<std::uintptr_t>(line[0].memory());
    EXPECT_EQ(at % kPage, 64u * (colour % 8u)) << colour;
    EXPECT_EQ(line[0].memory_size(), reg::kProcessRam + 8 * kOneKiB);
    // Every colour maps the same bytes: the block and room for colour 7.
    EXPECT_EQ(line[0].memory_mapped(), reg::kProcessRam + 8 * kOneKiB + 7 * 64) << colour;
    assign_stations(line);
    const auto last = static_cast<std::uint16_t>(line[0].memory_size() - 2);
    EXPECT_EQ(transact(line.segment, Command::Fpwr, fp(kStation, last), Data{0x12, 0x34}).wkc, 1);
    EXPECT_EQ(transact(line.segment, Command::Fprd, fp(kStation, last), Data{0, 0}).data, (Data{0x12, 0x34}));
    EXPECT_EQ(transact(line.segment, Command::Fprd, fp(kStation, reg::kProcessRam), Data{0xFF}).data, (Data{0}));
  }
}

TEST(EscMemorySize, EcatAccessPastTheRamIsNotPresent) {
  Line line(1, config_with_ram(kOneKiB));
  assign_stations(line);
  const auto end = static_cast<std::uint16_t>(reg::kProcessRam + kOneKiB);
  // Read past the end: data untouched, WKC 0.
  auto r = transact(line.segment, Command::Fprd, fp(kStation, end), Data{0xA5, 0x5A});
  EXPECT_EQ(r.wkc, 0);
  EXPECT_EQ(r.data, (Data{0xA5, 0x5A}));
  r = transact(line.segment, Command::Fprd, fp(kStation, 0xFFFE), Data{0x11, 0x22});
  EXPECT_EQ(r.wkc, 0);
  EXPECT_EQ(r.data, (Data{0x11, 0x22}));
  // Write past the end: not counted, and a read finds nothing there.
  r = transact(line.segment, Command::Fpwr, fp(kStation, 0xF000), Data{1, 2, 3, 4});
  EXPECT_EQ(r.wkc, 0);
  // A write across the end stores the bytes inside the RAM and counts once.
  r = transact(line.segment, Command::Fpwr, fp(kStation, static_cast<std::uint16_t>(end - 2)), Data{7, 8, 9, 10});
  EXPECT_EQ(r.wkc, 1);
  r = transact(line.segment, Command::Fprd, fp(kStation, static_cast<std::uint16_t>(end - 2)), Data{0, 0, 0xEE, 0xEE});
  EXPECT_EQ(r.wkc, 1);
  EXPECT_EQ(r.data, (Data{7, 8, 0xEE, 0xEE}));
  // A broadcast read over the end ORs only the bytes that exist.
  r = transact(line.segment, Command::Brd, device_address(0, static_cast<std::uint16_t>(end - 1)), Data{0, 0x40});
  EXPECT_EQ(r.wkc, 1);
  EXPECT_EQ(r.data, (Data{8, 0x40}));
  EXPECT_EQ(line[0].register_u16(static_cast<std::uint16_t>(end - 1)), 8u);  // the missing byte reads 0
}

TEST(EscMemorySize, PdiAccessPastTheRamReadsZero) {
  Line line(1, config_with_ram(kOneKiB));
  const auto end = static_cast<std::uint16_t>(reg::kProcessRam + kOneKiB);
  line[0].write(static_cast<std::uint16_t>(end - 1), Data{0x33, 0x44});
  Data out{0xFF, 0xFF, 0xFF};
  line[0].read(static_cast<std::uint16_t>(end - 1), out);
  EXPECT_EQ(out, (Data{0x33, 0x00, 0x00}));
  Data top{0xFF, 0xFF};
  line[0].read(0xFFFE, top);
  EXPECT_EQ(top, (Data{0x00, 0x00}));
}

TEST(EscMemorySize, FmmuOntoAbsentRamDoesNotCount) {
  Line line(1, config_with_ram(kOneKiB));
  assign_stations(line);
  constexpr std::uint32_t kLogical = 0x10000;
  const auto end = static_cast<std::uint16_t>(reg::kProcessRam + kOneKiB);
  // FMMU 0: 4 logical bytes onto the last 2 RAM bytes and 2 absent ones, read/write.
  config_fmmu(line.segment, kStation, 0, kLogical, 4, 0, 7, static_cast<std::uint16_t>(end - 2), 0,
              fmmu_reg::kTypeRead | fmmu_reg::kTypeWrite);
  // FMMU 1: wholly past the RAM, read.
  config_fmmu(line.segment, kStation, 1, kLogical + 0x100, 2, 0, 7, 0x8000, 0, fmmu_reg::kTypeRead);
  auto r = transact(line.segment, Command::Lwr, kLogical, Data{1, 2, 3, 4});
  EXPECT_EQ(r.wkc, 1);
  r = transact(line.segment, Command::Lrd, kLogical, Data{0xC0, 0xC1, 0xC2, 0xC3});
  EXPECT_EQ(r.wkc, 1);
  EXPECT_EQ(r.data, (Data{1, 2, 0xC2, 0xC3}));  // absent bytes: frame data untouched
  r = transact(line.segment, Command::Lrd, kLogical + 0x100, Data{0x5A, 0xA5});
  EXPECT_EQ(r.wkc, 0);
  EXPECT_EQ(r.data, (Data{0x5A, 0xA5}));
  // Bit-granular write onto an absent byte: nothing stored, not counted.
  config_fmmu(line.segment, kStation, 2, kLogical + 0x200, 1, 2, 5, 0x9000, 2, fmmu_reg::kTypeWrite);
  r = transact(line.segment, Command::Lwr, kLogical + 0x200, Data{0xFF});
  EXPECT_EQ(r.wkc, 0);
}

TEST(EscMemorySize, ResetClearsTheRamWithoutTouchingBeyond) {
  Line line(1, config_with_ram(2 * kOneKiB));
  const auto last = static_cast<std::uint16_t>(reg::kProcessRam + 2 * kOneKiB - 1);
  line[0].write(last, Data{0x99});
  EXPECT_EQ(line[0].memory()[last], 0x99);
  line[0].reset();
  EXPECT_EQ(line[0].memory()[last], 0x00);
  EXPECT_EQ(line[0].memory()[reg::kRamSize], 2u);
}

}  // namespace
}  // namespace ecat::esc::test
