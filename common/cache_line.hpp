// The cache line the layout of the per-cycle structures is planned around
// (issue 30 item 1: at 1000 drives each line a drive's cycle touches is a
// miss): 64 bytes, the line of the x86-64 hosts its figures come from.
// std::hardware_destructive_interference_size is not used: GCC warns that
// its value may differ between compilations (-Winterference-size).
#pragma once

#include <cstddef>

namespace ecat {

inline constexpr std::size_t kCacheLineBytes = 64;

}  // namespace ecat
