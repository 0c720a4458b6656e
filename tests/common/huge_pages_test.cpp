#include "common/huge_pages.hpp"

#include <cstdint>
#include <fstream>
#include <memory>
#include <regex>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace ecat {
namespace {

constexpr std::uintptr_t kMiB = std::uintptr_t{1} << 20;

TEST(WholeHugePages, RoundsTheBeginUpAndTheEndDown) {
  const AddressRange r = whole_huge_pages({0x55a0'0000'1000, 0x55a0'0060'0000 + 0x345});
  EXPECT_EQ(r.begin, 0x55a0'0020'0000u);
  EXPECT_EQ(r.end, 0x55a0'0060'0000u);
  EXPECT_EQ(r.size(), 4 * kMiB);
}

TEST(WholeHugePages, AnAlignedRangeIsKept) {
  const AddressRange r = whole_huge_pages({0x40'0000, 0xA0'0000});
  EXPECT_EQ(r.begin, 0x40'0000u);
  EXPECT_EQ(r.end, 0xA0'0000u);
}

TEST(WholeHugePages, NoWholePageGivesAnEmptyRange) {
  // Less than 2 MiB, and 2 MiB that straddle a boundary.
  EXPECT_EQ(whole_huge_pages({0x20'0000, 0x3F'FFFF}).size(), 0u);
  EXPECT_EQ(whole_huge_pages({0x10'0000, 0x30'0000}).size(), 0u);
  EXPECT_EQ(whole_huge_pages({0x1F'F000, 0x20'0000}).size(), 0u);
  EXPECT_EQ(whole_huge_pages({0, 0}).size(), 0u);
}

// What /proc/self/smaps says of the mapping that starts at `begin` ("" when none does).
std::string smaps_field(std::uintptr_t begin, const std::string& field) {
  std::ifstream smaps("/proc/self/smaps");
  const std::regex mapping("^([0-9a-f]+)-[0-9a-f]+ ");
  bool in = false;
  for (std::string line; std::getline(smaps, line);) {
    if (std::smatch m; std::regex_search(line, m, mapping)) {
      in = std::stoull(m[1].str(), nullptr, 16) == begin;
    } else if (in && line.rfind(field + ":", 0) == 0) {
      return line.substr(field.size() + 1);
    }
  }
  return {};
}

bool thp_mode_is(const char* mode) {
  std::ifstream f("/sys/kernel/mm/transparent_hugepage/enabled");
  std::string modes;
  std::getline(f, modes);
  return modes.find(std::string("[") + mode + "]") != std::string::npos;
}

// Allocations of 64 KiB (below glibc's mmap threshold: they come from brk's
// heap) adding up to 8 MiB, each filled with its own pattern.
struct HeapFill {
  static constexpr std::size_t kChunk = 64 * 1024;
  static constexpr std::size_t kChunks = 128;
  std::vector<std::unique_ptr<std::uint8_t[]>> chunks;
  HeapFill() {
    for (std::size_t i = 0; i < kChunks; ++i) {
      chunks.push_back(std::make_unique<std::uint8_t[]>(kChunk));
      for (std::size_t k = 0; k < kChunk; k += 512) chunks.back()[k] = static_cast<std::uint8_t>(i * 7 + k / 512);
    }
  }
  bool intact() const {
    for (std::size_t i = 0; i < kChunks; ++i) {
      for (std::size_t k = 0; k < kChunk; k += 512) {
        if (chunks[i][k] != static_cast<std::uint8_t>(i * 7 + k / 512)) return false;
      }
    }
    return true;
  }
  bool on(AddressRange heap) const {
    const auto a = reinterpret_cast<std::uintptr_t>(chunks.back().get());
    return a >= heap.begin && a < heap.end;
  }
};

TEST(AdviseHeapHugePages, AdvisesTheWholePagesOfTheHeapAndKeepsItsBytes) {
  HeapFill fill;
  const auto heap = heap_range();
  ASSERT_TRUE(heap) << heap.error();
  if (!fill.on(*heap)) GTEST_SKIP() << "malloc does not allocate from brk's [heap] here (a sanitizer's allocator)";
  // In "madvise" mode the heap is not eligible before the advice.
  const bool madvise_mode = thp_mode_is("madvise");
  if (madvise_mode) {
    EXPECT_NE(smaps_field(heap->begin, "THPeligible").find('0'), std::string::npos);
  }
  const auto advice = advise_heap_huge_pages();
  ASSERT_TRUE(advice) << advice.error();
  const AddressRange whole = whole_huge_pages({heap->begin, heap->end});
  EXPECT_EQ(advice->advised.begin, whole.begin);
  EXPECT_EQ(advice->advised.end, whole.end);
  EXPECT_GE(advice->advised.size(), 2 * kHugePageBytes);  // 8 MiB of heap hold at least 3 whole pages
  EXPECT_TRUE(fill.intact());
  if (!madvise_mode && !thp_mode_is("always")) GTEST_SKIP() << "transparent huge pages are off on this host";
  // The advised part is a mapping of its own, eligible for huge pages.
  const std::string eligible = smaps_field(advice->advised.begin, "THPeligible");
  EXPECT_NE(eligible.find('1'), std::string::npos) << "THPeligible:" << eligible;
}

}  // namespace
}  // namespace ecat
