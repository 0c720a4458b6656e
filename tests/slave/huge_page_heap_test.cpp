// The heap on 2 MiB pages (slave/huge_page_heap.hpp): the /proc and /sys
// texts it reads, exact; and on this machine, that backing the heap keeps
// every byte it holds.
#include "slave/huge_page_heap.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <memory>
#include <vector>

namespace ecat::slave {
namespace {

TEST(HugePageHeap, ParsesTheBracketedModeOfTheSysfsFile) {
  EXPECT_EQ(parse_huge_page_mode("always [madvise] never\n"), HugePageMode::Madvise);
  EXPECT_EQ(parse_huge_page_mode("[always] madvise never\n"), HugePageMode::Always);
  EXPECT_EQ(parse_huge_page_mode("always madvise [never]\n"), HugePageMode::Never);
  EXPECT_EQ(parse_huge_page_mode(""), HugePageMode::Unknown);
  EXPECT_EQ(parse_huge_page_mode("always madvise never\n"), HugePageMode::Unknown);
  EXPECT_EQ(parse_huge_page_mode("[sometimes]"), HugePageMode::Unknown);
}

constexpr const char* kMaps =
    "55de58f00000-55de58fe1000 r--p 00000000 fe:00 1234    /usr/bin/x\n"
    "55de58fe1000-55de5a507000 rw-p 00000000 00:00 0                          [heap]\n"
    "55de5a507000-55de5a513000 rw-p 00000000 00:00 0                          [heap]\n"
    "7f3634112000-7f3634c00000 rw-p 00000000 00:00 0 \n"
    "7ffe81f02000-7ffe81f23000 rw-p 00000000 00:00 0                          [stack]\n";

TEST(HugePageHeap, TakesTheHeapAsItsMappingsBackToBack) {
  const auto maps = heap_mappings(kMaps);
  ASSERT_EQ(maps.size(), 2u);
  EXPECT_EQ(maps[0].start, 0x55de58fe1000u);
  EXPECT_EQ(maps[1].end, 0x55de5a513000u);
  const auto heap = find_heap(kMaps);
  ASSERT_TRUE(heap.has_value());
  EXPECT_EQ(heap->start, 0x55de58fe1000u);
  EXPECT_EQ(heap->end, 0x55de5a513000u);
  EXPECT_EQ(heap->size(), 0x1532000u);
  EXPECT_FALSE(find_heap("7f3634112000-7f3634c00000 rw-p 00000000 00:00 0 \n").has_value());
  // A line that is not "start-end ..." is no mapping.
  EXPECT_FALSE(find_heap("zz-55de5a507000 rw-p 00000000 00:00 0 [heap]\n").has_value());
}

TEST(HugePageHeap, SumsTheHugePagesOfTheMappingsInsideTheRange) {
  constexpr const char* kSmaps =
      "55de58fe1000-55de5a507000 rw-p 00000000 00:00 0                          [heap]\n"
      "Size:              21656 kB\n"
      "AnonHugePages:     18432 kB\n"
      "55de5a507000-55de5a513000 rw-p 00000000 00:00 0                          [heap]\n"
      "Size:                 48 kB\n"
      "AnonHugePages:         0 kB\n"
      "7f3634000000-7f3634c00000 rw-p 00000000 00:00 0 \n"
      "AnonHugePages:      2048 kB\n";
  EXPECT_EQ(huge_bytes_in(kSmaps, AddressRange{0x55de58fe1000u, 0x55de5a513000u}), std::size_t{18432} * 1024);
  EXPECT_EQ(huge_bytes_in(kSmaps, AddressRange{0x7f3634000000u, 0x7f3634c00000u}), std::size_t{2048} * 1024);
  EXPECT_EQ(huge_bytes_in(kSmaps, AddressRange{0x1000u, 0x2000u}), 0u);
}

// 16 MiB in 1 KiB blocks, each filled with its own pattern, as a chain's
// slaves fill the heap; then the call; then every byte is checked.
TEST(HugePageHeap, BackingTheHeapKeepsEveryByteItHolds) {
  constexpr std::size_t kBlock = 1024;
  constexpr std::size_t kBlocks = 16 * 1024;
  std::vector<std::unique_ptr<std::uint8_t[]>> blocks;
  blocks.reserve(kBlocks);
  for (std::size_t i = 0; i < kBlocks; ++i) {
    blocks.push_back(std::make_unique<std::uint8_t[]>(kBlock));
    for (std::size_t k = 0; k < kBlock; ++k) blocks.back()[k] = static_cast<std::uint8_t>(i * 31 + k);
  }
  const HugePageReport r = back_heap_with_huge_pages();
  if (r.mode == HugePageMode::Never || r.mode == HugePageMode::Unknown) GTEST_SKIP() << r.note;
  ASSERT_TRUE(r.heap.has_value()) << r.note;
  if (!r.heap->contains(blocks[kBlocks / 2].get())) {
    GTEST_SKIP() << "the allocator keeps these blocks outside [heap] (a sanitizer's allocator does)";
  }
  EXPECT_TRUE(r.marked) << r.note;
  if (r.collapsed) {
    // 16 MiB of blocks: at least 6 whole aligned 2 MiB pages, whatever the heap's start.
    EXPECT_GE(r.huge_bytes_after, std::size_t{6} << 20);
    EXPECT_TRUE(r.note.empty()) << r.note;
  } else {
    EXPECT_FALSE(r.note.empty());
  }
  std::size_t wrong = 0;
  for (std::size_t i = 0; i < kBlocks; ++i) {
    for (std::size_t k = 0; k < kBlock; ++k) wrong += blocks[i][k] != static_cast<std::uint8_t>(i * 31 + k);
  }
  EXPECT_EQ(wrong, 0u);
  // A second call finds the pages it made and keeps them.
  const HugePageReport again = back_heap_with_huge_pages();
  if (r.collapsed) {
    EXPECT_GE(again.huge_bytes_before, r.huge_bytes_after);
  }
}

}  // namespace
}  // namespace ecat::slave
