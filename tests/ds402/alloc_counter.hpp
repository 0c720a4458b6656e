// Heap allocations made while an AllocCounter is alive (operator new is
// replaced in alloc_counter.cpp for the whole test program).
#pragma once

#include <cstddef>

namespace ecat::ds402::test {
struct AllocCounter {
  AllocCounter();
  ~AllocCounter();
  std::size_t count() const;
};
}  // namespace ecat::ds402::test
