// CoE emergency (ETG.1000.6 §5.6.4, CiA 301 §7.2.7; shared/spec/coe-mailbox.md
// §9): an 8-byte message (error code, error register, 5 manufacturer bytes)
// sent unsolicited through the read mailbox. raise() also sets the error
// register 1001h, records the error in the pre-defined error field 1003h
// where the device has one (coe::ErrorField) and, if the device has one,
// appends a message to the diagnosis history 10F3h (coe::DiagnosisHistory,
// Diag Code E800h).
#pragma once

#include <array>
#include <cstdint>

#include "coe/diagnosis_history.hpp"
#include "coe/error_field.hpp"
#include "coe/mailbox_server.hpp"
#include "coe/object_store.hpp"
#include "coe/recent_log.hpp"
#include "common/clock.hpp"

namespace ecat::coe {

class Emergency {
 public:
  static constexpr std::uint16_t kErrorRegister = 0x1001;
  static constexpr std::size_t kPayloadSize = 2 + 8;  // CoE header + message
  static constexpr std::size_t kManufacturerBytes = 5;

  // `history`: the device's 10F3h (null or absent: no message is kept).
  Emergency(MailboxServer& mailbox, ObjectStore& store, DiagnosisHistory* history = nullptr)
      : mailbox_(mailbox), store_(store), history_(history), errors_(store) {}
  Emergency(const Emergency&) = delete;
  Emergency& operator=(const Emergency&) = delete;
  const ErrorField& error_field() const noexcept { return errors_; }

  // Queues the message; 1001h and 10F3h are updated even when the mailbox is
  // closed or full (the error is then returned: the message itself was not sent).
  Expected<void, MailboxError> raise(std::uint16_t error_code, std::uint8_t error_register,
                                     const std::array<std::uint8_t, kManufacturerBytes>& manufacturer = {},
                                     Nanoseconds now = Nanoseconds{0}) noexcept;

  // The mailbox payload of an emergency: CoE header (service 1) and the
  // 8-byte message (CiA 301 §7.2.7.3.1).
  static std::array<std::uint8_t, kPayloadSize> message(
      std::uint16_t error_code, std::uint8_t error_register,
      const std::array<std::uint8_t, kManufacturerBytes>& manufacturer = {}) noexcept;

  // The messages raise() queued (error code, error register), newest last:
  // what the control interface reports as "emergency" events.
  struct Sent {
    std::uint16_t error_code = 0;
    std::uint8_t error_register = 0;
  };
  static constexpr std::size_t kSentLogSize = 8;
  const RecentLog<Sent, kSentLogSize>& sent() const noexcept { return sent_; }

 private:
  MailboxServer& mailbox_;
  ObjectStore& store_;
  DiagnosisHistory* history_;
  ErrorField errors_;  // 1003h (hooks on the store: not copyable)
  RecentLog<Sent, kSentLogSize> sent_;
};

}  // namespace ecat::coe
