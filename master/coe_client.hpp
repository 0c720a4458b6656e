// CoE over the mailbox for one slave (ETG.1000.6 §5.6; coe-mailbox.md §4-§11):
// SDO upload/download (expedited, normal, segmented, complete access), SDO
// Information (OD list, object and entry description, fragments reassembled),
// and PDO mapping/assignment the IgH way (sub 0 = 0, entries, sub 0 = n).
// Emergencies that arrive while waiting for an answer are kept, not fatal.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "common/expected.hpp"
#include "master/master.hpp"
#include "master/sdo_abort.hpp"

namespace ecat::master {

namespace coe {
inline constexpr std::size_t kCoeHeaderSize = 2;
inline constexpr std::size_t kSdoHeaderSize = 8;  // command, index, subindex, 4 data bytes
inline constexpr unsigned kServiceShift = 12;
inline constexpr std::uint8_t kServiceEmergency = 1;
inline constexpr std::uint8_t kServiceSdoRequest = 2;
inline constexpr std::uint8_t kServiceSdoResponse = 3;
inline constexpr std::uint8_t kServiceSdoInfo = 8;
// Command specifier bytes (coe-mailbox.md §5.1).
inline constexpr std::uint8_t kDownloadExpedited = 0x23;  // | (4 - n) << 2
inline constexpr std::uint8_t kDownloadNormal = 0x21;
inline constexpr std::uint8_t kUploadRequest = 0x40;
inline constexpr std::uint8_t kUploadSegmentRequest = 0x60;
inline constexpr std::uint8_t kAbort = 0x80;
inline constexpr std::uint8_t kCompleteAccess = 0x10;
inline constexpr std::uint8_t kToggle = 0x10;
inline constexpr std::uint8_t kLastSegment = 0x01;
inline constexpr std::uint8_t kSizeIndicated = 0x01;
inline constexpr std::uint8_t kExpedited = 0x02;
inline constexpr unsigned kSpecifierShift = 5;
inline constexpr std::uint8_t kScsUploadSegment = 0;
inline constexpr std::uint8_t kScsDownloadSegment = 1;
inline constexpr std::uint8_t kScsUploadInitiate = 2;
inline constexpr std::uint8_t kScsDownloadInitiate = 3;
inline constexpr std::size_t kMinSegmentData = 7;
// SDO Information opcodes (coe-mailbox.md §7).
inline constexpr std::uint8_t kInfoGetOdList = 0x01;
inline constexpr std::uint8_t kInfoGetObjectDescription = 0x03;
inline constexpr std::uint8_t kInfoGetEntryDescription = 0x05;
inline constexpr std::uint8_t kInfoError = 0x07;
inline constexpr std::uint8_t kInfoIncomplete = 0x80;
inline constexpr std::uint8_t kInfoOpcodeMask = 0x7F;
inline constexpr std::size_t kInfoHeaderSize = 4;
inline constexpr std::uint16_t kListAll = 1;
// Value-info bits of Get Entry Description.
inline constexpr std::uint8_t kValueInfoUnit = 0x08;
inline constexpr std::uint8_t kValueInfoDefault = 0x10;
inline constexpr std::uint8_t kValueInfoMinimum = 0x20;
inline constexpr std::uint8_t kValueInfoMaximum = 0x40;
// PDO objects.
inline constexpr std::uint16_t kSmPdoAssignBase = 0x1C10;  // + SM number (ETG.1000.6 §5.6.7.4.2)
inline constexpr std::uint16_t kRxPdoAssign = 0x1C12;
inline constexpr std::uint16_t kTxPdoAssign = 0x1C13;
inline constexpr std::uint16_t kSmCommunicationType = 0x1C00;
}  // namespace coe

struct ObjectDescription {
  std::uint16_t index = 0;
  std::uint16_t data_type = 0;
  std::uint8_t max_subindex = 0;
  std::uint8_t object_code = 0;
  std::string name;
};

struct EntryDescription {
  std::uint16_t index = 0;
  std::uint8_t subindex = 0;
  std::uint8_t value_info = 0;
  std::uint16_t data_type = 0;
  std::uint16_t bit_length = 0;
  std::uint16_t access = 0;
  std::vector<std::uint8_t> value_data;  // unit/default/min/max as requested, raw
  std::string name;
};

struct Emergency {
  std::uint16_t error_code = 0;
  std::uint8_t error_register = 0;
  std::array<std::uint8_t, 5> data{};
};

class CoeClient {
 public:
  // The object an SDO initiate request names: its reply must name it too.
  struct SdoAddress {
    std::uint16_t index;
    std::uint8_t subindex;
  };

  CoeClient(Master& master, std::size_t slave) noexcept : master_(master), slave_(slave) {}

  Expected<std::vector<std::uint8_t>, SdoError> upload(std::uint16_t index, std::uint8_t subindex,
                                                       bool complete_access = false);
  Expected<void, SdoError> download(std::uint16_t index, std::uint8_t subindex, ConstBytes data,
                                    bool complete_access = false);
  // Expedited download with exactly `size` bytes of `value` (size 1..4).
  Expected<void, SdoError> download_value(std::uint16_t index, std::uint8_t subindex, std::uint32_t value,
                                          std::size_t size);
  // Upload that must return 1..4 bytes; returns them as a little-endian number.
  Expected<std::uint32_t, SdoError> upload_value(std::uint16_t index, std::uint8_t subindex);

  Expected<std::vector<std::uint16_t>, SdoError> od_list(std::uint16_t list_type = coe::kListAll);
  Expected<ObjectDescription, SdoError> object_description(std::uint16_t index);
  Expected<EntryDescription, SdoError> entry_description(std::uint16_t index, std::uint8_t subindex,
                                                         std::uint8_t value_info = 0x07);

  // PDO mapping object (0x16xx/0x1Axx): sub 0 = 0, sub 1..n = entries, sub 0 = n.
  Expected<void, SdoError> write_pdo_mapping(std::uint16_t pdo, std::span<const std::uint32_t> entries);
  // PDO assignment (0x1C12/0x1C13): sub 0 = 0, sub 1..n = PDO indices, sub 0 = n.
  Expected<void, SdoError> write_pdo_assignment(std::uint16_t assign, std::span<const std::uint16_t> pdos);
  Expected<std::vector<std::uint16_t>, SdoError> read_pdo_assignment(std::uint16_t assign);
  Expected<std::vector<std::uint32_t>, SdoError> read_pdo_mapping(std::uint16_t pdo);
  // Sum of the entry bit lengths of every PDO assigned in `assign`.
  Expected<std::uint32_t, SdoError> assigned_bits(std::uint16_t assign);
  // Fills the slave's process-data sizes: per SM from 1C10h+n for every SII
  // SM of type 3/4 (pd.sms, pd.per_sm), else pd.output_bytes/input_bytes
  // from 0x1C12/0x1C13.
  Expected<void, SdoError> read_pdo_sizes();

  const std::vector<Emergency>& emergencies() const noexcept { return emergencies_; }
  // SDO replies dropped because they answered an earlier request (late
  // answers of a request that timed out), since this client was made.
  std::size_t stale_replies() const noexcept { return stale_replies_; }

  // Builds the SDO request payloads (CoE header onward) the client sends; public
  // so tests can check the exact bytes.
  static std::array<std::uint8_t, coe::kCoeHeaderSize + coe::kSdoHeaderSize> upload_request(
      std::uint16_t index, std::uint8_t subindex, bool complete_access) noexcept;
  static std::array<std::uint8_t, coe::kCoeHeaderSize + coe::kSdoHeaderSize> expedited_download_request(
      std::uint16_t index, std::uint8_t subindex, std::uint32_t value, std::size_t size, bool complete_access) noexcept;

 private:
  // Sends `payload` as a CoE message and returns the next CoE reply that is not
  // an emergency (its payload, starting at the CoE header). With `request`,
  // an SDO initiate response or abort that names another object is a late
  // answer to an earlier request: it is dropped and the mailbox read again.
  Expected<std::vector<std::uint8_t>, SdoError> exchange(ConstBytes payload, const SdoAddress* request = nullptr);
  Expected<std::vector<std::uint8_t>, SdoError> info_exchange(std::uint8_t opcode, ConstBytes request);

  Master& master_;
  std::size_t slave_;
  std::vector<Emergency> emergencies_;
  std::size_t stale_replies_ = 0;
};

// CoeClient::read_pdo_sizes for each of `slaves`, their mailbox steps sent
// side by side (several mailbox datagrams per frame); a slave that leaves the
// plain path is read alone by CoeClient (master/pdo_sizes_batch.cpp).
Expected<void, SdoError> read_pdo_sizes_all(Master& master, std::span<const std::size_t> slaves);

}  // namespace ecat::master
