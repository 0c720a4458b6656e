// SDO Information (ETG.1000.6 §5.6.3; coe-mailbox.md §7): requests with the
// 4-byte info header, answers reassembled over fragments ("incomplete" bit 7
// and "fragments left") before they are parsed.
#include "master/coe_client.hpp"

namespace ecat::master {

using namespace coe;

Expected<std::vector<std::uint8_t>, SdoError> CoeClient::info_exchange(std::uint8_t opcode, ConstBytes request) {
  std::vector<std::uint8_t> req(kCoeHeaderSize + kInfoHeaderSize + request.size());
  ByteWriter w(req);
  w.u16(static_cast<std::uint16_t>(kServiceSdoInfo << kServiceShift));
  w.u8(opcode);
  w.u8(0);
  w.u16(0);  // fragments left
  w.bytes(request);
  auto reply = exchange(req);
  std::vector<std::uint8_t> data;
  const std::uint8_t want = static_cast<std::uint8_t>(opcode + 1);
  for (unsigned n = 0; n < master_.config().max_polls; ++n) {
    if (!reply) return fail(reply.error());
    const ConstBytes p(*reply);
    if (p.size() < kCoeHeaderSize + kInfoHeaderSize) return fail(SdoError::master(MasterError::InvalidResponse));
    const auto service = static_cast<std::uint8_t>(load_le<std::uint16_t>(p.data()) >> kServiceShift);
    // An SDO abort answer (service 2, command 0x80) is accepted as well.
    if (service == kServiceSdoRequest && p[kCoeHeaderSize] == kAbort && p.size() >= kCoeHeaderSize + kSdoHeaderSize) {
      return fail(SdoError::abort(static_cast<SdoAbortCode>(load_le<std::uint32_t>(p.data() + 6))));
    }
    if (service != kServiceSdoInfo) return fail(SdoError::master(MasterError::InvalidResponse));
    const std::uint8_t op = p[kCoeHeaderSize] & kInfoOpcodeMask;
    const bool incomplete = (p[kCoeHeaderSize] & kInfoIncomplete) != 0;
    const ConstBytes body = p.subspan(kCoeHeaderSize + kInfoHeaderSize);
    if (op == kInfoError) {
      if (body.size() < 4) return fail(SdoError::master(MasterError::InvalidResponse));
      return fail(SdoError::abort(static_cast<SdoAbortCode>(load_le<std::uint32_t>(body.data()))));
    }
    if (op != want) return fail(SdoError::master(MasterError::InvalidResponse));
    data.insert(data.end(), body.begin(), body.end());
    if (!incomplete) return data;
    // Next fragment: the slave sends it unasked once SM1 is read.
    auto m = master_.mailbox_receive(slave_, master_.config().mailbox_timeout);
    if (!m) return fail(SdoError::master(m.error()));
    reply = std::vector<std::uint8_t>(m->payload.begin(), m->payload.end());
  }
  return fail(SdoError::master(MasterError::InvalidResponse));
}

Expected<std::vector<std::uint16_t>, SdoError> CoeClient::od_list(std::uint16_t list_type) {
  std::uint8_t req[2];
  store_le(req, list_type);
  auto data = info_exchange(kInfoGetOdList, req);
  if (!data) return fail(data.error());
  ByteReader r(*data);
  if (r.u16() != list_type || !r.ok()) return fail(SdoError::master(MasterError::InvalidResponse));
  std::vector<std::uint16_t> out;
  while (r.remaining() >= 2) out.push_back(r.u16());
  return out;
}

Expected<ObjectDescription, SdoError> CoeClient::object_description(std::uint16_t index) {
  std::uint8_t req[2];
  store_le(req, index);
  auto data = info_exchange(kInfoGetObjectDescription, req);
  if (!data) return fail(data.error());
  ByteReader r(*data);
  ObjectDescription d;
  d.index = r.u16();
  d.data_type = r.u16();
  d.max_subindex = r.u8();
  d.object_code = r.u8();
  if (!r.ok() || d.index != index) return fail(SdoError::master(MasterError::InvalidResponse));
  const ConstBytes name = r.rest();
  d.name.assign(name.begin(), name.end());
  return d;
}

Expected<EntryDescription, SdoError> CoeClient::entry_description(std::uint16_t index, std::uint8_t subindex,
                                                                  std::uint8_t value_info) {
  std::uint8_t req[4];
  store_le(req, index);
  req[2] = subindex;
  req[3] = value_info;
  auto data = info_exchange(kInfoGetEntryDescription, req);
  if (!data) return fail(data.error());
  ByteReader r(*data);
  EntryDescription d;
  d.index = r.u16();
  d.subindex = r.u8();
  d.value_info = r.u8();
  d.data_type = r.u16();
  d.bit_length = r.u16();
  d.access = r.u16();
  if (!r.ok() || d.index != index || d.subindex != subindex) {
    return fail(SdoError::master(MasterError::InvalidResponse));
  }
  // Optional elements in order: unit (2 bytes), default, minimum, maximum
  // (ceil(bit length / 8) bytes each) — coe-mailbox.md §7.3.
  std::size_t extra = 0;
  const std::size_t value_bytes = (d.bit_length + 7u) / 8u;
  if ((d.value_info & kValueInfoUnit) != 0) extra += 2;
  for (std::uint8_t bit : {kValueInfoDefault, kValueInfoMinimum, kValueInfoMaximum}) {
    if ((d.value_info & bit) != 0) extra += value_bytes;
  }
  const ConstBytes values = r.bytes(extra);
  if (!r.ok()) return fail(SdoError::master(MasterError::InvalidResponse));
  d.value_data.assign(values.begin(), values.end());
  const ConstBytes name = r.rest();
  d.name.assign(name.begin(), name.end());
  return d;
}

}  // namespace ecat::master
