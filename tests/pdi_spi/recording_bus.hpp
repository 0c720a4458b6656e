// A SpiBus that records every transaction's MOSI bytes and answers with
// scripted MISO bytes (zeros when the script runs out): the exact bytes a
// backend clocks, without any chip.
#pragma once

#include <algorithm>
#include <cstdint>
#include <deque>
#include <span>
#include <vector>

#include "pdi_spi/spi_bus.hpp"

namespace ecat::pdi_spi::test {

using Bytes = std::vector<std::uint8_t>;

class RecordingBus final : public SpiBus {
 public:
  bool transfer(std::span<const std::uint8_t> tx, std::span<std::uint8_t> rx) noexcept override {
    sent.emplace_back(tx.begin(), tx.end());
    std::fill(rx.begin(), rx.end(), std::uint8_t{0});
    if (!replies.empty()) {
      const Bytes& r = replies.front();
      std::copy_n(r.begin(), std::min(r.size(), rx.size()), rx.begin());
      replies.pop_front();
    }
    return !fail;
  }
  std::vector<Bytes> sent;
  std::deque<Bytes> replies;  // MISO of the next transactions, in order
  bool fail = false;
};

}  // namespace ecat::pdi_spi::test
