// The heap of a process that hosts many slaves, on 2 MiB pages (issue 16
// item 5: the cost per drive at 1000 drives within 1.2x of 100).
//
// Why: a servo keeps about 20 KiB of state on the heap (ESC object, CoE
// server, object store, drive), and every cycle touches a few lines on each
// of its ~6 pages. 100 drives touch ~600 pages, which the CPU's second-level
// TLB holds (1,536-3,072 entries on the x86 cores of 2017-2024); 1000 drives
// touch ~6,000, so nearly every access to a drive's state walks the page
// tables first. Measured on this project's CSP cycle: 1.3-2.3 us per drive
// at 1000 drives on 4 KiB pages against 0.8 us on 2 MiB pages, where 100
// drives cost 0.8-0.9 us either way (docs/performance.md, "Scale, part 7").
//
// How: Linux transparent huge pages (Documentation/admin-guide/mm/transhuge
// .rst). With the system setting "madvise" (as on the machines measured) only ranges
// marked MADV_HUGEPAGE get them. The heap ([heap], grown by brk) is marked
// and what it holds is collapsed at once with MADV_COLLAPSE (Linux 6.1+; on
// older kernels khugepaged collapses the marked range in the background).
// Contents are unchanged: the kernel copies the small pages into the huge
// one. Heap growth after the call is not marked (brk adds a mapping of its
// own): call it again after building more.
//
// When: after the slaves are built (ecat-slave does it after making its
// chain, before locking memory). It is process-wide, so a program that
// embeds the library calls it itself; nothing in the library calls it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

namespace ecat::slave {

// /sys/kernel/mm/transparent_hugepage/enabled: the bracketed word.
enum class HugePageMode { Always, Madvise, Never, Unknown };
HugePageMode parse_huge_page_mode(std::string_view sysfs_text) noexcept;

// An address range of /proc/self/maps: "start-end perms ...", hexadecimal.
struct AddressRange {
  std::uintptr_t start = 0;
  std::uintptr_t end = 0;
  std::size_t size() const noexcept { return end - start; }
  bool contains(const void* p) const noexcept {
    const auto a = reinterpret_cast<std::uintptr_t>(p);
    return a >= start && a < end;
  }
};
// The [heap] mappings of /proc/self/maps text, in order.
std::vector<AddressRange> heap_mappings(std::string_view maps_text);
// The heap in /proc/self/maps text: its [heap] lines, back to back, as one
// range; none when there is no [heap].
std::optional<AddressRange> find_heap(std::string_view maps_text);
// The AnonHugePages (kB) of the mappings inside `range` in /proc/self/smaps
// text, summed, in bytes.
std::size_t huge_bytes_in(std::string_view smaps_text, AddressRange range) noexcept;

struct HugePageReport {
  HugePageMode mode = HugePageMode::Unknown;
  std::optional<AddressRange> heap;  // at the time of the call
  std::size_t huge_bytes_before = 0;  // of the heap on 2 MiB pages
  std::size_t huge_bytes_after = 0;
  bool marked = false;     // MADV_HUGEPAGE took
  bool collapsed = false;  // MADV_COLLAPSE ran (the kernel has it)
  std::string note;        // why not, when something did not take; empty when all did
};

// Marks the heap MADV_HUGEPAGE and collapses it (see above). Never fails
// the caller: what did not take is in the report's note.
HugePageReport back_heap_with_huge_pages() noexcept;

}  // namespace ecat::slave
