// Where each axis of a multi-axis CiA 402 device keeps its objects and PDOs.
// CiA 402-1 §6 places the objects of logical device (axis) n at the axis-1
// index + (n-1)·800h; a device may list per-axis exceptions its manual
// states (the Welcon puts axis 2 of 2244h/2245h at 2A42h/2A43h), and its
// per-axis PDOs sit at the axis-1 PDO index + (n-1)·pdo_offset (ETG.6010
// leaves the PDO numbering to the device; the Welcon uses +10h). Common
// objects (outside every per-axis range: 1xxxh, 5xxxh, ...) are shared.
#pragma once

#include <cstdint>
#include <vector>

namespace ecat::od {

// CiA 402-1 §6: index offset between consecutive logical devices (axes).
inline constexpr std::uint16_t kAxisIndexOffset = 0x0800;
// Default offset between consecutive axes' PDOs (docs/device-format.md).
inline constexpr std::uint16_t kAxisPdoOffset = 0x0010;
// The CiA 402 profile area of axis 1 (CiA 402-1 §6), the default per-axis range.
inline constexpr std::uint16_t kProfileAreaFirst = 0x6000;
inline constexpr std::uint16_t kProfileAreaLast = 0x67FF;
// First RxPDO / TxPDO mapping index (ETG.1000.6 §5.6.7.4.7/8).
inline constexpr std::uint16_t kRxPdoFirst = 0x1600;
inline constexpr std::uint16_t kTxPdoFirst = 0x1A00;

struct AxisRange {
  std::uint16_t first = 0, last = 0;  // axis-1 indices, inclusive
};

// One exception to the offset rule: axis `axis` keeps axis-1 object `index` at `at`.
struct AxisIndex {
  unsigned axis = 0;
  std::uint16_t index = 0, at = 0;
};

struct AxisLayout {
  unsigned axes = 1;
  std::uint16_t index_offset = kAxisIndexOffset;
  std::uint16_t pdo_offset = kAxisPdoOffset;
  std::vector<AxisRange> ranges{{kProfileAreaFirst, kProfileAreaLast}};
  std::vector<AxisIndex> exceptions;

  // Whether axis-1 object `index` has one copy per axis.
  bool per_axis(std::uint16_t index) const noexcept {
    for (const AxisRange& r : ranges) {
      if (index >= r.first && index <= r.last) return true;
    }
    return false;
  }
  // The index axis `axis` (1-based) uses for axis-1 object `index`: the index
  // itself for axis 1 and for common objects.
  std::uint16_t object_index(unsigned axis, std::uint16_t index) const noexcept {
    if (axis <= 1 || !per_axis(index)) return index;
    for (const AxisIndex& e : exceptions) {
      if (e.axis == axis && e.index == index) return e.at;
    }
    return static_cast<std::uint16_t>(index + (axis - 1) * index_offset);
  }
  // Whether axis-1 PDO `index` has one copy per axis: the PDOs of the first
  // pdo_offset RxPDO and TxPDO indices.
  bool per_axis_pdo(std::uint16_t index) const noexcept {
    return (index >= kRxPdoFirst && index < kRxPdoFirst + pdo_offset) ||
           (index >= kTxPdoFirst && index < kTxPdoFirst + pdo_offset);
  }
  std::uint16_t pdo_index(unsigned axis, std::uint16_t index) const noexcept {
    if (axis <= 1 || !per_axis_pdo(index)) return index;
    return static_cast<std::uint16_t>(index + (axis - 1) * pdo_offset);
  }
};

}  // namespace ecat::od
