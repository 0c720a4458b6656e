// Why a master operation failed, as a value (STYLE lesson 6). Slave-reported
// outcomes (a refused state change with its AL status code, an SDO abort code,
// a mailbox error reply) travel in their own types next to these.
#pragma once

#include <cstdint>
#include <string_view>

namespace ecat::master {

enum class MasterError : std::uint8_t {
  Transport = 1,       // the transport failed to send or receive
  Timeout,             // no matching reply frame within the frame timeout and retries
  WorkingCounter,      // reply arrived with an unexpected working counter
  InvalidFrame,        // a frame could not be built (too large)
  NoSlaves,            // BRD 0x0000 returned WKC 0
  TooManySlaves,       // more slaves than the configured maximum
  SiiTimeout,          // SII interface stayed busy (0x0502 bit 15)
  SiiError,            // SII error bits 11/13/14 set after a command
  SiiInvalid,          // SII image malformed (category walk, sizes)
  StateTimeout,        // AL status did not reach the requested state in time
  NoMailbox,           // slave has no mailbox (SII words 0x18-0x1B are 0)
  MailboxTimeout,      // no reply in the read mailbox (SM1) in time
  MailboxFull,         // write mailbox (SM0) stayed full
  MailboxErrorReply,   // slave answered with a mailbox error reply (type 0)
  InvalidResponse,     // reply of the wrong type/service/index
  InvalidArgument,     // caller error (slave position, sizes)
  NotConfigured,       // operation needs a step not done yet (scan, mailbox, PDO layout)
  WrongSlave,          // another device than the one scanned answers at a position (identity differs)
  Sync0StartMissed,    // the SYNC0 start time had passed when the unit was activated, at every attempt
};

std::string_view describe(MasterError e) noexcept;

}  // namespace ecat::master
