// A list of datagrams built at set-up time (one or more per slave) and sent
// packed into as few frames as fit (DatagramLink::exchange_batch): the scan,
// mailbox and process-data set-up of N slaves in about N / (datagrams per
// frame) frames instead of N or more (masters.md §1.1: SOEM reads the SII
// words of all slaves interleaved, TwinCAT puts many per-slave datagrams in
// one frame). Owns the data bytes; not for the cyclic path (it allocates).
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "master/datagram_link.hpp"

namespace ecat::master {

class DatagramBatch {
 public:
  // Appends a datagram carrying a copy of `data`; returns its index.
  std::size_t add(Command command, std::uint32_t address, ConstBytes data);
  // Appends a datagram with `length` zero bytes (reads).
  std::size_t add_zeros(Command command, std::uint32_t address, std::size_t length);
  // Sends all of them in order; returns the number of frames.
  Expected<std::size_t, MasterError> exchange(DatagramLink& link);

  std::size_t size() const noexcept { return entries_.size(); }
  bool empty() const noexcept { return entries_.empty(); }
  std::uint16_t wkc(std::size_t i) const noexcept { return entries_[i].wkc; }
  ConstBytes data(std::size_t i) const noexcept {
    return ConstBytes(bytes_.data() + entries_[i].offset, entries_[i].length);
  }
  // True when every datagram came back with exactly `wkc`.
  bool all_wkc(std::uint16_t wkc) const noexcept;
  void clear() noexcept;

 private:
  struct Entry {
    Command command;
    std::uint32_t address;
    std::size_t offset;
    std::size_t length;
    std::uint16_t wkc;
  };
  std::vector<Entry> entries_;
  std::vector<std::uint8_t> bytes_;
  std::vector<Datagram> datagrams_;
};

}  // namespace ecat::master
