#include "common/huge_pages.hpp"

#include <sys/mman.h>

#include <cerrno>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <cstring>

#include <fmt/format.h>

namespace ecat {
namespace {

// madvise(2) MADV_COLLAPSE (Linux 6.1, uapi asm-generic/mman-common.h),
// which glibc 2.36's <sys/mman.h> does not name yet.
#ifdef MADV_COLLAPSE
constexpr int kMadvCollapse = MADV_COLLAPSE;
#else
constexpr int kMadvCollapse = 25;
#endif

}  // namespace

Expected<AddressRange, std::string> heap_range() {
  std::FILE* f = std::fopen("/proc/self/maps", "r");
  if (f == nullptr) return fail(fmt::format("/proc/self/maps: {}", std::strerror(errno)));
  AddressRange heap;
  char line[512];
  while (std::fgets(line, sizeof line, f) != nullptr) {
    if (std::strstr(line, "[heap]") == nullptr) continue;
    std::uintmax_t b = 0;
    std::uintmax_t e = 0;
    if (std::sscanf(line, "%" SCNxMAX "-%" SCNxMAX, &b, &e) == 2) {
      heap = {static_cast<std::uintptr_t>(b), static_cast<std::uintptr_t>(e)};
    }
    break;
  }
  std::fclose(f);
  return heap;
}

Expected<HugePageAdvice, std::string> advise_heap_huge_pages() {
  auto heap = heap_range();
  if (!heap) return fail(heap.error());
  const AddressRange whole = whole_huge_pages(*heap);
  HugePageAdvice a;
  if (whole.size() == 0) return a;
  void* p = reinterpret_cast<void*>(whole.begin);
  const std::size_t length = whole.size();
  if (::madvise(p, length, MADV_HUGEPAGE) != 0) {
    if (errno == EINVAL) return a;  // a kernel without transparent huge pages
    return fail(fmt::format("madvise(MADV_HUGEPAGE) of {} bytes of heap: {}", length, std::strerror(errno)));
  }
  a.advised = whole;
  // Synchronous where the kernel can (else khugepaged collapses them in its
  // own time); EINVAL from a kernel before 6.1, EAGAIN/ENOMEM when no huge
  // page was free: the advice stands either way.
  a.collapsed = ::madvise(p, length, kMadvCollapse) == 0;
  return a;
}

}  // namespace ecat
