#include "coe/emergency.hpp"

#include "coe/coe_header.hpp"

namespace ecat::coe {

static_assert(Emergency::kPayloadSize <= MailboxServer::kMaxUnsolicitedPayload,
              "an emergency fits the unsolicited queue's slots");

Expected<void, MailboxError> Emergency::raise(std::uint16_t error_code, std::uint8_t error_register,
                                              const std::array<std::uint8_t, kManufacturerBytes>& manufacturer,
                                              Nanoseconds now) noexcept {
  (void)store_.set<std::uint8_t>(kErrorRegister, 0, error_register);
  if (history_) (void)history_->add(DiagnosisHistory::from_emergency(error_code), now);
  errors_.add(error_code, static_cast<std::uint16_t>(manufacturer[0] | (manufacturer[1] << 8)));
  const auto payload = message(error_code, error_register, manufacturer);
  auto queued = mailbox_.send(MailboxType::CoE, payload);
  if (queued) sent_.add({error_code, error_register});
  return queued;
}

std::array<std::uint8_t, Emergency::kPayloadSize> Emergency::message(
    std::uint16_t error_code, std::uint8_t error_register,
    const std::array<std::uint8_t, kManufacturerBytes>& manufacturer) noexcept {
  std::array<std::uint8_t, kPayloadSize> payload{};
  ByteWriter w(payload);
  CoeHeader::write(w, CoeService::Emergency);
  w.u16(error_code);
  w.u8(error_register);
  w.bytes(manufacturer);
  return payload;
}

}  // namespace ecat::coe
