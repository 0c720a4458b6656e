// SII reads through the ESC's EEPROM interface 0x0500-0x050F the way SOEM and
// ethercrab do it (esc-registers.md §9, masters.md §1.2): wait until not busy,
// clear errors, write {0x0100, word address} to 0x0502, wait until not busy,
// read 4 or 8 bytes (0x0502 bit 6) from 0x0508 - the last wait and the data
// read are one FPRD of 0x0502-0x050F (sii_read_word).
#include <algorithm>

#include "master/master.hpp"
#include "master/poll_budget.hpp"
#include "master/registers.hpp"

namespace ecat::master {

namespace {
constexpr std::size_t kSiiReadMax = sii::kReadMax;
constexpr std::size_t kSiiMaxBytes = sii::kMaxImageBytes;
constexpr unsigned kSiiCommandTries = sii::kCommandTries;
}  // namespace

Expected<void, MasterError> Master::sii_wait_idle(std::uint16_t station, std::uint16_t& status) {
  for (PollBudget budget(clock_, config_.sii_timeout, config_.max_polls); budget.next();) {
    auto s = fprd_u16(station, reg::kEepromControlStatus);
    if (!s) return fail(s.error());
    status = *s;
    if ((status & reg::kEepromBusy) == 0) return {};
  }
  return fail(MasterError::SiiTimeout);
}

Expected<std::size_t, MasterError> Master::sii_read(std::uint16_t station, std::uint16_t word_address, Bytes out) {
  return sii_read_word(station, word_address, out, false);
}

// `idle`: the caller's previous read on this station ended idle and without
// error, so the first wait is skipped. The wait after the command reads
// 0x0502-0x050F in one FPRD: the datagram that shows "not busy" carries the
// data of the same instant (the ESC loads 0x0508 before it clears busy,
// Section II 0x0502 bit 15), so the separate read of 0x0508 is not needed.
// Two frames per 8 bytes instead of four (issue 16 item 5: scan of 1000 slaves).
Expected<std::size_t, MasterError> Master::sii_read_word(std::uint16_t station, std::uint16_t word_address, Bytes out,
                                                         bool idle) {
  if (out.size() < kSiiReadMax) return fail(MasterError::InvalidArgument);
  std::uint16_t status = 0;
  if (!idle) {
    if (auto r = sii_wait_idle(station, status); !r) return fail(r.error());
    if ((status & reg::kEepromErrorBits) != 0) {
      if (auto r = fpwr_u16(station, reg::kEepromControlStatus, 0); !r) return fail(r.error());
    }
  }
  constexpr std::size_t kDataAt = reg::kEepromData - reg::kEepromControlStatus;
  for (unsigned attempt = 0; attempt < kSiiCommandTries; ++attempt) {
    std::uint8_t cmd[6];
    store_le(cmd, reg::kEepromCmdRead);
    store_le(cmd + 2, static_cast<std::uint32_t>(word_address));
    if (auto r = fpwr(station, reg::kEepromControlStatus, cmd); !r) return fail(r.error());
    std::uint8_t regs[kDataAt + kSiiReadMax]{};
    bool done = false;
    for (PollBudget budget(clock_, config_.sii_timeout, config_.max_polls); budget.next();) {
      if (auto r = fprd(station, reg::kEepromControlStatus, regs); !r) return fail(r.error());
      status = load_le<std::uint16_t>(regs);
      if ((status & reg::kEepromBusy) == 0) {
        done = true;
        break;
      }
    }
    if (!done) return fail(MasterError::SiiTimeout);
    if ((status & reg::kEepromAckError) != 0) continue;  // SOEM retries on ack error
    if ((status & reg::kEepromErrorBits) != 0) return fail(MasterError::SiiError);
    const std::size_t n = (status & reg::kEepromReadSize8) != 0 ? 8 : 4;
    std::copy_n(regs + kDataAt, n, out.begin());
    return n;
  }
  return fail(MasterError::SiiError);
}

Expected<std::vector<std::uint8_t>, MasterError> Master::read_sii_image(std::uint16_t station) {
  std::vector<std::uint8_t> image;
  image.reserve(sii::kFixedAreaBytes * 4);
  std::uint8_t chunk[kSiiReadMax]{};
  auto read_until = [&](std::size_t bytes) -> Expected<void, MasterError> {
    while (image.size() < bytes) {
      const auto word = static_cast<std::uint16_t>(image.size() / 2);
      auto n = sii_read_word(station, word, chunk, !image.empty());
      if (!n) return fail(n.error());
      image.insert(image.end(), chunk, chunk + *n);
    }
    return {};
  };
  if (auto r = read_until(sii::kFixedAreaBytes); !r) return fail(r.error());
  // Walk category headers, reading each category in full.
  std::size_t w = sii::kFirstCategory;
  for (;;) {
    if (auto r = read_until(2 * (w + 2)); !r) return fail(r.error());
    const auto type = load_le<std::uint16_t>(image.data() + 2 * w);
    if (type == static_cast<std::uint16_t>(sii::Category::End)) break;
    const auto words = load_le<std::uint16_t>(image.data() + 2 * (w + 1));
    w += 2u + words;
    if (2 * w >= kSiiMaxBytes) return fail(MasterError::SiiInvalid);
  }
  image.resize(std::min(image.size(), 2 * (w + 1)));
  return image;
}

}  // namespace ecat::master
