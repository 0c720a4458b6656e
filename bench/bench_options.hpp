// Options shared by the benchmark programs.
#pragma once

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <string>

#include "common/huge_pages.hpp"

namespace ecat::bench {

// ECAT_BENCH_ITERATIONS=N runs every case exactly N iterations (once), so a
// callgrind run gives instructions per operation as total / N - a figure
// that does not depend on the machine's load:
//   ECAT_BENCH_ITERATIONS=10000 valgrind --tool=callgrind build-bench/bin/bench_esc
inline void iterations_from_env(benchmark::internal::Benchmark* b) {
  if (const char* s = std::getenv("ECAT_BENCH_ITERATIONS")) {
    const long long n = std::strtoll(s, nullptr, 10);
    if (n > 0) b->Iterations(n);
  }
}

// Once a case has built its chain: the heap on 2 MiB pages, as ecat-slave
// does (common/huge_pages.hpp); ECAT_BENCH_SMALL_PAGES=1 leaves it on 4 KiB
// pages, so that one binary measures both (docs/performance-log.md "Session 19").
inline void advise_huge_pages_from_env() {
  const char* s = std::getenv("ECAT_BENCH_SMALL_PAGES");
  if (s != nullptr && std::string(s) == "1") return;
  (void)advise_heap_huge_pages();
}

}  // namespace ecat::bench
