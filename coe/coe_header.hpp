// The 2-byte CoE header after the mailbox header (ETG.1000.6 §5.6.2;
// shared/spec/coe-mailbox.md §4): bits 8:0 number, bits 15:12 service.
#pragma once

#include <cstdint>

#include "common/le.hpp"

namespace ecat::coe {

enum class CoeService : std::uint8_t {
  Emergency = 1,
  SdoRequest = 2,
  SdoResponse = 3,
  TxPdo = 4,
  RxPdo = 5,
  TxPdoRemoteRequest = 6,
  RxPdoRemoteRequest = 7,
  SdoInformation = 8,
};

struct CoeHeader {
  static constexpr std::size_t kSize = 2;
  static constexpr unsigned kServiceShift = 12;
  static constexpr std::uint16_t kNumberMask = 0x01FF;

  std::uint16_t number = 0;
  std::uint8_t service = 0;  // CoeService value (raw, unknown ones kept)

  static CoeHeader unpack(std::uint16_t raw) noexcept {
    return {static_cast<std::uint16_t>(raw & kNumberMask), static_cast<std::uint8_t>(raw >> kServiceShift)};
  }
  static void write(ByteWriter& w, CoeService service, std::uint16_t number = 0) noexcept {
    w.u16(static_cast<std::uint16_t>((static_cast<unsigned>(service) << kServiceShift) | (number & kNumberMask)));
  }
};

}  // namespace ecat::coe
