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
// Lines outside those objects ("other") are named by the heap block they
// lie in: the program records every heap block allocated after the marker
// is printed (its address, size and the code that asked for it) and lists
// the live ones before the cycles, so the script can count a cycle's other
// lines by the function that allocated them.
//
// Output (stdout): "MARK <hex address>" and "PHASE <hex address>" (of the
// phase marker, loaded before each frame's pass, its firmware run and the
// poll) first, then "OBJ <name> <index>
// <hex address> <bytes>" per object, "BASE <hex address of cycle_marker>", then
// "BLOCK <hex address> <bytes> <hex return address>" per live heap block,
// then nothing while the cycles run.
#include <algorithm>
#include <cstdio>
#include <cstdlib>
#include <exception>
#include <new>
#include <string>

#include "bench/drive_line.hpp"
#include "ds402/drive.hpp"
#include "slave/application.hpp"

namespace {

volatile int g_cycle_marker = 0;
// Loaded at the start of each phase of a cycle (each frame's pass through
// the ESCs, its firmware run, the poll): scripts/lines-per-drive's cache
// model names the phase each miss fell in.
volatile int g_phase_marker = 0;

// The heap blocks allocated while recording, in a fixed table (the recorder
// must not allocate). A block freed is marked so; a table full stops the
// record and the script names the missing lines "other" as before.
struct HeapBlock {
  void* at;
  std::size_t bytes;
  void* site;  // the return address of the operator new call
};
constexpr std::size_t kMaxBlocks = 1u << 20;
HeapBlock g_blocks[kMaxBlocks];
std::size_t g_block_count = 0;
bool g_recording = false;

void* record_new(std::size_t bytes, void* site, std::size_t align = 0) {
  void* p = align == 0 ? std::malloc(bytes == 0 ? 1 : bytes)
                       : std::aligned_alloc(align, (std::max<std::size_t>(bytes, 1) + align - 1) / align * align);
  if (p == nullptr) throw std::bad_alloc();
  if (g_recording && g_block_count < kMaxBlocks) g_blocks[g_block_count++] = {p, bytes, site};
  return p;
}

void record_delete(void* p) noexcept {
  if (p == nullptr) return;
  if (g_recording) {
    for (std::size_t i = g_block_count; i-- > 0;) {
      if (g_blocks[i].at == p) {
        g_blocks[i].at = nullptr;
        break;
      }
    }
  }
  std::free(p);
}

// Out of line, so that its one load sits between two cycles in the trace.
[[gnu::noinline]] void cycle_marker() { (void)g_cycle_marker; }
[[gnu::noinline]] void phase_marker() { (void)g_phase_marker; }

// DriveLine::cycle's frame path: Chain::process_frame in its two halves,
// a phase marker before each, and one after the last frame's firmware
// (so that the poll is a phase of its own).
struct MarkedPath {
  ecat::slave::Chain& chain;
  std::size_t frames;
  std::size_t seen = 0;
  bool whole = std::getenv("LINES_WHOLE_FRAMES") != nullptr;
  bool process_frame(std::span<std::uint8_t> frame, ecat::Nanoseconds now) noexcept {
    phase_marker();
    if (whole) {  // Chain::process_frame as the bench runs it: one phase a frame
      const bool returned = chain.process_frame(frame, now);
      phase_marker();
      if (++seen % frames == 0) phase_marker();
      return returned;
    }
    const bool returned = chain.pass_frame(frame, now);
    phase_marker();
    chain.run_firmware(now);
    if (++seen % frames == 0) phase_marker();
    return returned;
  }
};

void print_object(const char* name, std::size_t index, const void* at, std::size_t bytes) {
  std::printf("OBJ %s %zu %p %zu\n", name, index, at, bytes);
}

}  // namespace

void* operator new(std::size_t bytes) { return record_new(bytes, __builtin_return_address(0)); }
void* operator new[](std::size_t bytes) { return record_new(bytes, __builtin_return_address(0)); }
void operator delete(void* p) noexcept { record_delete(p); }
void operator delete[](void* p) noexcept { record_delete(p); }
void operator delete(void* p, std::size_t) noexcept { record_delete(p); }
void operator delete[](void* p, std::size_t) noexcept { record_delete(p); }
void* operator new(std::size_t bytes, std::align_val_t a) {
  return record_new(bytes, __builtin_return_address(0), static_cast<std::size_t>(a));
}
void* operator new[](std::size_t bytes, std::align_val_t a) {
  return record_new(bytes, __builtin_return_address(0), static_cast<std::size_t>(a));
}
void operator delete(void* p, std::align_val_t) noexcept { record_delete(p); }
void operator delete[](void* p, std::align_val_t) noexcept { record_delete(p); }
void operator delete(void* p, std::size_t, std::align_val_t) noexcept { record_delete(p); }
void operator delete[](void* p, std::size_t, std::align_val_t) noexcept { record_delete(p); }

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
  std::printf("PHASE %p\n", static_cast<const void*>(const_cast<const int*>(&g_phase_marker)));
  std::fflush(stdout);
  g_recording = true;
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
    g_recording = false;
    std::printf("BASE %p\n", reinterpret_cast<const void*>(&cycle_marker));
    for (std::size_t i = 0; i < g_block_count; ++i) {
      if (g_blocks[i].at != nullptr) std::printf("BLOCK %p %zu %p\n", g_blocks[i].at, g_blocks[i].bytes, g_blocks[i].site);
    }
    std::fflush(stdout);
    MarkedPath path{chain, line.frames()};
    for (int c = 0; c < cycles; ++c) {
      cycle_marker();
      line.cycle(path);
    }
    cycle_marker();
  } catch (const std::exception& e) {
    std::fprintf(stderr, "ecat-bench-lines: %s\n", e.what());
    return 1;
  }
  return 0;
}
