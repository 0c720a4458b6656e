// SDO abort codes (ETG.1000.6 §5.6.2.7, CiA 301; coe-mailbox.md §6), as the
// master sees them. The coe/ layer has its own enum for the slave side; the
// layer rule keeps the master from including it.
#pragma once

#include <cstdint>
#include <string_view>

#include "master/master_error.hpp"

namespace ecat::master {

enum class SdoAbortCode : std::uint32_t {
  None = 0,
  ToggleBit = 0x05030000,
  Timeout = 0x05040000,
  InvalidCommand = 0x05040001,
  OutOfMemory = 0x05040005,
  UnsupportedAccess = 0x06010000,
  WriteOnly = 0x06010001,
  ReadOnly = 0x06010002,
  SubindexCannotBeWritten = 0x06010003,
  CompleteAccessUnsupported = 0x06010004,
  ObjectTooLong = 0x06010005,
  MappedToRxPdo = 0x06010006,
  ObjectNotFound = 0x06020000,
  NotMappable = 0x06040041,
  PdoLengthExceeded = 0x06040042,
  ParameterIncompatible = 0x06040043,
  InternalIncompatible = 0x06040047,
  HardwareError = 0x06060000,
  LengthMismatch = 0x06070010,
  LengthTooHigh = 0x06070012,
  LengthTooLow = 0x06070013,
  SubindexNotFound = 0x06090011,
  ValueRange = 0x06090030,
  ValueTooHigh = 0x06090031,
  ValueTooLow = 0x06090032,
  MaxLessThanMin = 0x06090036,
  GeneralError = 0x08000000,
  DataNotTransferred = 0x08000020,
  LocalControl = 0x08000021,
  DeviceState = 0x08000022,
  NoObjectDictionary = 0x08000023,
};

std::string_view describe(SdoAbortCode code) noexcept;

// Why an SDO transfer failed: the slave's abort code (from_slave), or a
// master-side failure with the abort code the master would report for it
// (e.g. Timeout 0x05040000) and its cause.
struct SdoError {
  SdoAbortCode code = SdoAbortCode::GeneralError;
  bool from_slave = false;
  MasterError cause = MasterError::InvalidResponse;

  static SdoError abort(SdoAbortCode c) noexcept { return SdoError{c, true, MasterError::InvalidResponse}; }
  static SdoError master(MasterError e) noexcept {
    const bool timeout = e == MasterError::MailboxTimeout || e == MasterError::Timeout;
    return SdoError{timeout ? SdoAbortCode::Timeout : SdoAbortCode::GeneralError, false, e};
  }
  friend bool operator==(const SdoError&, const SdoError&) = default;
};

}  // namespace ecat::master
