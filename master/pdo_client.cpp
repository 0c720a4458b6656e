// PDO mapping and assignment over SDO, the IgH way (masters.md §2.3 step 11,
// coe-mailbox.md §11.1/§11.2): disable with sub 0 = 0, write the entries,
// enable with sub 0 = n. Sizes are read back the same way IgH and SOEM do:
// 1C1x:00 (1 byte), 1C1x:i (2 bytes), PDO:00 (1 byte), PDO:j (4 bytes).
#include "master/coe_client.hpp"

namespace ecat::master {

namespace {
constexpr std::uint32_t kEntryBitLengthMask = 0xFF;
constexpr std::size_t kSi0Size = 1;
constexpr std::size_t kAssignEntrySize = 2;
constexpr std::size_t kMappingEntrySize = 4;
constexpr std::uint32_t kBitsPerByte = 8;
}  // namespace

Expected<void, SdoError> CoeClient::write_pdo_mapping(std::uint16_t pdo, std::span<const std::uint32_t> entries) {
  if (entries.size() > 0xFF) return fail(SdoError::master(MasterError::InvalidArgument));
  if (auto r = download_value(pdo, 0, 0, kSi0Size); !r) return r;
  for (std::size_t i = 0; i < entries.size(); ++i) {
    if (auto r = download_value(pdo, static_cast<std::uint8_t>(i + 1), entries[i], kMappingEntrySize); !r) return r;
  }
  return download_value(pdo, 0, static_cast<std::uint32_t>(entries.size()), kSi0Size);
}

Expected<void, SdoError> CoeClient::write_pdo_assignment(std::uint16_t assign, std::span<const std::uint16_t> pdos) {
  if (pdos.size() > 0xFF) return fail(SdoError::master(MasterError::InvalidArgument));
  if (auto r = download_value(assign, 0, 0, kSi0Size); !r) return r;
  for (std::size_t i = 0; i < pdos.size(); ++i) {
    if (auto r = download_value(assign, static_cast<std::uint8_t>(i + 1), pdos[i], kAssignEntrySize); !r) return r;
  }
  return download_value(assign, 0, static_cast<std::uint32_t>(pdos.size()), kSi0Size);
}

Expected<std::vector<std::uint16_t>, SdoError> CoeClient::read_pdo_assignment(std::uint16_t assign) {
  auto n = upload(assign, 0);
  if (!n) return fail(n.error());
  if (n->size() != kSi0Size) return fail(SdoError::master(MasterError::InvalidResponse));
  std::vector<std::uint16_t> out;
  for (std::uint8_t i = 1; i <= (*n)[0]; ++i) {
    auto e = upload(assign, i);
    if (!e) return fail(e.error());
    if (e->size() != kAssignEntrySize) return fail(SdoError::master(MasterError::InvalidResponse));
    out.push_back(load_le<std::uint16_t>(e->data()));
  }
  return out;
}

Expected<std::vector<std::uint32_t>, SdoError> CoeClient::read_pdo_mapping(std::uint16_t pdo) {
  auto n = upload(pdo, 0);
  if (!n) return fail(n.error());
  if (n->size() != kSi0Size) return fail(SdoError::master(MasterError::InvalidResponse));
  std::vector<std::uint32_t> out;
  for (std::uint8_t i = 1; i <= (*n)[0]; ++i) {
    auto e = upload(pdo, i);
    if (!e) return fail(e.error());
    if (e->size() != kMappingEntrySize) return fail(SdoError::master(MasterError::InvalidResponse));
    out.push_back(load_le<std::uint32_t>(e->data()));
  }
  return out;
}

Expected<std::uint32_t, SdoError> CoeClient::assigned_bits(std::uint16_t assign) {
  auto pdos = read_pdo_assignment(assign);
  // ETG.1000.6 §5.6.7.4.2: 1C12h/1C13h exist only for a sync manager of that
  // direction; an inputs-only or outputs-only slave has no bits the other way.
  if (!pdos && pdos.error().from_slave && pdos.error().code == SdoAbortCode::ObjectNotFound) return 0u;
  if (!pdos) return fail(pdos.error());
  std::uint32_t bits = 0;
  for (std::uint16_t pdo : *pdos) {
    auto entries = read_pdo_mapping(pdo);
    if (!entries) return fail(entries.error());
    for (std::uint32_t e : *entries) bits += e & kEntryBitLengthMask;
  }
  return bits;
}

// ETG.1000.6 §5.6.7.4.2: SM n carries what 1C10h+n assigns. Every SII SM
// of type 3/4 is read (as SOEM walks the SMs of 1C00h); a slave whose SII
// lists no such SM gets 1C12h/1C13h for SM2/SM3.
Expected<void, SdoError> CoeClient::read_pdo_sizes() {
  auto& s = master_.slave(slave_);
  std::vector<ProcessSm> sms;
  const auto& sii_sms = s.sii.sync_managers;
  for (std::size_t n = 0; n < sii_sms.size(); ++n) {
    const bool outputs = sii_sms[n].type == sii::kSmTypeOutputs;
    if (!outputs && sii_sms[n].type != sii::kSmTypeInputs) continue;
    auto bits = assigned_bits(static_cast<std::uint16_t>(coe::kSmPdoAssignBase + n));
    if (!bits) return fail(bits.error());
    sms.push_back(ProcessSm{static_cast<std::uint8_t>(n), outputs, sii_sms[n].start, sii_sms[n].control,
                            static_cast<std::uint16_t>((*bits + kBitsPerByte - 1) / kBitsPerByte), 0});
  }
  if (!sms.empty()) {
    s.pd.sms = std::move(sms);
    s.pd.per_sm = true;
    s.pd.sum_sizes();
    return {};
  }
  auto out_bits = assigned_bits(coe::kRxPdoAssign);
  if (!out_bits) return fail(out_bits.error());
  auto in_bits = assigned_bits(coe::kTxPdoAssign);
  if (!in_bits) return fail(in_bits.error());
  s.pd.per_sm = false;
  s.pd.output_bytes = static_cast<std::uint16_t>((*out_bits + kBitsPerByte - 1) / kBitsPerByte);
  s.pd.input_bytes = static_cast<std::uint16_t>((*in_bits + kBitsPerByte - 1) / kBitsPerByte);
  return {};
}

}  // namespace ecat::master
