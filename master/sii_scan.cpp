// The SII images of all slaves read side by side (issue 16 item 5; SOEM
// reads the identity words of all slaves interleaved, masters.md §1.1/§1.2):
// every slave runs the same read sequence as Master::read_sii_image (idle
// check, error clear, read command, one FPRD of 0x0502-0x050F until not busy,
// the category walk), one step per round, and each round puts one datagram
// per slave into as few frames as fit. A slave sees exactly the datagrams it
// saw when read alone; N slaves take about N / 57 frames per step instead of N.
// MasterConfig::read_sii_strings = false leaves the STRINGS category out (SOEM
// reads strings only for the name; half of a generic servo's 1 KiB image).
#include <algorithm>
#include <optional>

#include "master/datagram_batch.hpp"
#include "master/master.hpp"
#include "master/poll_budget.hpp"
#include "master/registers.hpp"

namespace ecat::master {

namespace {

enum class Step : std::uint8_t { IdleCheck, ClearError, Command, Wait, Done };

constexpr std::size_t kStatusBytes = 2;
constexpr std::size_t kCommandBytes = 6;  // {0x0100, word address (u32)}
constexpr std::size_t kDataAt = reg::kEepromData - reg::kEepromControlStatus;
constexpr std::size_t kWaitBytes = kDataAt + sii::kReadMax;  // status, address, data

struct Reader {
  std::uint16_t station = 0;
  Step step = Step::IdleCheck;
  std::vector<std::uint8_t> image;
  std::size_t need = sii::kFixedAreaBytes;  // read until the image holds this many bytes
  std::size_t walk = sii::kFirstCategory;   // word of the category header to look at next
  bool walking = false;
  unsigned attempts = 0;  // read commands sent for the current word
  std::optional<PollBudget> budget;
};

// After data arrived (or at the start): the next word to read, or done.
// Without `strings`, a STRINGS category is not read: its data bytes are left
// zero (a category of 0 strings) and the walk reads on at the next header.
Expected<void, MasterError> advance(Reader& r, bool strings) {
  for (;;) {
    if (r.image.size() < r.need) {
      r.step = Step::Command;
      r.attempts = 0;
      return {};
    }
    if (!r.walking) {
      r.walking = true;
      r.need = 2 * (r.walk + 2);
      continue;
    }
    const auto type = load_le<std::uint16_t>(r.image.data() + 2 * r.walk);
    if (type == static_cast<std::uint16_t>(sii::Category::End)) {
      r.image.resize(std::min(r.image.size(), 2 * (r.walk + 1)));
      r.step = Step::Done;
      return {};
    }
    const auto words = load_le<std::uint16_t>(r.image.data() + 2 * (r.walk + 1));
    if (!strings && (type & sii::kCategoryTypeMask) == static_cast<std::uint16_t>(sii::Category::Strings)) {
      r.image.resize(2 * (r.walk + 2));              // drop what a read brought beyond the header
      r.image.resize(2 * (r.walk + 2 + words), 0);   // and leave the strings out
    }
    r.walk += 2u + words;
    if (2 * r.walk >= sii::kMaxImageBytes) return fail(MasterError::SiiInvalid);
    r.need = 2 * (r.walk + 2);
  }
}

}  // namespace

Expected<void, MasterError> Master::read_sii_images() {
  std::vector<Reader> readers(slaves_.size());
  for (std::size_t i = 0; i < slaves_.size(); ++i) {
    readers[i].station = slaves_[i].station_address;
    readers[i].image.reserve(sii::kFixedAreaBytes * 4);
  }
  DatagramBatch batch;
  std::vector<std::size_t> active;
  for (;;) {
    batch.clear();
    active.clear();
    for (std::size_t i = 0; i < readers.size(); ++i) {
      Reader& r = readers[i];
      if (r.step == Step::Done) continue;
      const auto at = device_address(r.station, reg::kEepromControlStatus);
      switch (r.step) {
        case Step::IdleCheck:
          if (!r.budget) r.budget.emplace(clock_, config_.sii_timeout, config_.max_polls);
          if (!r.budget->next()) return fail(MasterError::SiiTimeout);
          batch.add_zeros(Command::Fprd, at, kStatusBytes);
          break;
        case Step::ClearError: {
          const std::uint8_t zero[kStatusBytes]{};
          batch.add(Command::Fpwr, at, zero);
          break;
        }
        case Step::Command: {
          std::uint8_t cmd[kCommandBytes];
          store_le(cmd, reg::kEepromCmdRead);
          store_le(cmd + 2, static_cast<std::uint32_t>(r.image.size() / 2));
          batch.add(Command::Fpwr, at, cmd);
          break;
        }
        case Step::Wait:
          if (!r.budget->next()) return fail(MasterError::SiiTimeout);
          batch.add_zeros(Command::Fprd, at, kWaitBytes);
          break;
        case Step::Done: break;
      }
      active.push_back(i);
    }
    if (active.empty()) break;
    if (auto x = batch.exchange(link_); !x) return fail(x.error());
    for (std::size_t k = 0; k < active.size(); ++k) {
      Reader& r = readers[active[k]];
      if (batch.wkc(k) != 1) return fail(MasterError::WorkingCounter);
      const ConstBytes data = batch.data(k);
      switch (r.step) {
        case Step::IdleCheck: {
          const auto status = load_le<std::uint16_t>(data.data());
          if ((status & reg::kEepromBusy) != 0) break;  // poll again
          r.budget.reset();
          if ((status & reg::kEepromErrorBits) != 0) {
            r.step = Step::ClearError;
          } else if (auto a = advance(r, config_.read_sii_strings); !a) {
            return fail(a.error());
          }
          break;
        }
        case Step::ClearError:
          if (auto a = advance(r, config_.read_sii_strings); !a) return fail(a.error());
          break;
        case Step::Command:
          ++r.attempts;
          r.step = Step::Wait;
          r.budget.emplace(clock_, config_.sii_timeout, config_.max_polls);
          break;
        case Step::Wait: {
          const auto status = load_le<std::uint16_t>(data.data());
          if ((status & reg::kEepromBusy) != 0) break;  // poll again
          r.budget.reset();
          if ((status & reg::kEepromAckError) != 0) {  // SOEM retries on ack error
            if (r.attempts >= sii::kCommandTries) return fail(MasterError::SiiError);
            r.step = Step::Command;
            break;
          }
          if ((status & reg::kEepromErrorBits) != 0) return fail(MasterError::SiiError);
          const std::size_t n = (status & reg::kEepromReadSize8) != 0 ? 8 : 4;
          r.image.insert(r.image.end(), data.begin() + kDataAt, data.begin() + static_cast<std::ptrdiff_t>(kDataAt + n));
          if (auto a = advance(r, config_.read_sii_strings); !a) return fail(a.error());
          break;
        }
        case Step::Done: break;
      }
    }
  }
  for (std::size_t i = 0; i < slaves_.size(); ++i) slaves_[i].sii_image = std::move(readers[i].image);
  return {};
}

}  // namespace ecat::master
