// SDO server (CiA 301 §7.2.4, ETG.1000.6 §5.6.2; shared/spec/coe-mailbox.md
// §5): expedited, normal and segmented download and upload, complete access
// from subindex 0 or 1, abort frames with the CiA 301 codes. Access rights
// per ESM state come from od::Access; values, lengths, ranges and hooks from
// the ObjectStore. One transfer at a time (the mailbox is one request, one
// reply); its buffer is sized once from the dictionary.
#pragma once

#include <cstdint>
#include <vector>

#include "coe/mailbox_header.hpp"
#include "coe/object_store.hpp"
#include "coe/sdo_abort.hpp"
#include "common/expected.hpp"
#include "common/le.hpp"
#include "od/access.hpp"

namespace ecat::coe {

class SdoServer {
 public:
  // `complete_access`: whether the device offers it (ESI CoE CompleteAccess,
  // SII CoE details bit 5); if not, a CA request is aborted with 06010000.
  explicit SdoServer(ObjectStore& store, bool complete_access = true);

  // `request`: the bytes after the CoE header. Writes the whole CoE reply
  // (CoE header included) into `reply`; returns its length (0 = no reply).
  Expected<std::size_t, MailboxError> handle(ConstBytes request, Bytes reply, od::EsmState state) noexcept;
  void reset() noexcept { transfer_ = Transfer::None; }
  bool busy() const noexcept { return transfer_ != Transfer::None; }

  std::size_t transfer_capacity() const noexcept { return buffer_.size(); }

  // Fault injection (slave::FaultCatalogue, docs/faults.md), as SSC's test
  // application offers it. Truncated uploads: the first upload segment
  // reply carries the last-segment bit (CiA 301 §7.2.4.3.6, c = 1) though
  // fewer bytes than the initiate reply's size have been sent. Wrong toggle:
  // every segment reply (upload and download) carries the toggle bit the
  // request did not have (CiA 301 §7.2.4.3.4/.6, t).
  void set_upload_truncated(bool on) noexcept { truncate_upload_ = on; }
  void set_wrong_toggle(bool on) noexcept { wrong_toggle_ = on; }

 private:
  enum class Transfer : std::uint8_t { None, Download, Upload };

  std::size_t initiate_download(std::uint8_t cmd, std::uint16_t index, std::uint8_t sub, ConstBytes request,
                                Bytes reply, od::EsmState state) noexcept;
  std::size_t download_segment(std::uint8_t cmd, ConstBytes request, Bytes reply, od::EsmState state) noexcept;
  std::size_t initiate_upload(std::uint8_t cmd, std::uint16_t index, std::uint8_t sub, Bytes reply,
                              od::EsmState state) noexcept;
  std::size_t upload_segment(std::uint8_t cmd, Bytes reply) noexcept;

  Expected<void, SdoAbort> check_target(std::uint16_t index, std::uint8_t sub, bool complete_access) const noexcept;
  Expected<void, SdoAbort> commit(std::uint16_t index, std::uint8_t sub, bool complete_access, ConstBytes data,
                                  od::EsmState state) noexcept;
  std::size_t abort(Bytes reply, std::uint16_t index, std::uint8_t sub, SdoAbort code) noexcept;
  // This thread's rollback buffer, at least `bytes` long (empty: no memory).
  static Bytes rollback_buffer(std::size_t bytes) noexcept;

  ObjectStore& store_;
  bool complete_access_supported_ = true;
  std::vector<std::uint8_t> buffer_;   // segmented transfer data
  // The complete-access rollback copy's size (the largest object): the
  // copy itself lives only within one request, so it is one buffer per
  // thread (rollback_buffer in sdo_server.cpp), not one per slave.
  std::size_t rollback_bytes_ = 0;
  Transfer transfer_ = Transfer::None;
  std::uint16_t index_ = 0;
  std::uint8_t subindex_ = 0;
  bool complete_access_ = false;
  bool toggle_ = false;
  std::size_t size_ = 0;    // complete size (the buffer's room when not indicated)
  bool size_known_ = true;  // false: a download whose size only its last segment tells
  std::size_t offset_ = 0;  // bytes received / sent
  bool truncate_upload_ = false;
  bool wrong_toggle_ = false;
};

}  // namespace ecat::coe
