#include "slave/faults/mailbox_faults.hpp"

#include <fmt/format.h>

#include "coe/coe_server.hpp"
#include "coe/emergency.hpp"

namespace ecat::slave::faults {
namespace {

// Defaults (docs/faults.md): an error reply says "unsupported protocol"; a
// storm is 100 emergencies of the generic manufacturer code FF00h with the
// manufacturer bit of 1001h (CiA 301 Table 21, bit 7).
constexpr std::int64_t kDefaultErrorCode = static_cast<std::int64_t>(coe::MailboxError::UnsupportedProtocol);
constexpr std::int64_t kDefaultStormCount = 100;
constexpr std::int64_t kDefaultStormCode = 0xFF00;
constexpr std::int64_t kDefaultStormRegister = 0x80;
constexpr std::int64_t kMaxCount = 1'000'000'000;
constexpr std::int64_t kMaxReplyLimit = 0xFFFF;

std::int64_t param(const std::map<std::string, std::int64_t>& p, const char* name, std::int64_t fallback) {
  const auto it = p.find(name);
  return it == p.end() ? fallback : it->second;
}

Expected<void, std::string> in_range(std::string_view kind, const std::map<std::string, std::int64_t>& p,
                                     const char* name, std::int64_t lo, std::int64_t hi) {
  const auto it = p.find(name);
  if (it == p.end() || (it->second >= lo && it->second <= hi)) return {};
  return fail(fmt::format("{}: {} = {} is out of range ({}..{})", kind, name, it->second, lo, hi));
}

}  // namespace

std::optional<MailboxFault> mailbox_fault(std::string_view kind) noexcept {
  if (kind == "mailbox_counter_frozen") return MailboxFault::CounterFrozen;
  if (kind == "mailbox_held") return MailboxFault::Held;
  if (kind == "mailbox_error_replies") return MailboxFault::ErrorReplies;
  if (kind == "mailbox_reply_limit") return MailboxFault::ReplyLimit;
  if (kind == "emergency_storm") return MailboxFault::EmergencyStorm;
  if (kind == "sdo_upload_truncated") return MailboxFault::UploadTruncated;
  if (kind == "sdo_toggle_wrong") return MailboxFault::WrongToggle;
  return std::nullopt;
}

Expected<void, std::string> engage(MailboxFault fault, std::string_view kind, coe::CoeServer& coe,
                                   const std::map<std::string, std::int64_t>& params) {
  coe::MailboxServer& mbx = coe.mailbox();
  switch (fault) {
    case MailboxFault::CounterFrozen:
      mbx.set_counter_frozen(true);
      break;
    case MailboxFault::Held:
      mbx.set_replies_held(true);
      break;
    case MailboxFault::ErrorReplies: {
      constexpr auto kFirst = static_cast<std::int64_t>(coe::MailboxError::Syntax);
      constexpr auto kLast = static_cast<std::int64_t>(coe::MailboxError::InvalidSize);
      if (auto ok = in_range(kind, params, "code", kFirst, kLast); !ok) return ok;
      if (auto ok = in_range(kind, params, "count", 0, kMaxCount); !ok) return ok;
      mbx.set_error_replies(static_cast<coe::MailboxError>(param(params, "code", kDefaultErrorCode)),
                            static_cast<std::uint64_t>(param(params, "count", 0)));
      break;
    }
    case MailboxFault::ReplyLimit:
      if (auto ok = in_range(kind, params, "bytes", static_cast<std::int64_t>(coe::MailboxServer::kMinReplyLimit),
                             kMaxReplyLimit);
          !ok) {
        return ok;
      }
      mbx.set_reply_limit(static_cast<std::size_t>(param(params, "bytes", 0)));
      break;
    case MailboxFault::EmergencyStorm: {
      if (auto ok = in_range(kind, params, "count", 1, kMaxCount); !ok) return ok;
      if (auto ok = in_range(kind, params, "code", 0, 0xFFFF); !ok) return ok;
      if (auto ok = in_range(kind, params, "error_register", 0, 0xFF); !ok) return ok;
      const auto message =
          coe::Emergency::message(static_cast<std::uint16_t>(param(params, "code", kDefaultStormCode)),
                                  static_cast<std::uint8_t>(param(params, "error_register", kDefaultStormRegister)));
      (void)mbx.set_unsolicited_storm(coe::MailboxType::CoE, message,
                                      static_cast<std::uint64_t>(param(params, "count", kDefaultStormCount)));
      break;
    }
    case MailboxFault::UploadTruncated:
      coe.sdo().set_upload_truncated(true);
      break;
    case MailboxFault::WrongToggle:
      coe.sdo().set_wrong_toggle(true);
      break;
  }
  return {};
}

void clear(MailboxFault fault, coe::CoeServer& coe) noexcept {
  coe::MailboxServer& mbx = coe.mailbox();
  switch (fault) {
    case MailboxFault::CounterFrozen: mbx.set_counter_frozen(false); break;
    case MailboxFault::Held: mbx.set_replies_held(false); break;
    case MailboxFault::ErrorReplies: mbx.set_error_replies(std::nullopt); break;
    case MailboxFault::ReplyLimit: mbx.set_reply_limit(0); break;
    case MailboxFault::EmergencyStorm: (void)mbx.set_unsolicited_storm(coe::MailboxType::CoE, {}, 0); break;
    case MailboxFault::UploadTruncated: coe.sdo().set_upload_truncated(false); break;
    case MailboxFault::WrongToggle: coe.sdo().set_wrong_toggle(false); break;
  }
}

}  // namespace ecat::slave::faults
