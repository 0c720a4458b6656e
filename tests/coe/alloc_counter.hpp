// Counts heap allocations made while a scope is armed (the global operator
// new replacement lives in alloc_counter.cpp), for "no heap per cycle" tests.
#pragma once

#include <cstddef>

namespace ecat::coe::test {

struct AllocCounter {
  AllocCounter();
  ~AllocCounter();
  std::size_t count() const;
};

}  // namespace ecat::coe::test
