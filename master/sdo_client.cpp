// SDO upload/download (ETG.1000.6 §5.6.2; coe-mailbox.md §5), byte values as
// SOEM sends them: expedited for <= 4 bytes, normal otherwise, segments when
// the data does not fit the mailbox; index and subindex of every answer must
// echo the request (masters.md §6 #22); an abort is command 0x80 in any
// service.
#include <algorithm>

#include "master/coe_client.hpp"

namespace ecat::master {

namespace {

using namespace coe;

std::uint16_t coe_header(std::uint8_t service) noexcept {
  return static_cast<std::uint16_t>(service << kServiceShift);
}

std::uint8_t service_of(ConstBytes p) noexcept {
  return static_cast<std::uint8_t>(load_le<std::uint16_t>(p.data()) >> kServiceShift);
}

// Where the SDO header's fields lie in a CoE payload (coe-mailbox.md §5): the
// command byte, then index (2 bytes) and subindex, then data or abort code.
constexpr std::size_t kSdoIndexAt = kCoeHeaderSize + 1;
constexpr std::size_t kSdoSubindexAt = kSdoIndexAt + 2;
constexpr std::size_t kSdoDataAt = kSdoSubindexAt + 1;

// The SDO header names another object than index/subindex.
bool names_other(ConstBytes p, std::uint16_t index, std::uint8_t subindex) noexcept {
  return load_le<std::uint16_t>(p.data() + kSdoIndexAt) != index || p[kSdoSubindexAt] != subindex;
}

// An SDO reply: at least CoE header + command byte; abort -> its code.
Expected<std::uint8_t, SdoError> sdo_command(ConstBytes p, std::uint16_t index, std::uint8_t subindex,
                                             bool initiate) {
  if (p.size() < kCoeHeaderSize + 1) return fail(SdoError::master(MasterError::InvalidResponse));
  const std::uint8_t cmd = p[kCoeHeaderSize];
  if (cmd == kAbort && p.size() >= kCoeHeaderSize + kSdoHeaderSize) {
    return fail(SdoError::abort(static_cast<SdoAbortCode>(load_le<std::uint32_t>(p.data() + kSdoDataAt))));
  }
  if (service_of(p) != kServiceSdoResponse) return fail(SdoError::master(MasterError::InvalidResponse));
  if (initiate) {
    if (p.size() < kCoeHeaderSize + kSdoHeaderSize) return fail(SdoError::master(MasterError::InvalidResponse));
    if (names_other(p, index, subindex)) {
      return fail(SdoError::master(MasterError::InvalidResponse));
    }
  }
  return cmd;
}

// An SDO initiate response or an abort (the commands that carry index and
// subindex) naming another object than `request`: the late answer to an
// earlier request whose wait ran out. IgH keeps waiting in that case
// (masters.md §2, SDO upload); taking it as the answer would leave every
// later request one reply behind.
bool answers_another(ConstBytes p, const CoeClient::SdoAddress& request) noexcept {
  if (p.size() < kCoeHeaderSize + kSdoHeaderSize) return false;
  const std::uint8_t cmd = p[kCoeHeaderSize];
  const std::uint8_t specifier = static_cast<std::uint8_t>(cmd >> kSpecifierShift);
  const bool names_object =
      cmd == kAbort || (service_of(p) == kServiceSdoResponse &&
                        (specifier == kScsUploadInitiate || specifier == kScsDownloadInitiate));
  return names_object && names_other(p, request.index, request.subindex);
}

}  // namespace

std::array<std::uint8_t, kCoeHeaderSize + kSdoHeaderSize> CoeClient::upload_request(std::uint16_t index,
                                                                                   std::uint8_t subindex,
                                                                                   bool complete_access) noexcept {
  std::array<std::uint8_t, kCoeHeaderSize + kSdoHeaderSize> b{};
  ByteWriter w(b);
  w.u16(coe_header(kServiceSdoRequest));
  w.u8(static_cast<std::uint8_t>(kUploadRequest | (complete_access ? kCompleteAccess : 0)));
  w.u16(index);
  w.u8(subindex);
  w.u32(0);
  return b;
}

std::array<std::uint8_t, kCoeHeaderSize + kSdoHeaderSize> CoeClient::expedited_download_request(
    std::uint16_t index, std::uint8_t subindex, std::uint32_t value, std::size_t size, bool complete_access) noexcept {
  std::array<std::uint8_t, kCoeHeaderSize + kSdoHeaderSize> b{};
  ByteWriter w(b);
  w.u16(coe_header(kServiceSdoRequest));
  w.u8(static_cast<std::uint8_t>(kDownloadExpedited | ((4 - size) << 2) | (complete_access ? kCompleteAccess : 0)));
  w.u16(index);
  w.u8(subindex);
  const std::uint32_t mask = size >= 4 ? 0xFFFFFFFFu : ((1u << (8 * size)) - 1u);
  w.u32(value & mask);
  return b;
}

Expected<std::vector<std::uint8_t>, SdoError> CoeClient::exchange(ConstBytes payload, const SdoAddress* request) {
  if (auto s = master_.mailbox_send(slave_, mbx::kTypeCoe, payload); !s) return fail(SdoError::master(s.error()));
  for (unsigned n = 0; n < master_.config().max_polls; ++n) {
    auto m = master_.mailbox_receive(slave_, master_.config().mailbox_timeout);
    if (!m) return fail(SdoError::master(m.error()));
    if (m->header.type != mbx::kTypeCoe || m->payload.size() < kCoeHeaderSize) {
      return fail(SdoError::master(MasterError::InvalidResponse));
    }
    if (service_of(m->payload) == kServiceEmergency) {
      Emergency e;
      ByteReader r(m->payload.subspan(kCoeHeaderSize));
      e.error_code = r.u16();
      e.error_register = r.u8();
      const ConstBytes d = r.bytes(e.data.size());
      std::copy(d.begin(), d.end(), e.data.begin());
      emergencies_.push_back(e);
      continue;
    }
    if (request != nullptr && answers_another(m->payload, *request)) {
      ++stale_replies_;
      continue;
    }
    return std::vector<std::uint8_t>(m->payload.begin(), m->payload.end());
  }
  return fail(SdoError::master(MasterError::MailboxTimeout));
}

Expected<std::vector<std::uint8_t>, SdoError> CoeClient::upload(std::uint16_t index, std::uint8_t subindex,
                                                                bool complete_access) {
  const auto req = upload_request(index, subindex, complete_access);
  const SdoAddress object{index, subindex};
  auto reply = exchange(req, &object);
  if (!reply) return fail(reply.error());
  auto cmd = sdo_command(*reply, index, subindex, true);
  if (!cmd) return fail(cmd.error());
  if ((*cmd >> kSpecifierShift) != kScsUploadInitiate) return fail(SdoError::master(MasterError::InvalidResponse));
  const ConstBytes p(*reply);
  if ((*cmd & kExpedited) != 0) {
    const std::size_t size = (*cmd & kSizeIndicated) != 0 ? 4 - ((*cmd >> 2) & 0x03) : 4;
    return std::vector<std::uint8_t>(p.begin() + 6, p.begin() + 6 + static_cast<std::ptrdiff_t>(size));
  }
  const std::uint32_t complete = load_le<std::uint32_t>(p.data() + kSdoDataAt);
  std::vector<std::uint8_t> data(p.begin() + kCoeHeaderSize + kSdoHeaderSize, p.end());
  if (data.size() > complete) data.resize(complete);
  bool toggle = false;
  while (data.size() < complete) {
    std::array<std::uint8_t, kCoeHeaderSize + kSdoHeaderSize> seg{};
    ByteWriter w(seg);
    w.u16(coe_header(kServiceSdoRequest));
    w.u8(static_cast<std::uint8_t>(kUploadSegmentRequest | (toggle ? kToggle : 0)));
    auto sr = exchange(seg);
    if (!sr) return fail(sr.error());
    auto scmd = sdo_command(*sr, index, subindex, false);
    if (!scmd) return fail(scmd.error());
    if ((*scmd >> kSpecifierShift) != kScsUploadSegment || ((*scmd & kToggle) != 0) != toggle) {
      return fail(SdoError::master(MasterError::InvalidResponse));
    }
    std::size_t n = sr->size() - kCoeHeaderSize - 1;
    const bool last = (*scmd & kLastSegment) != 0;
    // A padded 7-byte segment says in bits 3:1 how many bytes are unused (SOEM).
    if (n == kMinSegmentData) n -= static_cast<std::size_t>((*scmd >> 1) & 0x07);
    data.insert(data.end(), sr->begin() + kCoeHeaderSize + 1,
                sr->begin() + static_cast<std::ptrdiff_t>(kCoeHeaderSize + 1 + n));
    toggle = !toggle;
    if (last) break;
  }
  if (data.size() != complete) return fail(SdoError::master(MasterError::InvalidResponse));
  return data;
}

Expected<void, SdoError> CoeClient::download(std::uint16_t index, std::uint8_t subindex, ConstBytes data,
                                             bool complete_access) {
  if (data.empty()) return fail(SdoError::master(MasterError::InvalidArgument));
  if (data.size() <= 4) {
    std::uint32_t v = 0;
    for (std::size_t i = 0; i < data.size(); ++i) v |= static_cast<std::uint32_t>(data[i]) << (8 * i);
    const auto req = expedited_download_request(index, subindex, v, data.size(), complete_access);
    const SdoAddress object{index, subindex};
    auto reply = exchange(req, &object);
    if (!reply) return fail(reply.error());
    auto cmd = sdo_command(*reply, index, subindex, true);
    if (!cmd) return fail(cmd.error());
    if ((*cmd >> kSpecifierShift) != kScsDownloadInitiate) return fail(SdoError::master(MasterError::InvalidResponse));
    return {};
  }
  const std::size_t mailbox = master_.slave(slave_).mailbox.rx_size;
  if (mailbox < mbx::kHeaderSize + kCoeHeaderSize + kSdoHeaderSize + kMinSegmentData) {
    return fail(SdoError::master(MasterError::NotConfigured));
  }
  const std::size_t first_max = mailbox - mbx::kHeaderSize - kCoeHeaderSize - kSdoHeaderSize;
  const std::size_t first = std::min(data.size(), first_max);
  std::vector<std::uint8_t> req(kCoeHeaderSize + kSdoHeaderSize + first);
  ByteWriter w(req);
  w.u16(coe_header(kServiceSdoRequest));
  w.u8(static_cast<std::uint8_t>(kDownloadNormal | (complete_access ? kCompleteAccess : 0)));
  w.u16(index);
  w.u8(subindex);
  w.u32(static_cast<std::uint32_t>(data.size()));
  w.bytes(data.first(first));
  req.resize(w.position());
  const SdoAddress object{index, subindex};
  auto reply = exchange(req, &object);
  if (!reply) return fail(reply.error());
  auto cmd = sdo_command(*reply, index, subindex, true);
  if (!cmd) return fail(cmd.error());
  if ((*cmd >> kSpecifierShift) != kScsDownloadInitiate) return fail(SdoError::master(MasterError::InvalidResponse));

  const std::size_t seg_max = mailbox - mbx::kHeaderSize - kCoeHeaderSize - 1;
  std::size_t sent = first;
  bool toggle = false;
  while (sent < data.size()) {
    const std::size_t chunk = std::min(data.size() - sent, seg_max);
    const bool last = sent + chunk == data.size();
    const std::size_t padded = std::max(chunk, kMinSegmentData);
    std::vector<std::uint8_t> seg(kCoeHeaderSize + 1 + padded, 0);
    ByteWriter sw(seg);
    sw.u16(coe_header(kServiceSdoRequest));
    const std::size_t unused = padded - chunk;
    sw.u8(static_cast<std::uint8_t>((toggle ? kToggle : 0) | (unused << 1) | (last ? kLastSegment : 0)));
    sw.bytes(data.subspan(sent, chunk));
    auto sr = exchange(seg);
    if (!sr) return fail(sr.error());
    auto scmd = sdo_command(*sr, index, subindex, false);
    if (!scmd) return fail(scmd.error());
    if ((*scmd >> kSpecifierShift) != kScsDownloadSegment || ((*scmd & kToggle) != 0) != toggle) {
      return fail(SdoError::master(MasterError::InvalidResponse));
    }
    sent += chunk;
    toggle = !toggle;
  }
  return {};
}

Expected<void, SdoError> CoeClient::download_value(std::uint16_t index, std::uint8_t subindex, std::uint32_t value,
                                                   std::size_t size) {
  if (size == 0 || size > 4) return fail(SdoError::master(MasterError::InvalidArgument));
  std::uint8_t b[4];
  store_le(b, value);
  return download(index, subindex, ConstBytes(b, size));
}

Expected<std::uint32_t, SdoError> CoeClient::upload_value(std::uint16_t index, std::uint8_t subindex) {
  auto d = upload(index, subindex);
  if (!d) return fail(d.error());
  if (d->empty() || d->size() > 4) return fail(SdoError::master(MasterError::InvalidResponse));
  std::uint32_t v = 0;
  for (std::size_t i = 0; i < d->size(); ++i) v |= static_cast<std::uint32_t>((*d)[i]) << (8 * i);
  return v;
}

}  // namespace ecat::master
