#include "pdi_host/pdi_session.hpp"

#include <fmt/format.h>

#include "common/le.hpp"
#include "esc/registers.hpp"

namespace ecat::pdi_host {
namespace {

constexpr std::size_t kReadRequestSize = 4;   // u16 address, u16 length
constexpr std::size_t kWriteAddressSize = 2;  // u16 address, then the bytes
constexpr std::size_t kTimeReplySize = 8;     // u64 ns

template <typename T>
void put(std::vector<std::uint8_t>& out, T v) {
  std::uint8_t b[sizeof(T)];
  store_le(b, v);
  out.insert(out.end(), b, b + sizeof(T));
}

std::uint64_t ns_of(Nanoseconds t) noexcept { return static_cast<std::uint64_t>(t.count()); }

}  // namespace

void put_header(std::vector<std::uint8_t>& out, std::uint8_t type, std::size_t payload_length) {
  out.push_back(type);
  out.push_back(0);
  put(out, static_cast<std::uint16_t>(payload_length));
}

PdiLines PdiSession::lines() const noexcept {
  PdiLines l;
  l.event_request = esc_.al_event_request();
  l.event_mask = load_le<std::uint32_t>(esc_.memory() + esc::reg::kAlEventMask);
  l.irq = chip_ ? chip_->irq_pin() : esc_.irq();
  return l;
}

void PdiSession::append_lines(std::vector<std::uint8_t>& out, std::uint8_t type, std::uint8_t sync) {
  PdiLines l = lines();
  l.sync = sync;
  put_header(out, type, ECAT_PDI_LINES_SIZE);
  put(out, l.event_request);
  put(out, l.event_mask);
  out.push_back(l.irq ? 1 : 0);
  out.push_back(l.sync);
  put(out, std::uint16_t{0});
  put(out, ns_of(clock_.now()));
  sent_ = l;
  sent_any_ = true;
}

void PdiSession::greet(std::vector<std::uint8_t>& out) {
  put_header(out, ECAT_PDI_MSG_HELLO, 4);
  put(out, static_cast<std::uint16_t>(ECAT_PDI_PROTOCOL_VERSION));
  out.push_back(static_cast<std::uint8_t>(kind_));
  out.push_back(0);
  append_lines(out, ECAT_PDI_MSG_NOTIFY, 0);
}

bool PdiSession::notify(std::vector<std::uint8_t>& out, std::uint8_t sync) {
  if (sent_any_ && sync == 0 && lines().same_level(sent_)) return false;
  append_lines(out, ECAT_PDI_MSG_NOTIFY, sync);
  return true;
}

bool PdiSession::has_message(const std::vector<std::uint8_t>& in) noexcept {
  if (in.size() < kHeaderSize) return false;
  return in.size() >= kHeaderSize + load_le<std::uint16_t>(in.data() + 2);
}

Expected<std::size_t, std::string> PdiSession::handle(std::vector<std::uint8_t>& in, std::vector<std::uint8_t>& out,
                                                      std::size_t max_messages) {
  std::size_t at = 0;
  std::size_t handled = 0;
  Expected<std::size_t, std::string> result = std::size_t{0};
  while (handled < max_messages && in.size() - at >= kHeaderSize) {
    const std::uint8_t* h = in.data() + at;
    if (h[1] != 0) {
      result = fail(fmt::format("message type 0x{:02X}: reserved header byte is 0x{:02X}, not 0", h[0], h[1]));
      break;
    }
    const std::size_t length = load_le<std::uint16_t>(h + 2);
    if (in.size() - at < kHeaderSize + length) break;  // the rest has not come yet
    if (auto ok = one(h[0], h + kHeaderSize, length, out); !ok) {
      result = fail(ok.error());
      break;
    }
    at += kHeaderSize + length;
    ++handled;
  }
  in.erase(in.begin(), in.begin() + static_cast<std::ptrdiff_t>(at));
  if (!result) return result;
  return handled;
}

Expected<void, std::string> PdiSession::one(std::uint8_t type, const std::uint8_t* payload, std::size_t length,
                                            std::vector<std::uint8_t>& out) {
  const bool direct = kind_ == PdiChip::Direct;
  switch (type) {
    case ECAT_PDI_MSG_READ: {
      if (!direct) return fail(fmt::format("READ on a {} PDI: send its SPI transactions", describe(kind_)));
      if (length != kReadRequestSize) return fail(fmt::format("READ with a {}-byte payload, not 4", length));
      const std::uint16_t address = load_le<std::uint16_t>(payload);
      const std::uint16_t count = load_le<std::uint16_t>(payload + 2);
      if (count == 0 || address + std::uint32_t{count} > kAddressSpace) {
        return fail(fmt::format("READ of {} bytes at 0x{:04X}: outside 0x0000-0xFFFF or empty", count, address));
      }
      put_header(out, ECAT_PDI_MSG_READ | ECAT_PDI_REPLY, count);
      const std::size_t start = out.size();
      out.resize(start + count);
      esc_.read(address, std::span<std::uint8_t>(out.data() + start, count));
      return {};
    }
    case ECAT_PDI_MSG_WRITE: {
      if (!direct) return fail(fmt::format("WRITE on a {} PDI: send its SPI transactions", describe(kind_)));
      if (length <= kWriteAddressSize) return fail(std::string("WRITE without data"));
      const std::uint16_t address = load_le<std::uint16_t>(payload);
      const std::size_t count = length - kWriteAddressSize;
      if (address + count > kAddressSpace) {
        return fail(fmt::format("WRITE of {} bytes at 0x{:04X}: past 0xFFFF", count, address));
      }
      esc_.write(address, std::span<const std::uint8_t>(payload + kWriteAddressSize, count));
      put_header(out, ECAT_PDI_MSG_WRITE | ECAT_PDI_REPLY, 0);
      return {};
    }
    case ECAT_PDI_MSG_SPI: {
      if (chip_ == nullptr) return fail(std::string("SPI on a direct PDI: send READ and WRITE"));
      if (length == 0) return fail(std::string("SPI transaction of 0 bytes"));
      put_header(out, ECAT_PDI_MSG_SPI | ECAT_PDI_REPLY, length);
      const std::size_t start = out.size();
      out.resize(start + length);
      (void)chip_->transfer(std::span<const std::uint8_t>(payload, length),
                            std::span<std::uint8_t>(out.data() + start, length));
      return {};
    }
    case ECAT_PDI_MSG_TIME:
      if (length != 0) return fail(fmt::format("TIME with a {}-byte payload, not 0", length));
      put_header(out, ECAT_PDI_MSG_TIME | ECAT_PDI_REPLY, kTimeReplySize);
      put(out, ns_of(clock_.now()));
      return {};
    case ECAT_PDI_MSG_LINES:
      if (length != 0) return fail(fmt::format("LINES with a {}-byte payload, not 0", length));
      append_lines(out, ECAT_PDI_MSG_LINES | ECAT_PDI_REPLY, 0);
      return {};
    default:
      return fail(fmt::format("unknown message type 0x{:02X}", type));
  }
}

}  // namespace ecat::pdi_host
