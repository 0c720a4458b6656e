// The diagnosis history 10F3h (ETG.1020 §13 "Diagnosis handling"; the
// object as Beckhoff's and WAGO's manuals describe it): a ring of diagnosis
// messages in subindices 6.., each
//   Diag Code (UDINT) | Flags (UINT) | Text ID (UINT) | Time Stamp (ULINT, ns) |
//   per parameter: flags (UINT, bits 0-11 data type index) + value,
// with subindex 1 the ring's size, 2 the newest message's subindex, 3 the
// newest acknowledged one (written by the master), 4 "new messages
// available" and 5 the flags (bit 0 emergency on new message, bits 1-3
// disable info/warning/error messages, bit 4 acknowledge mode instead of
// overwrite mode, bit 5 overflow, read-only). The CoE side adds messages
// (from emergencies, AL errors); the master reads, acknowledges and clears
// through the SDO server, whose writes and reads come here as hooks. The
// time stamps are the slave's local time (message flags bit 4), which
// 10F8h "Actual Time Stamp" shows now, so a master can tell a message's age
// (WAGO 765-1205 manual; docs/coe.md "Diagnosis history" names the sources).
// docs/coe.md "Diagnosis history" has the decisions where the material at
// hand is silent.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "coe/object_hooks.hpp"
#include "common/clock.hpp"

namespace ecat::coe {

class ObjectStore;

class DiagnosisHistory final : public ObjectHooks {
 public:
  static constexpr std::uint16_t kIndex = 0x10F3;
  static constexpr std::uint8_t kMaxMessages = 1;
  static constexpr std::uint8_t kNewestMessage = 2;
  static constexpr std::uint8_t kNewestAcknowledged = 3;
  static constexpr std::uint8_t kNewMessagesAvailable = 4;
  static constexpr std::uint8_t kFlags = 5;
  static constexpr std::uint8_t kFirstMessage = 6;
  // 10F3h:05 bits.
  static constexpr std::uint16_t kFlagEmergency = 0x0001;
  static constexpr std::uint16_t kFlagDisableInfo = 0x0002;
  static constexpr std::uint16_t kFlagDisableWarning = 0x0004;
  static constexpr std::uint16_t kFlagDisableError = 0x0008;
  static constexpr std::uint16_t kFlagAcknowledgeMode = 0x0010;
  static constexpr std::uint16_t kFlagOverflow = 0x0020;  // read-only
  static constexpr std::uint16_t kFlagsWritable = 0x001F;
  // Diag Code low words: 0xE000-0xE7FF manufacturer, 0xE800 an emergency
  // (its error code in bits 16-31), 0xEE00-0xEFFF profile.
  static constexpr std::uint32_t kDiagCodeEmergency = 0xE800;
  // ecatslave's own code in the manufacturer range: an AL status error,
  // the AL status code in bits 16-31 (docs/coe.md).
  static constexpr std::uint32_t kDiagCodeAlStatus = 0xE001;
  // Message flags: bits 0-3 type, bit 4 local time stamp, bits 8-15 parameters.
  static constexpr std::uint16_t kMessageLocalTimeStamp = 0x0010;
  // 10F8h Actual Time Stamp (UINT64, ns): the local time the stamps count in.
  static constexpr std::uint16_t kActualTimeStampIndex = 0x10F8;
  static constexpr unsigned kParameterCountShift = 8;
  // Parameter flags: the CoE data type index of the value.
  static constexpr std::uint16_t kTypeUnsigned8 = 0x0005;
  static constexpr std::uint16_t kTypeUnsigned16 = 0x0006;
  static constexpr std::uint16_t kTypeUnsigned32 = 0x0007;
  static constexpr std::size_t kHeaderBytes = 4 + 2 + 2 + 8;
  static constexpr std::size_t kMaxParameters = 3;

  enum class Type : std::uint8_t { Info = 0, Warning = 1, Error = 2 };

  struct Parameter {
    std::uint16_t data_type = kTypeUnsigned16;  // one of kTypeUnsigned8/16/32
    std::uint32_t value = 0;
  };
  struct Message {
    std::uint32_t diag_code = 0;
    Type type = Type::Error;
    std::uint16_t text_id = 0;  // 0: none
    std::array<Parameter, kMaxParameters> parameters{};
    std::size_t parameter_count = 0;
  };

  // A message for an emergency: Diag Code E800h with the error code above it.
  static Message from_emergency(std::uint16_t error_code) noexcept;
  // A message for an AL status error, with the code as a UINT16 parameter.
  static Message from_al_status(std::uint16_t al_status_code) noexcept;
  // The bytes of a message as they are stored in its subindex.
  static std::size_t encode(const Message& m, Nanoseconds time_stamp, Bytes out) noexcept;

  // Takes 10F3h of `store` if the device has it (present()), and registers
  // itself as the object's hooks.
  explicit DiagnosisHistory(ObjectStore& store) noexcept;
  bool present() const noexcept { return capacity_ > 0; }
  // The slave's local time now (CoeServer::poll, before requests are
  // served): what a read of 10F8h returns.
  void set_time(Nanoseconds now) noexcept { now_ = now; }

  // Stores a message unless its type is disabled (10F3h:05 bits 1-3) or, in
  // acknowledge mode, the ring is full of unacknowledged messages (then the
  // overflow flag is set). Returns whether it was stored; `emergency`, when
  // given, is told whether 10F3h:05 bit 0 asks for an emergency as well.
  bool add(const Message& m, Nanoseconds now, bool* emergency = nullptr) noexcept;

  // ObjectHooks: 10F3h:03 (acknowledge, 0 clears), 10F3h:05 (flags), a read
  // of the newest message (overwrite mode: no longer new), a read of 10F8h.
  void on_read(ObjectStore& store, std::uint16_t index, std::uint8_t subindex) noexcept override;
  Expected<void, SdoAbort> on_write(ObjectStore& store, const WriteRequest& request) noexcept override;
  void after_write(ObjectStore& store, std::uint16_t index, std::uint8_t subindex) noexcept override;

 private:
  std::uint8_t subindex_of(std::size_t slot) const noexcept { return static_cast<std::uint8_t>(kFirstMessage + slot); }
  std::uint16_t flags() const noexcept;
  void set_flags(std::uint16_t f) noexcept;
  void clear_all() noexcept;
  void publish_state() noexcept;  // subindices 2, 3 and 4 from the ring's state

  ObjectStore& store_;
  std::size_t capacity_ = 0;           // messages (10F3h:01, limited to the subindices present)
  std::vector<std::uint64_t> seq_;     // per slot: the message's number (0: empty)
  std::uint64_t next_seq_ = 1;
  std::size_t newest_ = 0;             // slot of the newest message (valid when newest_seq_ > 0)
  std::uint64_t newest_seq_ = 0;
  std::uint64_t acknowledged_seq_ = 0;  // messages up to this number are acknowledged
  bool newest_read_ = false;           // overwrite mode: the newest message was read
  bool overwritten_ack_ = false;       // overwrite mode: the acknowledged one was overwritten (SI3 reads 0)
  bool overflow_ = false;              // 10F3h:05 bit 5
  Nanoseconds now_{0};                 // for 10F8h
};

}  // namespace ecat::coe
