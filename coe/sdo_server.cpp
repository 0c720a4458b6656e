#include "coe/sdo_server.hpp"

#include <algorithm>
#include <cstring>

#include "coe/coe_header.hpp"
#include "coe/complete_access.hpp"
#include "coe/sdo_command.hpp"

namespace ecat::coe {
namespace {

constexpr std::size_t kReplySize = CoeHeader::kSize + sdo::kHeaderSize;

std::size_t initiate_reply(Bytes reply, std::uint8_t cmd, std::uint16_t index, std::uint8_t sub) noexcept {
  ByteWriter w(reply);
  CoeHeader::write(w, CoeService::SdoResponse);
  w.u8(cmd);
  w.u16(index);
  w.u8(sub);
  w.u32(0);
  return w.position();
}

}  // namespace

// The rollback copy of a complete-access download (complete_access_download)
// is needed only while one request is handled, so the slaves a thread runs
// share one (issue 16: a copy per slave was 0.45 KiB of a servo's 32). Grown
// to the largest any of them asks for: at construction on the thread that
// builds the slaves, and on a firmware lane the first time it handles one
// (a failed growth is the SDO abort 0x05040005, out of memory).
Bytes SdoServer::rollback_buffer(std::size_t bytes) noexcept {
  thread_local std::vector<std::uint8_t> buffer;
  if (buffer.size() < bytes) {
    try {
      buffer.resize(bytes);
    } catch (...) {
      return {};
    }
  }
  return {buffer.data(), bytes};
}

SdoServer::SdoServer(ObjectStore& store, bool complete_access)
    : store_(store),
      complete_access_supported_(complete_access),
      buffer_(std::max<std::size_t>(store.max_entry_capacity(), max_complete_access_size(store.dictionary()))),
      rollback_bytes_(buffer_.size()) {
  // The rollback copy of a complete access holds every entry of one object.
  std::size_t largest_object = 0;
  for (const od::Object& o : store.dictionary().objects()) {
    std::size_t n = 0;
    for (const od::Entry& e : o.entries) n += store.slot(o.index, e.subindex)->capacity;
    largest_object = std::max(largest_object, n);
  }
  rollback_bytes_ = std::max(rollback_bytes_, largest_object);
  // Room on this thread now, so that a complete access on it allocates nothing.
  (void)rollback_buffer(rollback_bytes_);
}

Expected<std::size_t, MailboxError> SdoServer::handle(ConstBytes request, Bytes reply,
                                                      od::EsmState state) noexcept {
  if (reply.size() < kReplySize) return fail(MailboxError::NoMoreMemory);
  if (request.size() < sdo::kHeaderSize) return fail(MailboxError::SizeTooShort);
  ByteReader r(request);
  const std::uint8_t cmd = r.u8();
  const std::uint16_t index = r.u16();
  const std::uint8_t sub = r.u8();
  switch (cmd >> sdo::kSpecifierShift) {
    case sdo::kCcsInitiateDownload: return initiate_download(cmd, index, sub, request, reply, state);
    case sdo::kCcsDownloadSegment: return download_segment(cmd, request, reply, state);
    case sdo::kCcsInitiateUpload: return initiate_upload(cmd, index, sub, reply, state);
    case sdo::kCcsUploadSegment: return upload_segment(cmd, reply);
    case sdo::kCsAbort: transfer_ = Transfer::None; return std::size_t{0};  // no answer to an abort
    default: return abort(reply, index, sub, SdoAbort::CommandSpecifier);
  }
}

std::size_t SdoServer::abort(Bytes reply, std::uint16_t index, std::uint8_t sub, SdoAbort code) noexcept {
  transfer_ = Transfer::None;
  // Aborts go out as CoE service 2 "SDO request" (ETG.1000.6 §5.6.2.7; IgH depends on it).
  ByteWriter w(reply);
  CoeHeader::write(w, CoeService::SdoRequest);
  w.u8(sdo::command(sdo::kCsAbort));
  w.u16(index);
  w.u8(sub);
  w.u32(to_u32(code));
  return w.position();
}

Expected<void, SdoAbort> SdoServer::check_target(std::uint16_t index, std::uint8_t sub,
                                                 bool complete_access) const noexcept {
  const ObjectStore::Slot* s0 = store_.slot(index, 0);
  if (!s0) return fail(SdoAbort::NoObject);
  if (complete_access) {
    if (!complete_access_supported_) return fail(SdoAbort::UnsupportedAccess);
    // Complete access starts at subindex 0 or 1 of an ARRAY/RECORD (ETG.1000.6 §5.6.2.1.2).
    const od::Object* object = store_.dictionary().find(index);
    if (sub > 1 || object == nullptr || object->code == od::ObjectCode::Var) return fail(SdoAbort::UnsupportedAccess);
    return {};
  }
  if (!store_.slot(index, sub)) return fail(SdoAbort::NoSubindex);
  return {};
}

Expected<void, SdoAbort> SdoServer::commit(std::uint16_t index, std::uint8_t sub, bool complete_access,
                                           ConstBytes data, od::EsmState state) noexcept {
  if (complete_access) {
    const Bytes rollback = rollback_buffer(rollback_bytes_);
    if (rollback.size() < rollback_bytes_) return fail(SdoAbort::OutOfMemory);
    return complete_access_download(store_, index, sub == 0, data, state, rollback);
  }
  return store_.write({index, sub, data, state});
}

std::size_t SdoServer::initiate_download(std::uint8_t cmd, std::uint16_t index, std::uint8_t sub,
                                         ConstBytes request, Bytes reply, od::EsmState state) noexcept {
  transfer_ = Transfer::None;
  const bool ca = cmd & sdo::kCompleteAccess;
  if (auto ok = check_target(index, sub, ca); !ok) return abort(reply, index, sub, ok.error());
  std::size_t capacity = buffer_.size();
  if (!ca) {
    const ObjectStore::Slot& s = *store_.slot(index, sub);
    const od::Access a = s.entry->access;
    if (!a.writable()) return abort(reply, index, sub, SdoAbort::ReadOnly);
    if (!a.writable_in(state)) return abort(reply, index, sub, SdoAbort::DataTransferDeviceState);
    capacity = s.capacity;
  }
  const ConstBytes data4 = request.subspan(4, sdo::kExpeditedMax);
  if (cmd & sdo::kExpedited) {
    std::size_t n = sdo::kExpeditedMax;
    if (cmd & sdo::kSizeIndicated) {
      n -= (cmd >> sdo::kUnusedShift) & sdo::kUnusedMask;
    } else if (!ca) {
      n = std::min<std::size_t>(n, capacity);
    }
    if (auto ok = commit(index, sub, ca, data4.first(n), state); !ok) return abort(reply, index, sub, ok.error());
    return initiate_reply(reply, sdo::command(sdo::kScsInitiateDownload), index, sub);
  }
  // Normal transfer (ETG.1000.6 §5.6.2.1): the complete-size field, then as
  // much data as fits this frame. s = 0 is "size not indicated" (CiA 301
  // §7.2.4.3.3), a valid request (KickCAT sends 0x20/0x30 with the size in the
  // field): a non-zero field is still the complete size; a zero field means
  // the data is what arrives, this frame's own or, when it carries none, the
  // segments up to the one marked last (docs/coe.md "Normal download, s = 0").
  const std::size_t field = load_le<std::uint32_t>(data4.data());
  const ConstBytes first = request.subspan(sdo::kHeaderSize);
  const bool size_indicated = (cmd & sdo::kSizeIndicated) || field != 0;
  const bool open_ended = !size_indicated && first.empty();
  const std::size_t size = size_indicated ? field : open_ended ? capacity : first.size();
  if (size > capacity) return abort(reply, index, sub, SdoAbort::LengthTooHigh);
  if (!open_ended && !ca && !store_.slot(index, sub)->variable() && size < capacity) {
    return abort(reply, index, sub, SdoAbort::LengthTooLow);
  }
  if (first.size() > size) return abort(reply, index, sub, SdoAbort::LengthMismatch);
  if (first.size() == size && !open_ended) {
    if (auto ok = commit(index, sub, ca, first.first(size), state); !ok) return abort(reply, index, sub, ok.error());
  } else {
    std::memcpy(buffer_.data(), first.data(), first.size());
    transfer_ = Transfer::Download;
    index_ = index;
    subindex_ = sub;
    complete_access_ = ca;
    toggle_ = false;
    size_ = size;
    size_known_ = !open_ended;
    offset_ = first.size();
  }
  return initiate_reply(reply, sdo::command(sdo::kScsInitiateDownload), index, sub);
}

std::size_t SdoServer::download_segment(std::uint8_t cmd, ConstBytes request, Bytes reply,
                                        od::EsmState state) noexcept {
  if (transfer_ != Transfer::Download) return abort(reply, 0, 0, SdoAbort::CommandSpecifier);
  const bool toggle = cmd & sdo::kToggle;
  if (toggle != toggle_) return abort(reply, index_, subindex_, SdoAbort::ToggleBit);
  const std::size_t unused = (cmd >> sdo::kSegUnusedShift) & sdo::kSegUnusedMask;
  const std::size_t carried = request.size() - sdo::kSegmentHeaderSize;
  if (unused > carried) return abort(reply, index_, subindex_, SdoAbort::LengthMismatch);
  const std::size_t n = carried - unused;
  if (offset_ + n > size_) return abort(reply, index_, subindex_, SdoAbort::LengthTooHigh);
  std::memcpy(buffer_.data() + offset_, request.data() + sdo::kSegmentHeaderSize, n);
  offset_ += n;
  toggle_ = !toggle_;
  if (cmd & sdo::kLastSegment) {
    transfer_ = Transfer::None;
    if (size_known_ && offset_ != size_) return abort(reply, index_, subindex_, SdoAbort::LengthTooLow);
    if (auto ok = commit(index_, subindex_, complete_access_, {buffer_.data(), offset_}, state); !ok) {
      return abort(reply, index_, subindex_, ok.error());
    }
  }
  ByteWriter w(reply);
  CoeHeader::write(w, CoeService::SdoResponse);
  w.u8(sdo::command(sdo::kScsDownloadSegment, toggle != wrong_toggle_ ? sdo::kToggle : 0));
  w.fill(0, sdo::kMinSegmentData);
  return w.position();
}

std::size_t SdoServer::initiate_upload(std::uint8_t cmd, std::uint16_t index, std::uint8_t sub, Bytes reply,
                                       od::EsmState state) noexcept {
  transfer_ = Transfer::None;
  const bool ca = cmd & sdo::kCompleteAccess;
  if (auto ok = check_target(index, sub, ca); !ok) return abort(reply, index, sub, ok.error());
  Expected<std::size_t, SdoAbort> size = 0;
  if (ca) {
    size = complete_access_upload(store_, index, sub == 0, buffer_, state);
  } else {
    const od::Access a = store_.slot(index, sub)->entry->access;
    if (!a.readable()) return abort(reply, index, sub, SdoAbort::WriteOnly);
    if (!a.readable_in(state)) return abort(reply, index, sub, SdoAbort::DataTransferDeviceState);
    size = store_.read(index, sub, buffer_);
  }
  if (!size) return abort(reply, index, sub, size.error());
  const std::uint8_t ca_flag = ca ? sdo::kCompleteAccess : 0;
  ByteWriter w(reply);
  CoeHeader::write(w, CoeService::SdoResponse);
  if (*size > 0 && *size <= sdo::kExpeditedMax) {
    const auto unused = static_cast<std::uint8_t>((sdo::kExpeditedMax - *size) << sdo::kUnusedShift);
    w.u8(sdo::command(sdo::kScsInitiateUpload, sdo::kExpedited | sdo::kSizeIndicated | unused | ca_flag));
    w.u16(index);
    w.u8(sub);
    w.bytes({buffer_.data(), *size});
    w.fill(0, sdo::kExpeditedMax - *size);
    return w.position();
  }
  w.u8(sdo::command(sdo::kScsInitiateUpload, sdo::kSizeIndicated | ca_flag));
  w.u16(index);
  w.u8(sub);
  w.u32(static_cast<std::uint32_t>(*size));
  const std::size_t n = std::min(*size, w.remaining());
  w.bytes({buffer_.data(), n});
  if (n < *size) {
    // The rest follows in upload segments (ETG.1000.6 §5.6.2.3).
    transfer_ = Transfer::Upload;
    index_ = index;
    subindex_ = sub;
    toggle_ = false;
    size_ = *size;
    offset_ = n;
  }
  return w.position();
}

std::size_t SdoServer::upload_segment(std::uint8_t cmd, Bytes reply) noexcept {
  if (transfer_ != Transfer::Upload) return abort(reply, 0, 0, SdoAbort::CommandSpecifier);
  const bool toggle = cmd & sdo::kToggle;
  if (toggle != toggle_) return abort(reply, index_, subindex_, SdoAbort::ToggleBit);
  const std::size_t room = reply.size() - CoeHeader::kSize - sdo::kSegmentHeaderSize;
  const std::size_t n = std::min(size_ - offset_, room);
  const bool last = offset_ + n == size_ || truncate_upload_;
  std::uint8_t flags = toggle != wrong_toggle_ ? sdo::kToggle : 0;
  if (n < sdo::kMinSegmentData) flags |= static_cast<std::uint8_t>((sdo::kMinSegmentData - n) << sdo::kSegUnusedShift);
  if (last) flags |= sdo::kLastSegment;
  ByteWriter w(reply);
  CoeHeader::write(w, CoeService::SdoResponse);
  w.u8(sdo::command(sdo::kScsUploadSegment, flags));
  w.bytes({buffer_.data() + offset_, n});
  if (n < sdo::kMinSegmentData) w.fill(0, sdo::kMinSegmentData - n);
  offset_ += n;
  toggle_ = !toggle_;
  if (last) transfer_ = Transfer::None;
  return w.position();
}

}  // namespace ecat::coe
