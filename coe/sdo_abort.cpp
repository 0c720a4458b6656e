#include "coe/sdo_abort.hpp"

namespace ecat::coe {

std::string_view describe(SdoAbort code) noexcept {
  switch (code) {
    case SdoAbort::ToggleBit: return "Toggle bit not alternated";
    case SdoAbort::Timeout: return "SDO protocol timed out";
    case SdoAbort::CommandSpecifier: return "Client/server command specifier not valid or unknown";
    case SdoAbort::InvalidBlockSize: return "Invalid block size";
    case SdoAbort::InvalidSequenceNumber: return "Invalid sequence number";
    case SdoAbort::CrcError: return "CRC error";
    case SdoAbort::OutOfMemory: return "Out of memory";
    case SdoAbort::UnsupportedAccess: return "Unsupported access to an object";
    case SdoAbort::WriteOnly: return "Attempt to read a write only object";
    case SdoAbort::ReadOnly: return "Attempt to write a read only object";
    case SdoAbort::SubindexZeroMustBeZero:
      return "Subindex cannot be written, SI0 must be 0 for write access";
    case SdoAbort::CompleteAccessVariableLength:
      return "SDO complete access not supported for objects of variable length";
    case SdoAbort::ObjectLengthExceedsMailbox: return "Object length exceeds mailbox size";
    case SdoAbort::MappedToRxPdo: return "Object mapped to RxPDO, SDO download blocked";
    case SdoAbort::NoObject: return "The object does not exist in the object dictionary";
    case SdoAbort::NotMappable: return "The object cannot be mapped into the PDO";
    case SdoAbort::PdoLengthExceeded:
      return "The number and length of the objects to be mapped would exceed the PDO length";
    case SdoAbort::ParameterIncompatibility: return "General parameter incompatibility reason";
    case SdoAbort::InternalIncompatibility: return "General internal incompatibility in the device";
    case SdoAbort::HardwareError: return "Access failed due to a hardware error";
    case SdoAbort::LengthMismatch:
      return "Data type does not match, length of service parameter does not match";
    case SdoAbort::LengthTooHigh: return "Data type does not match, length of service parameter too high";
    case SdoAbort::LengthTooLow: return "Data type does not match, length of service parameter too low";
    case SdoAbort::NoSubindex: return "Subindex does not exist";
    case SdoAbort::ValueRange: return "Value range of parameter exceeded (only for write access)";
    case SdoAbort::ValueTooHigh: return "Value of parameter written too high";
    case SdoAbort::ValueTooLow: return "Value of parameter written too low";
    case SdoAbort::ModuleListMismatch: return "Configured module list does not match detected module list";
    case SdoAbort::MaxLessThanMin: return "Maximum value is less than minimum value";
    case SdoAbort::ResourceNotAvailable: return "Resource not available: SDO connection";
    case SdoAbort::GeneralError: return "General error";
    case SdoAbort::DataTransfer: return "Data cannot be transferred or stored to the application";
    case SdoAbort::DataTransferLocalControl:
      return "Data cannot be transferred or stored to the application because of local control";
    case SdoAbort::DataTransferDeviceState:
      return "Data cannot be transferred or stored to the application because of the present device "
             "state";
    case SdoAbort::NoObjectDictionary:
      return "Object dictionary dynamic generation fails or no object dictionary is present";
    case SdoAbort::NoData: return "No data available";
  }
  return "unknown SDO abort code";
}

}  // namespace ecat::coe
