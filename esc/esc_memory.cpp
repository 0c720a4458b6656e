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
#include <sys/mman.h>

#include <new>

#include "esc/esc.hpp"

namespace ecat::esc {

std::unique_ptr<std::uint8_t[], Esc::MemoryUnmap> Esc::map_memory(std::size_t size) {
  void* p = ::mmap(nullptr, size, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (p == MAP_FAILED) throw std::bad_alloc();
  return std::unique_ptr<std::uint8_t[], MemoryUnmap>(static_cast<std::uint8_t*>(p), MemoryUnmap{size});
}

void Esc::MemoryUnmap::operator()(std::uint8_t* p) const noexcept {
  if (p != nullptr) ::munmap(p, size);
}

}  // namespace ecat::esc
