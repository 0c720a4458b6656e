#include "coe/emergency.hpp"

#include "coe/coe_header.hpp"

namespace ecat::coe {

static_assert(Emergency::kPayloadSize <= MailboxServer::kMaxUnsolicitedPayload,
              "an emergency fits the unsolicited queue's slots");

Expected<void, MailboxError> Emergency::raise(std::uint16_t error_code, std::uint8_t error_register,
                                              const std::array<std::uint8_t, kManufacturerBytes>& manufacturer,
                                              Nanoseconds now) noexcept {
  (void)store_.set<std::uint8_t>(kErrorRegister, 0, error_register);
  record_diagnosis(error_code, now);
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

// Diagnosis message (ETG.1020 §13.3): DiagCode UDINT, Flags UINT, TextID UINT,
// TimeStamp ULINT; the emergency error code is the DiagCode's low word.
void Emergency::record_diagnosis(std::uint16_t error_code, Nanoseconds now) noexcept {
  const ObjectStore::Slot* max = store_.slot(kDiagnosisHistory, kDiagMaxMessages);
  if (!max) return;
  const std::uint8_t capacity = store_.get<std::uint8_t>(*max);
  if (capacity == 0) return;
  const std::uint8_t newest = store_.get<std::uint8_t>(kDiagnosisHistory, kDiagNewestMessage);
  std::uint8_t next = kDiagFirstMessage;
  if (newest >= kDiagFirstMessage && newest + 1 < kDiagFirstMessage + capacity) next = static_cast<std::uint8_t>(newest + 1);
  ObjectStore::Slot* message = store_.slot(kDiagnosisHistory, next);
  if (!message) return;
  std::uint8_t raw[16];
  ByteWriter w(raw);
  w.u32(error_code);
  w.u16(kDiagFlagsError);
  w.u16(0);
  w.u64(static_cast<std::uint64_t>(now.count()));
  const std::size_t n = std::min<std::size_t>(sizeof raw, message->capacity);
  if (!store_.assign(*message, {raw, n})) return;
  (void)store_.set<std::uint8_t>(kDiagnosisHistory, kDiagNewestMessage, next);
  (void)store_.set<std::uint8_t>(kDiagnosisHistory, kDiagNewMessagesAvailable, 1);
}

}  // namespace ecat::coe
