#include "master/master_error.hpp"

namespace ecat::master {

std::string_view describe(MasterError e) noexcept {
  switch (e) {
    case MasterError::Transport: return "transport error";
    case MasterError::Timeout: return "no reply (timeout)";
    case MasterError::WorkingCounter: return "unexpected working counter";
    case MasterError::InvalidFrame: return "frame could not be built";
    case MasterError::NoSlaves: return "no slaves found";
    case MasterError::TooManySlaves: return "too many slaves";
    case MasterError::SiiTimeout: return "SII interface busy (timeout)";
    case MasterError::SiiError: return "SII interface error";
    case MasterError::SiiInvalid: return "SII content malformed";
    case MasterError::StateTimeout: return "AL state not reached (timeout)";
    case MasterError::NoMailbox: return "slave has no mailbox";
    case MasterError::MailboxTimeout: return "no mailbox reply (timeout)";
    case MasterError::MailboxFull: return "write mailbox stays full";
    case MasterError::MailboxErrorReply: return "mailbox error reply";
    case MasterError::InvalidResponse: return "unexpected response";
    case MasterError::InvalidArgument: return "invalid argument";
    case MasterError::NotConfigured: return "not configured";
    case MasterError::WrongSlave: return "another device answers at this position";
    case MasterError::Sync0StartMissed: return "0x0990 read back behind 0x0910 after every SYNC0 activation (start time missed)";
  }
  return "unknown master error";
}

}  // namespace ecat::master
