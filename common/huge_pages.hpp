// The heap on 2 MiB pages once a process has built what it runs (issue 30
// item 1). A chain of 1000 drives touches about 100 cache lines per drive
// and cycle, spread over some 5,000 pages of heap and 3,000 of ESC memory
// when the pages are 4 KiB - more than a core's second-level TLB holds - so
// a cycle pays page walks on top of its cache misses. With the heap on huge
// pages the 1000-drive CSP cycle took 0.96x its CPU time (15 alternating
// rounds on a 2-vCPU AMD EPYC, 0.83..1.16) at the same resident size
// (docs/performance-log.md "Session 19: the heap on huge pages").
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>

#include "common/expected.hpp"

namespace ecat {

// A transparent huge page on x86-64 (and on AArch64 with 4 KiB base pages).
inline constexpr std::uintptr_t kHugePageBytes = std::uintptr_t{2} << 20;

// The whole huge pages inside [begin, end): begin rounded up, end rounded
// down to kHugePageBytes; an empty range (begin == end) when none fits.
struct AddressRange {
  std::uintptr_t begin = 0;
  std::uintptr_t end = 0;
  std::size_t size() const noexcept { return end - begin; }
};
constexpr AddressRange whole_huge_pages(AddressRange r) noexcept {
  const std::uintptr_t begin = (r.begin + kHugePageBytes - 1) & ~(kHugePageBytes - 1);
  const std::uintptr_t end = r.end & ~(kHugePageBytes - 1);
  return end > begin ? AddressRange{begin, end} : AddressRange{begin, begin};
}

// The heap of this process ([heap] of /proc/self/maps, brk's), an empty
// range when it has none.
Expected<AddressRange, std::string> heap_range();

struct HugePageAdvice {
  AddressRange advised;       // whole 2 MiB pages of the heap advised (empty: none)
  bool collapsed = false;     // the kernel collapsed them at once (MADV_COLLAPSE, Linux 6.1+)
};

// Advises the kernel to back the whole 2 MiB pages inside the heap
// ([heap] of /proc/self/maps) with transparent huge pages (MADV_HUGEPAGE)
// and, where it can, collapses them now (MADV_COLLAPSE); the partial pages
// at either end stay as they are, so the resident size grows only by the
// unused 4 KiB pages inside whole ones. Call once, after set-up: the heap
// grown afterwards is not advised. Nothing to do (advised empty) when the heap
// holds no whole 2 MiB page or the kernel has no transparent huge pages; with
// them switched off ("never") the advice is given and has no effect. An error
// only when /proc/self/maps cannot be read or madvise refuses.
Expected<HugePageAdvice, std::string> advise_heap_huge_pages();

}  // namespace ecat
