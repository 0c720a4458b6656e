#include "apps/ecat-master/pdo_locator.hpp"

#include <fmt/format.h>

#include "apps/ecat-master/error_text.hpp"

namespace ecat::app {
namespace {

constexpr unsigned kIndexShift = 16;
constexpr unsigned kSubindexShift = 8;
constexpr std::uint32_t kByteMask = 0xFF;
constexpr std::uint32_t kBitsPerByte = 8;

Expected<std::vector<MappedObject>, std::string> read_side(master::CoeClient& coe, std::uint16_t assign) {
  std::vector<MappedObject> out;
  auto pdos = coe.read_pdo_assignment(assign);
  // A device without process data on this side need not have the assignment
  // object (1C12h/1C13h) at all: its abort "object does not exist" means no
  // PDOs on this side, not a failure of the device.
  if (!pdos && pdos.error().from_slave && pdos.error().code == master::SdoAbortCode::ObjectNotFound) return out;
  if (!pdos) return fail(fmt::format("reading {:04X}h: {}", assign, error_text(pdos.error())));
  std::uint32_t offset = 0;
  for (std::uint16_t pdo : *pdos) {
    auto entries = coe.read_pdo_mapping(pdo);
    if (!entries) return fail(fmt::format("reading {:04X}h: {}", pdo, error_text(entries.error())));
    for (std::uint32_t e : *entries) {
      MappedObject m;
      m.index = static_cast<std::uint16_t>(e >> kIndexShift);
      m.subindex = static_cast<std::uint8_t>((e >> kSubindexShift) & kByteMask);
      m.bits = static_cast<std::uint8_t>(e & kByteMask);
      m.bit_offset = offset;
      offset += m.bits;
      out.push_back(m);
    }
  }
  return out;
}

std::optional<std::uint32_t> byte_of(const std::vector<MappedObject>& side, std::uint16_t index,
                                     std::uint8_t subindex) {
  for (const auto& m : side) {
    if (m.index == index && m.subindex == subindex && m.bit_offset % kBitsPerByte == 0) {
      return m.bit_offset / kBitsPerByte;
    }
  }
  return std::nullopt;
}

}  // namespace

Expected<PdoLocator, std::string> PdoLocator::read(master::CoeClient& coe) {
  PdoLocator l;
  auto out = read_side(coe, master::coe::kRxPdoAssign);
  if (!out) return fail(out.error());
  auto in = read_side(coe, master::coe::kTxPdoAssign);
  if (!in) return fail(in.error());
  l.outputs = std::move(*out);
  l.inputs = std::move(*in);
  return l;
}

std::optional<std::uint32_t> PdoLocator::output_byte(std::uint16_t index, std::uint8_t subindex) const {
  return byte_of(outputs, index, subindex);
}

std::optional<std::uint32_t> PdoLocator::input_byte(std::uint16_t index, std::uint8_t subindex) const {
  return byte_of(inputs, index, subindex);
}

}  // namespace ecat::app
