#include "esi/esi_reader_axes.hpp"

#include <fmt/format.h>

#include <cstdint>
#include <vector>

namespace ecat::esi {
namespace {

// CiA 402-1 §6: at most eight logical devices (axes) in one device.
constexpr unsigned kMaxAxes = 8;
constexpr std::uint16_t kControlword = 0x6040;  // CiA 402-2: every axis has both
constexpr std::uint16_t kStatusword = 0x6041;
// RxPDO 1600h-17FFh, TxPDO 1A00h-1BFFh (ETG.1000.6 §5.6.7.4.7/8).
constexpr std::uint32_t kPdoAreaSize = 0x200;

// The lowest index of a PDO in `list` that maps an object of `axis`.
std::optional<std::uint16_t> first_pdo_of_axis(const std::vector<od::Pdo>& list, const od::AxisLayout& l,
                                               unsigned axis) {
  std::optional<std::uint16_t> first;
  for (const od::Pdo& p : list) {
    for (const od::PdoEntry& e : p.entries) {
      bool of_axis = false;
      for (const od::AxisRange& r : l.ranges) {
        const std::uint32_t lo = r.first + (axis - 1) * std::uint32_t{l.index_offset};
        const std::uint32_t hi = r.last + (axis - 1) * std::uint32_t{l.index_offset};
        of_axis = of_axis || (e.index >= lo && e.index <= hi);
      }
      if (of_axis && (!first || p.index < *first)) first = p.index;
    }
  }
  return first;
}

const od::Pdo* find_pdo(const std::vector<od::Pdo>& list, std::uint16_t index) {
  for (const od::Pdo& p : list) {
    if (p.index == index) return &p;
  }
  return nullptr;
}

}  // namespace

std::optional<std::string> recover_axes(od::DeviceDescription& d) {
  if (!d.drive || d.modular) return std::nullopt;
  od::AxisLayout l;  // CiA 402-1 §6: +800h per axis, 6000h-67FFh per axis
  unsigned axes = 1;
  while (axes < kMaxAxes) {
    const auto offset = static_cast<std::uint16_t>(axes * l.index_offset);
    if (!d.dictionary.find(kControlword + offset) || !d.dictionary.find(kStatusword + offset)) break;
    ++axes;
  }
  if (axes == 1) return std::nullopt;
  l.axes = axes;
  const std::string head = fmt::format("{} CiA 402 axes (6040h/6041h at +800h steps)", axes);
  // Every per-axis object of axis 1 has its copy on every axis: the loader
  // would otherwise add objects the device does not have.
  for (const od::Object& o : d.dictionary.objects()) {
    if (!l.per_axis(o.index)) continue;
    for (unsigned axis = 2; axis <= axes; ++axis) {
      if (!d.dictionary.find(l.object_index(axis, o.index))) {
        return fmt::format("{}, but axis {} has no {:04X}h (axis 1's {:04X}h); the twin runs axis 1's state "
                           "machine only", head, axis, l.object_index(axis, o.index), o.index);
      }
    }
  }
  // The PDO offset: where axis 2's first PDO lies against axis 1's, the same
  // for both directions that map axis objects.
  std::optional<std::uint16_t> offset;
  for (const auto* list : {&d.rx_pdos, &d.tx_pdos}) {
    const auto a1 = first_pdo_of_axis(*list, l, 1);
    const auto a2 = first_pdo_of_axis(*list, l, 2);
    if (!a1 && !a2) continue;
    if (!a1 || !a2 || *a2 <= *a1 || (offset && *offset != *a2 - *a1)) {
      return fmt::format("{}, but their PDOs lie at no one offset from axis 1's; the twin runs axis 1's state machine "
                         "only", head);
    }
    offset = static_cast<std::uint16_t>(*a2 - *a1);
  }
  if (offset) l.pdo_offset = *offset;
  if (std::uint32_t{axes} * l.pdo_offset > kPdoAreaSize) {
    return fmt::format("{}, but {} axes' PDOs {:#x} apart do not fit 1600h-17FFh; the twin runs axis 1's state "
                       "machine only", head, axes, l.pdo_offset);
  }
  // Every per-axis PDO of axis 1 has its copy on every axis (the loader
  // would otherwise add PDOs the SII does not list).
  for (const auto* list : {&d.rx_pdos, &d.tx_pdos}) {
    for (const od::Pdo& p : *list) {
      if (!l.per_axis_pdo(p.index)) continue;
      for (unsigned axis = 2; axis <= axes; ++axis) {
        if (!find_pdo(*list, l.pdo_index(axis, p.index))) {
          return fmt::format("{}, but axis {} has no PDO {:04X}h (axis 1's {:04X}h at +{:#x}); the twin runs axis 1's "
                             "state machine only", head, axis, l.pdo_index(axis, p.index), p.index, l.pdo_offset);
        }
      }
    }
  }
  d.drive->axes = l;
  return std::nullopt;
}

}  // namespace ecat::esi
