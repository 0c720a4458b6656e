// The ESC's memory: registers 0x0000-0x0FFF and the configured process RAM
// in one block (issue 16 item 5). It is an anonymous private mapping, so
// the kernel backs a page only when the ESC first writes it: a slave with
// 8 KiB of RAM whose mailboxes and process data lie in its first 4 KiB keeps
// 8 KiB resident (the register page and that RAM page), and one with the
// largest RAM (60 KiB) pays only for the pages its sync managers and the
// master use. A fresh mapping reads as zero, which is the power-on value of
// the RAM and of every register the reset does not set, so the first reset
// does not clear it (Esc::memory_fresh_); an ESC reset later clears it.
// Allocated once at construction; nothing here runs per frame.
//
// The block starts EscConfig::memory_colour x kMemoryColourStep bytes into its
// mapping (issue 30, docs/performance-log.md session 16): page-aligned blocks
// put the same register of every ESC at the same address modulo 4 KiB, and
// a frame passing a line stores to a register of one ESC and then loads the
// same register of the next - the CPU takes such a pair for one address
// until it has compared them in full, and the load waits. The offset is
// less than a page and the registers end at 0x0FFF, so the pages an ESC
// touches stay as many. Every mapping has room for the largest offset,
// whatever the block's own, so the ESCs of a chain map equal sizes: with
// size + offset (with 8 KiB of RAM, 3 pages for colour 0 and 4 for the
// others) the 1000-drive CSP cycle took 1.05-1.08x the CPU time at the same
// simulated cache misses (docs/performance-log.md "Session 19: ESC mappings of
// one size").
#include <sys/mman.h>
#include <unistd.h>

#include <cstdint>
#include <new>

#include "esc/esc.hpp"

namespace ecat::esc {
namespace {

constexpr std::size_t kLargestOffset = EscConfig::kMemoryColourStep * (EscConfig::kMemoryColours - 1);

}  // namespace

std::unique_ptr<std::uint8_t[], Esc::MemoryUnmap> Esc::map_memory(std::size_t size, unsigned colour) {
  const std::size_t offset = EscConfig::kMemoryColourStep * (colour % EscConfig::kMemoryColours);
  const std::size_t mapped = size + kLargestOffset;
  void* p = ::mmap(nullptr, mapped, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) throw std::bad_alloc();
  return std::unique_ptr<std::uint8_t[], MemoryUnmap>(static_cast<std::uint8_t*>(p) + offset, MemoryUnmap{mapped});
}

// The mapping starts at the page boundary at or below the block.
void Esc::MemoryUnmap::operator()(std::uint8_t* p) const noexcept {
  if (p == nullptr) return;
  const auto page = static_cast<std::uintptr_t>(::sysconf(_SC_PAGESIZE));
  ::munmap(reinterpret_cast<void*>(reinterpret_cast<std::uintptr_t>(p) & ~(page - 1)), size);
}

}  // namespace ecat::esc
