#include "slave/huge_page_heap.hpp"

#include <sys/mman.h>

#include <cerrno>
#include <charconv>
#include <cstring>
#include <fstream>
#include <iterator>
#include <vector>

#include <fmt/format.h>

namespace ecat::slave {
namespace {

#ifndef MADV_COLLAPSE
// Linux 6.1 include/uapi/asm-generic/mman-common.h, for older headers.
constexpr int MADV_COLLAPSE = 25;
#endif

constexpr std::uintptr_t kHugePage = std::uintptr_t{2} << 20;  // x86-64 PMD page
constexpr std::size_t kKib = 1024;
constexpr const char* kModeFile = "/sys/kernel/mm/transparent_hugepage/enabled";

std::string read_file(const char* path) {
  std::ifstream in(path);
  return {std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
}

std::optional<std::uintptr_t> parse_hex(std::string_view s) noexcept {
  std::uintptr_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v, 16);
  if (ec != std::errc{} || end != s.data() + s.size()) return std::nullopt;
  return v;
}

// "start-end ..." at the head of a maps/smaps line.
std::optional<AddressRange> parse_range(std::string_view line) noexcept {
  const auto dash = line.find('-');
  const auto space = line.find(' ');
  if (dash == std::string_view::npos || space == std::string_view::npos || dash > space) return std::nullopt;
  const auto a = parse_hex(line.substr(0, dash));
  const auto b = parse_hex(line.substr(dash + 1, space - dash - 1));
  if (!a || !b || *b < *a) return std::nullopt;
  return AddressRange{*a, *b};
}

template <typename F>
void for_each_line(std::string_view text, F f) {
  while (!text.empty()) {
    const auto nl = text.find('\n');
    f(text.substr(0, nl));
    if (nl == std::string_view::npos) break;
    text.remove_prefix(nl + 1);
  }
}

}  // namespace

HugePageMode parse_huge_page_mode(std::string_view text) noexcept {
  const auto open = text.find('[');
  const auto close = text.find(']', open);
  if (open == std::string_view::npos || close == std::string_view::npos) return HugePageMode::Unknown;
  const std::string_view word = text.substr(open + 1, close - open - 1);
  if (word == "always") return HugePageMode::Always;
  if (word == "madvise") return HugePageMode::Madvise;
  if (word == "never") return HugePageMode::Never;
  return HugePageMode::Unknown;
}

std::vector<AddressRange> heap_mappings(std::string_view maps_text) {
  std::vector<AddressRange> maps;
  for_each_line(maps_text, [&](std::string_view line) {
    if (!line.ends_with("[heap]")) return;
    if (const auto r = parse_range(line)) maps.push_back(*r);
  });
  return maps;
}

std::optional<AddressRange> find_heap(std::string_view maps_text) {
  // The heap is one mapping until part of it gets other flags (a madvise
  // on part of it, or brk growth after one): then it is several, back to back.
  std::optional<AddressRange> heap;
  for (const AddressRange& r : heap_mappings(maps_text)) {
    if (!heap) {
      heap = r;
    } else if (r.start == heap->end) {
      heap->end = r.end;
    }
  }
  return heap;
}

std::size_t huge_bytes_in(std::string_view smaps_text, AddressRange range) noexcept {
  constexpr std::string_view kField = "AnonHugePages:";
  bool inside = false;
  std::size_t bytes = 0;
  for_each_line(smaps_text, [&](std::string_view line) {
    if (const auto r = parse_range(line)) {
      inside = r->start >= range.start && r->end <= range.end;
      return;
    }
    if (!inside || !line.starts_with(kField)) return;
    std::string_view v = line.substr(kField.size());
    while (!v.empty() && v.front() == ' ') v.remove_prefix(1);
    std::size_t kib = 0;
    const auto [end, ec] = std::from_chars(v.data(), v.data() + v.size(), kib);
    if (ec == std::errc{} && std::string_view(end, static_cast<std::size_t>(v.data() + v.size() - end)) == " kB") {
      bytes += kib * kKib;
    }
  });
  return bytes;
}

HugePageReport back_heap_with_huge_pages() noexcept {
  HugePageReport r;
  try {
    r.mode = parse_huge_page_mode(read_file(kModeFile));
    if (r.mode == HugePageMode::Never || r.mode == HugePageMode::Unknown) {
      r.note = fmt::format("transparent huge pages are off ({}: {})", kModeFile,
                           r.mode == HugePageMode::Never ? "never" : "not readable");
      return r;
    }
    r.heap = find_heap(read_file("/proc/self/maps"));
    if (!r.heap) {
      r.note = "no [heap] in /proc/self/maps (the allocator does not use brk)";
      return r;
    }
    r.huge_bytes_before = huge_bytes_in(read_file("/proc/self/smaps"), *r.heap);
    // Marked now: the heap as it is. brk growth after this is a new mapping
    // without the mark (the kernel merges only equal flags), so a later
    // call marks and collapses that too.
    auto* base = reinterpret_cast<void*>(r.heap->start);
    if (madvise(base, r.heap->size(), MADV_HUGEPAGE) == 0) {
      r.marked = true;
    } else {
      r.note = fmt::format("MADV_HUGEPAGE: {}", std::strerror(errno));
      return r;
    }
    // Collapsed mapping by mapping: a 2 MiB page cannot span two (the heap
    // is several when parts had other flags), and the kernel refuses the
    // whole call (EINVAL) for a mapping that holds no aligned 2 MiB page.
    const std::vector<AddressRange> maps = heap_mappings(read_file("/proc/self/maps"));
    std::size_t whole = 0;
    int error = 0;
    for (const AddressRange& m : maps) {
      const std::uintptr_t first = (m.start + kHugePage - 1) & ~(kHugePage - 1);
      const std::uintptr_t last = m.end & ~(kHugePage - 1);
      if (last <= first) continue;
      whole += last - first;
      if (madvise(reinterpret_cast<void*>(first), last - first, MADV_COLLAPSE) != 0 && error == 0) error = errno;
    }
    r.collapsed = whole > 0 && error == 0;
    if (whole == 0) {
      r.note = "the heap holds no whole 2 MiB page yet";
    } else if (error == EINVAL) {
      r.note = "MADV_COLLAPSE not supported (Linux before 6.1): khugepaged collapses the heap in the background";
    } else if (error != 0) {
      // EAGAIN/ENOMEM: no free 2 MiB page now; what could be collapsed was.
      r.note = fmt::format("MADV_COLLAPSE: {}", std::strerror(error));
    }
    r.huge_bytes_after = huge_bytes_in(read_file("/proc/self/smaps"), *r.heap);
  } catch (...) {
    r.note = "out of memory while reading /proc";
  }
  return r;
}

}  // namespace ecat::slave
