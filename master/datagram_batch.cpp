#include "master/datagram_batch.hpp"

#include <algorithm>

namespace ecat::master {

std::size_t DatagramBatch::add(Command command, std::uint32_t address, ConstBytes data) {
  entries_.push_back(Entry{command, address, bytes_.size(), data.size(), 0});
  bytes_.insert(bytes_.end(), data.begin(), data.end());
  return entries_.size() - 1;
}

std::size_t DatagramBatch::add_zeros(Command command, std::uint32_t address, std::size_t length) {
  entries_.push_back(Entry{command, address, bytes_.size(), length, 0});
  bytes_.resize(bytes_.size() + length, 0);
  return entries_.size() - 1;
}

Expected<std::size_t, MasterError> DatagramBatch::exchange(DatagramLink& link) {
  datagrams_.clear();
  for (const Entry& e : entries_) {
    datagrams_.push_back(Datagram{e.command, e.address, Bytes(bytes_.data() + e.offset, e.length), 0});
  }
  auto frames = link.exchange_batch(datagrams_);
  if (!frames) return fail(frames.error());
  for (std::size_t i = 0; i < entries_.size(); ++i) entries_[i].wkc = datagrams_[i].wkc;
  return *frames;
}

bool DatagramBatch::all_wkc(std::uint16_t wkc) const noexcept {
  return std::all_of(entries_.begin(), entries_.end(), [wkc](const Entry& e) { return e.wkc == wkc; });
}

void DatagramBatch::clear() noexcept {
  entries_.clear();
  bytes_.clear();
  datagrams_.clear();
}

}  // namespace ecat::master
