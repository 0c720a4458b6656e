// Several CiA 402 axes in one device (docs/device-format.md "Several axes"):
// <Drive axes="N"> gives each axis 2..N a copy of every axis-1 object in the
// per-axis ranges (CiA 402-1 §6: +800h per axis, with the exceptions the
// file lists) and of every per-axis PDO (+axisPdoOffset), its entries moved
// to that axis' objects. An object or PDO the file defines itself at the
// copy's index is kept as written.
#include <algorithm>
#include <map>

#include <fmt/format.h>

#include "esi/device_attrs.hpp"
#include "esi/device_build.hpp"
#include "esi/device_failure.hpp"

namespace ecat::esi {
namespace {

// CiA 402-1 §6: at most eight logical devices (axes) in one device.
constexpr std::uint64_t kMaxAxes = 8;
constexpr std::uint64_t kMaxIndex = 0xFFFF;
// RxPDO 1600h-17FFh, TxPDO 1A00h-1BFFh (ETG.1000.6 §5.6.7.4.7/8).
constexpr std::uint64_t kPdoAreaSize = 0x200;

std::uint16_t index_attr(const ElementSpec& e, const char* name) {
  return static_cast<std::uint16_t>(attr_unsigned(e, name, kMaxIndex, 0));
}

std::string hex_index(std::uint16_t index) { return fmt::format("#x{:04X}", index); }

void check_layout(const DeviceSpec& spec, const od::AxisLayout& l) {
  const ElementSpec& d = spec.drive;
  if (l.axes == 0) fail_at(where_of(d, "axes"), "axes must be at least 1");
  if (l.axes == 1) return;
  if (l.index_offset == 0) fail_at(where_of(d, "axisIndexOffset"), "axisIndexOffset must not be 0");
  if (l.pdo_offset == 0 || std::uint64_t{l.axes} * l.pdo_offset > kPdoAreaSize) {
    fail_at(where_of(d, "axisPdoOffset"), fmt::format("axisPdoOffset {:#x} does not fit {} axes' PDOs into 1600h-17FFh "
                                                      "and 1A00h-1BFFh", l.pdo_offset, l.axes));
  }
  const std::vector<ElementSpec> none;
  const auto& ranges = spec.axis_objects ? *spec.axis_objects : none;
  for (std::size_t k = 0; k < l.ranges.size(); ++k) {
    const od::AxisRange& r = l.ranges[k];
    const Where w = k < ranges.size() ? ranges[k].where : d.where;
    if (r.first > r.last) fail_at(w, fmt::format("AxisObjects from {:04X}h is above to {:04X}h", r.first, r.last));
    if (std::uint64_t{r.last} + std::uint64_t{l.axes - 1} * l.index_offset > kMaxIndex) {
      fail_at(w, fmt::format("axis {} of {:04X}h-{:04X}h would lie beyond FFFFh", l.axes, r.first, r.last));
    }
    for (unsigned axis = 2; axis <= l.axes; ++axis) {
      for (std::uint16_t i : {r.first, r.last}) {
        if (l.per_axis(l.object_index(axis, i))) {
          fail_at(w, fmt::format("axis {} of {:04X}h ({:04X}h) lies inside a per-axis range of axis 1", axis, i,
                                 l.object_index(axis, i)));
        }
      }
    }
  }
  for (std::size_t k = 0; k < l.exceptions.size(); ++k) {
    const od::AxisIndex& x = l.exceptions[k];
    const ElementSpec& e = spec.axis_indices[k];
    if (x.axis < 2 || x.axis > l.axes) {
      fail_at(where_of(e, "axis"), fmt::format("AxisIndex axis {} is not one of the axes 2..{}", x.axis, l.axes));
    }
    if (!l.per_axis(x.index)) {
      fail_at(where_of(e, "index"), fmt::format("AxisIndex {:04X}h is not in a per-axis range (AxisObjects)", x.index));
    }
    if (l.per_axis(x.at)) {
      fail_at(where_of(e, "at"), fmt::format("AxisIndex at {:04X}h lies inside a per-axis range of axis 1", x.at));
    }
  }
}

// Every axis' copy of every per-axis object must have an index of its own.
void check_targets(const DeviceSpec& spec, const od::AxisLayout& l) {
  std::map<std::uint16_t, std::uint16_t> from;  // copy index -> axis-1 index
  for (const auto& [index, obj] : spec.objects) {
    if (!l.per_axis(index)) continue;
    for (unsigned axis = 2; axis <= l.axes; ++axis) {
      const std::uint16_t at = l.object_index(axis, index);
      auto [it, fresh] = from.emplace(at, index);
      if (!fresh) {
        fail_at(obj.where, fmt::format("axis {} copies of {:04X}h and {:04X}h would both be {:04X}h", axis,
                                       it->second, index, at));
      }
    }
  }
}

PdoSpec copy_pdo(const PdoSpec& p, const od::AxisLayout& l, unsigned axis) {
  PdoSpec c = p;
  c.index = l.pdo_index(axis, p.index);
  const Where& w = p.element.where;
  c.element.attrs.set("index", Attr{hex_index(c.index), w});
  c.element.attrs.set("name", Attr{fmt::format("{} (axis {})", attr_text(p.element, "name"), axis), w});
  if (p.element.attrs.has("excludes")) {
    std::string list;
    for (const auto& item : attr_list(p.element, "excludes")) {
      ElementSpec one;
      one.attrs.set("x", Attr{item, where_of(p.element, "excludes")});
      if (!list.empty()) list += ' ';
      list += hex_index(l.pdo_index(axis, index_attr(one, "x")));
    }
    c.element.attrs.set("excludes", Attr{list, where_of(p.element, "excludes")});
  }
  for (ElementSpec& e : c.entries) {
    if (!e.attrs.has("index")) continue;
    e.attrs.set("index", Attr{hex_index(l.object_index(axis, index_attr(e, "index"))), where_of(e, "index")});
  }
  return c;
}

}  // namespace

od::AxisLayout axis_layout(const DeviceSpec& spec) {
  od::AxisLayout l;
  const ElementSpec& d = spec.drive;
  if (d.where.file.empty()) return l;
  l.axes = static_cast<unsigned>(attr_unsigned(d, "axes", kMaxAxes, 1));
  if (d.attrs.has("axisIndexOffset")) l.index_offset = index_attr(d, "axisIndexOffset");
  l.pdo_offset = d.attrs.has("axisPdoOffset") ? index_attr(d, "axisPdoOffset") : od::kAxisPdoOffset;
  if (spec.axis_objects) {
    l.ranges.clear();
    for (const ElementSpec& r : *spec.axis_objects) l.ranges.push_back({index_attr(r, "from"), index_attr(r, "to")});
  }
  for (const ElementSpec& x : spec.axis_indices) {
    l.exceptions.push_back({static_cast<unsigned>(attr_unsigned(x, "axis", kMaxAxes, 0)), index_attr(x, "index"),
                            index_attr(x, "at")});
  }
  check_layout(spec, l);
  return l;
}

void derive_axes(DeviceSpec& spec) {
  const od::AxisLayout l = axis_layout(spec);
  if (l.axes <= 1) return;
  check_targets(spec, l);
  std::vector<std::pair<std::uint16_t, ObjectSpec>> objects;
  for (const auto& [index, obj] : spec.objects) {
    if (!l.per_axis(index)) continue;
    for (unsigned axis = 2; axis <= l.axes; ++axis) objects.emplace_back(l.object_index(axis, index), obj);
  }
  for (auto& [index, obj] : objects) spec.objects.try_emplace(index, std::move(obj));
  std::vector<PdoSpec> pdos;
  for (const auto& [index, pdo] : spec.pdos) {
    if (!l.per_axis_pdo(index)) continue;
    for (unsigned axis = 2; axis <= l.axes; ++axis) pdos.push_back(copy_pdo(pdo, l, axis));
  }
  for (PdoSpec& p : pdos) spec.pdos.try_emplace(p.index, std::move(p));
}

}  // namespace ecat::esi
