#include "master/sdo_abort.hpp"

namespace ecat::master {

std::string_view describe(SdoAbortCode code) noexcept {
  switch (code) {
    case SdoAbortCode::None: return "no abort";
    case SdoAbortCode::ToggleBit: return "toggle bit not changed";
    case SdoAbortCode::Timeout: return "SDO protocol timeout";
    case SdoAbortCode::InvalidCommand: return "command specifier invalid";
    case SdoAbortCode::OutOfMemory: return "out of memory";
    case SdoAbortCode::UnsupportedAccess: return "unsupported access to an object";
    case SdoAbortCode::WriteOnly: return "attempt to read a write-only object";
    case SdoAbortCode::ReadOnly: return "attempt to write a read-only object";
    case SdoAbortCode::SubindexCannotBeWritten: return "subindex cannot be written, SI0 must be 0";
    case SdoAbortCode::CompleteAccessUnsupported: return "complete access not supported";
    case SdoAbortCode::ObjectTooLong: return "object length exceeds mailbox size";
    case SdoAbortCode::MappedToRxPdo: return "object mapped to RxPDO";
    case SdoAbortCode::ObjectNotFound: return "object does not exist";
    case SdoAbortCode::NotMappable: return "object cannot be mapped";
    case SdoAbortCode::PdoLengthExceeded: return "PDO length exceeded";
    case SdoAbortCode::ParameterIncompatible: return "parameter incompatibility";
    case SdoAbortCode::InternalIncompatible: return "internal incompatibility";
    case SdoAbortCode::HardwareError: return "hardware error";
    case SdoAbortCode::LengthMismatch: return "data length does not match";
    case SdoAbortCode::LengthTooHigh: return "data length too high";
    case SdoAbortCode::LengthTooLow: return "data length too low";
    case SdoAbortCode::SubindexNotFound: return "subindex does not exist";
    case SdoAbortCode::ValueRange: return "value range exceeded";
    case SdoAbortCode::ValueTooHigh: return "value too high";
    case SdoAbortCode::ValueTooLow: return "value too low";
    case SdoAbortCode::MaxLessThanMin: return "maximum less than minimum";
    case SdoAbortCode::GeneralError: return "general error";
    case SdoAbortCode::DataNotTransferred: return "data cannot be transferred";
    case SdoAbortCode::LocalControl: return "data cannot be transferred (local control)";
    case SdoAbortCode::DeviceState: return "data cannot be transferred (device state)";
    case SdoAbortCode::NoObjectDictionary: return "no object dictionary";
  }
  return "unknown abort code";
}

}  // namespace ecat::master
