// Options shared by the benchmark programs.
#pragma once

#include <benchmark/benchmark.h>

#include <cstdlib>
#include <string>

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

}  // namespace ecat::bench
