#include "coe/mailbox_header.hpp"

namespace ecat::coe {

std::string_view describe(MailboxError error) noexcept {
  switch (error) {
    case MailboxError::Syntax: return "Syntax of the mailbox header is wrong";
    case MailboxError::UnsupportedProtocol: return "Mailbox protocol not supported";
    case MailboxError::InvalidChannel: return "Channel field contains a wrong value";
    case MailboxError::ServiceNotSupported: return "Service in the mailbox protocol not supported";
    case MailboxError::InvalidHeader: return "Mailbox protocol header is wrong";
    case MailboxError::SizeTooShort: return "Length of received mailbox data is too short";
    case MailboxError::NoMoreMemory: return "Mailbox protocol cannot be processed: no more memory";
    case MailboxError::InvalidSize: return "Length of data is inconsistent";
  }
  return "unknown mailbox error";
}

std::optional<MailboxHeader> MailboxHeader::unpack(ConstBytes in) noexcept {
  ByteReader r(in);
  MailboxHeader h;
  h.length = r.u16();
  h.address = r.u16();
  const std::uint8_t b4 = r.u8();
  const std::uint8_t b5 = r.u8();
  if (!r.ok()) return std::nullopt;
  h.channel = b4 & kChannelMask;
  h.priority = static_cast<std::uint8_t>(b4 >> kPriorityShift);
  h.type = b5 & kTypeMask;
  h.counter = (b5 >> kCounterShift) & kCounterMask;
  h.reserved = (b5 & kReservedBit) != 0;
  return h;
}

void MailboxHeader::pack(Bytes out) const noexcept {
  ByteWriter w(out);
  w.u16(length);
  w.u16(address);
  w.u8(static_cast<std::uint8_t>((channel & kChannelMask) | (priority << kPriorityShift)));
  w.u8(static_cast<std::uint8_t>((type & kTypeMask) | ((counter & kCounterMask) << kCounterShift)));
}

}  // namespace ecat::coe
