// Counts heap allocations while an AllocCounter is alive, for the tests that
// prove a cyclic path allocates nothing (STYLE lesson 11). The test program
// that links tests/support/alloc_counter.cpp replaces the global operator
// new/delete with malloc/free plus a counter.
#pragma once

#include <cstddef>

namespace ecat::test {

struct AllocCounter {
  AllocCounter();
  ~AllocCounter();
  AllocCounter(const AllocCounter&) = delete;
  AllocCounter& operator=(const AllocCounter&) = delete;
  std::size_t count() const;
};

}  // namespace ecat::test
