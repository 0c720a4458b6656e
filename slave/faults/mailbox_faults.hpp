// The mailbox faults of slave::FaultCatalogue (docs/faults.md), as Beckhoff
// SSC's test application offers them to test masters: a frozen mailbox
// counter, replies held, every request answered with a mailbox error, replies
// cut to a few bytes, an emergency storm, a segmented upload that ends
// early, segment replies with the wrong toggle bit. Each sets or resets one
// switch of the slave's coe::MailboxServer or coe::SdoServer.
#pragma once

#include <cstdint>
#include <map>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "common/expected.hpp"

namespace ecat::coe {
class CoeServer;
}

namespace ecat::slave::faults {

enum class MailboxFault : std::uint8_t {
  CounterFrozen,   // mailbox_counter_frozen
  Held,            // mailbox_held
  ErrorReplies,    // mailbox_error_replies
  ReplyLimit,      // mailbox_reply_limit
  EmergencyStorm,  // emergency_storm
  UploadTruncated, // sdo_upload_truncated
  WrongToggle,     // sdo_toggle_wrong
};

// The fault of a catalogue kind name; nullopt for a kind that is not one of these.
std::optional<MailboxFault> mailbox_fault(std::string_view kind) noexcept;

// Checks the parameters (range messages name the kind) and switches the
// fault on; nothing changes when a check fails.
Expected<void, std::string> engage(MailboxFault fault, std::string_view kind, coe::CoeServer& coe,
                                   const std::map<std::string, std::int64_t>& params);
// Switches it off again (held replies go out, a storm stops, ...).
void clear(MailboxFault fault, coe::CoeServer& coe) noexcept;

}  // namespace ecat::slave::faults
