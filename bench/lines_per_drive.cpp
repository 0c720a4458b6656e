// ecat-bench-lines: where a CSP cycle's memory accesses go, per drive
// (issue 30 item 1). Builds N generic servo drives in one chain taken to Op
// (bench/drive_line.hpp, as BM_Cycle_Csp), prints the address and size of
// each drive's per-slave objects, then runs CYCLES cycles, each one after
// a call of cycle_marker(), whose load of a static marks the cycle's start
// in a memory trace. scripts/lines-per-drive runs it under valgrind's
// lackey and counts the distinct 64-byte lines one cycle reads or writes,
// per object and in all, divided by N: a count that does not depend on the
// host or its load, unlike the simulated misses of a cache model (which
// move with the heap's layout: docs/performance.md "Issue 30: where it
// stands").
//
// Output (stdout): "MARK <hex address>" first, then "OBJ <name> <index>
// <hex address> <bytes>" per object, then nothing while the cycles run.
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <string>

#include "bench/drive_line.hpp"
#include "ds402/drive.hpp"
#include "slave/application.hpp"

namespace {

volatile int g_cycle_marker = 0;

// Out of line, so that its one load sits between two cycles in the trace.
[[gnu::noinline]] void cycle_marker() { (void)g_cycle_marker; }

void print_object(const char* name, std::size_t index, const void* at, std::size_t bytes) {
  std::printf("OBJ %s %zu %p %zu\n", name, index, at, bytes);
}

}  // namespace

int main(int argc, char** argv) {
  using ecat::bench::DriveLine;
  constexpr std::size_t kDefaultDrives = 10;
  constexpr int kDefaultCycles = 4;
  const std::size_t drives = argc > 1 ? std::strtoul(argv[1], nullptr, 10) : kDefaultDrives;
  const int cycles = argc > 2 ? std::atoi(argv[2]) : kDefaultCycles;
  if (drives == 0 || cycles < 2) {
    std::fprintf(stderr, "usage: ecat-bench-lines [DRIVES>=1] [CYCLES>=2]\n");
    return 2;
  }
  // The marker first, before the set-up: the script reads it while the
  // trace runs.
  std::printf("MARK %p\n", static_cast<const void*>(const_cast<const int*>(&g_cycle_marker)));
  std::fflush(stdout);
  try {
    DriveLine line(drives, DriveLine::default_device());
    ecat::slave::Chain& chain = line.chain();
    for (std::size_t i = 0; i < chain.size(); ++i) {
      ecat::slave::VirtualSlave& s = chain[i];
      print_object("vslave", i, &s, sizeof(s));
      print_object("esc", i, &s.esc(), sizeof(ecat::esc::Esc));
      print_object("esc-memory", i, s.esc().memory(), s.esc().memory_size());
      ecat::slave::Firmware& fw = s.firmware();
      print_object("firmware", i, &fw, sizeof(fw));
      auto& store = fw.coe().objects();
      print_object("od-values", i, store.values(), store.value_bytes());
      if (ecat::slave::Application* app = fw.application()) {
        if (ecat::ds402::Drive* d = app->drive(0)) print_object("drive", i, d, sizeof(*d));
      }
    }
    std::fflush(stdout);
    for (int c = 0; c < cycles; ++c) {
      cycle_marker();
      line.cycle();
    }
    cycle_marker();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ecat-bench-lines: %s\n", e.what());
    return 1;
  }
  return 0;
}
