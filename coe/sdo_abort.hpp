// SDO abort codes (CiA 301 §7.2.4.3.17, ETG.1000.6 Table 41;
// shared/spec/coe-mailbox.md §6). An SDO transfer that fails ends with one of
// these in an abort frame; SDO information reports them in its error reply.
#pragma once

#include <cstdint>
#include <string_view>

namespace ecat::coe {

enum class SdoAbort : std::uint32_t {
  ToggleBit = 0x05030000,
  Timeout = 0x05040000,
  CommandSpecifier = 0x05040001,
  InvalidBlockSize = 0x05040002,
  InvalidSequenceNumber = 0x05040003,
  CrcError = 0x05040004,
  OutOfMemory = 0x05040005,
  UnsupportedAccess = 0x06010000,
  WriteOnly = 0x06010001,
  ReadOnly = 0x06010002,
  SubindexZeroMustBeZero = 0x06010003,
  CompleteAccessVariableLength = 0x06010004,
  ObjectLengthExceedsMailbox = 0x06010005,
  MappedToRxPdo = 0x06010006,
  NoObject = 0x06020000,
  NotMappable = 0x06040041,
  PdoLengthExceeded = 0x06040042,
  ParameterIncompatibility = 0x06040043,
  InternalIncompatibility = 0x06040047,
  HardwareError = 0x06060000,
  LengthMismatch = 0x06070010,
  LengthTooHigh = 0x06070012,
  LengthTooLow = 0x06070013,
  NoSubindex = 0x06090011,
  ValueRange = 0x06090030,
  ValueTooHigh = 0x06090031,
  ValueTooLow = 0x06090032,
  ModuleListMismatch = 0x06090033,
  MaxLessThanMin = 0x06090036,
  ResourceNotAvailable = 0x060A0023,
  GeneralError = 0x08000000,
  DataTransfer = 0x08000020,
  DataTransferLocalControl = 0x08000021,
  DataTransferDeviceState = 0x08000022,
  NoObjectDictionary = 0x08000023,
  NoData = 0x08000024,
};

// The CiA 301 text of the code ("Toggle bit not alternated"); "unknown SDO
// abort code" for values outside the table.
std::string_view describe(SdoAbort code) noexcept;

constexpr std::uint32_t to_u32(SdoAbort code) noexcept { return static_cast<std::uint32_t>(code); }

}  // namespace ecat::coe
