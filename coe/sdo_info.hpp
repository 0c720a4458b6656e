// SDO information service (ETG.1000.6 §5.6.3; shared/spec/coe-mailbox.md §7):
// get OD list (all / RxPDO-mappable / TxPDO-mappable / backup / settings, and
// list type 0 = the five counts), get object description, get entry
// description with value info, and the info error reply. Long lists go out
// in fragments (incomplete bit + fragments left), one per free read mailbox.
// Names, types and access bits come from the same od model the ESI writer
// uses, so the two cannot disagree.
#pragma once

#include <cstdint>

#include "coe/mailbox_header.hpp"
#include "coe/object_store.hpp"
#include "coe/sdo_abort.hpp"
#include "common/expected.hpp"
#include "common/le.hpp"
#include "od/access.hpp"

namespace ecat::coe {

namespace info {
inline constexpr std::uint8_t kGetOdListRequest = 0x01;
inline constexpr std::uint8_t kGetOdListResponse = 0x02;
inline constexpr std::uint8_t kGetObjectDescriptionRequest = 0x03;
inline constexpr std::uint8_t kGetObjectDescriptionResponse = 0x04;
inline constexpr std::uint8_t kGetEntryDescriptionRequest = 0x05;
inline constexpr std::uint8_t kGetEntryDescriptionResponse = 0x06;
inline constexpr std::uint8_t kErrorRequest = 0x07;
inline constexpr std::uint8_t kOpcodeMask = 0x7F;
inline constexpr std::uint8_t kIncomplete = 0x80;
inline constexpr std::size_t kHeaderSize = 4;  // opcode, reserved, fragments left

enum class ListType : std::uint16_t { Counts = 0, All = 1, RxPdoMappable = 2, TxPdoMappable = 3, Backup = 4, Settings = 5 };
inline constexpr std::size_t kListTypeCount = 5;  // lists 1..5, reported by list type 0

// Value info bits of the entry description (ETG.1000.6 §5.6.3.6.1).
inline constexpr std::uint8_t kValueInfoAccess = 1u << 0;
inline constexpr std::uint8_t kValueInfoCategory = 1u << 1;
inline constexpr std::uint8_t kValueInfoMappable = 1u << 2;
inline constexpr std::uint8_t kValueInfoUnit = 1u << 3;
inline constexpr std::uint8_t kValueInfoDefault = 1u << 4;
inline constexpr std::uint8_t kValueInfoMinimum = 1u << 5;
inline constexpr std::uint8_t kValueInfoMaximum = 1u << 6;
inline constexpr std::uint16_t kObjectAccessMask = 0x03FF;  // bits 15:10 reserved
}  // namespace info

class SdoInfo {
 public:
  explicit SdoInfo(ObjectStore& store) : store_(store) {}

  // `request`: bytes after the CoE header. Writes the CoE reply (CoE header
  // included); returns its length.
  Expected<std::size_t, MailboxError> handle(ConstBytes request, Bytes reply) noexcept;
  // The next fragment of a long OD list, or 0.
  std::size_t next_fragment(Bytes reply) noexcept;
  void reset() noexcept { pending_ = false; }
  bool busy() const noexcept { return pending_; }

  // Whether `object` belongs to list `type` (1..5).
  static bool in_list(const od::Object& object, info::ListType type) noexcept;

 private:
  std::size_t od_list(ByteReader& r, Bytes reply) noexcept;
  std::size_t object_description(ByteReader& r, Bytes reply) noexcept;
  std::size_t entry_description(ByteReader& r, Bytes reply) noexcept;
  std::size_t error(Bytes reply, SdoAbort code) noexcept;
  std::size_t write_list_fragment(Bytes reply, bool first) noexcept;

  ObjectStore& store_;
  bool pending_ = false;
  info::ListType list_ = info::ListType::All;
  std::size_t position_ = 0;  // next object in dictionary order
  std::uint16_t fragments_left_ = 0;
};

}  // namespace ecat::coe
