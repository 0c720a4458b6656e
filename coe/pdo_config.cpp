#include "coe/pdo_config.hpp"

#include "coe/sm_bits.hpp"
#include "esc/registers.hpp"

namespace ecat::coe {
namespace {

std::size_t mapping_capacity(const od::Dictionary& dictionary) noexcept {
  std::size_t n = 0;
  for (const od::Object& o : dictionary.objects()) {
    if (is_mapping_index(o.index)) n += o.max_subindex();
  }
  return n;
}

std::uint32_t sm_max(const od::DeviceDescription& device, unsigned sm) noexcept {
  if (sm < device.sync_managers.size() && device.sync_managers[sm].max_size > 0) {
    return device.sync_managers[sm].max_size;
  }
  return device.esc.process_ram_bytes;
}

PdoDirection direction_of(std::uint16_t index) noexcept {
  return (index == kTxPdoAssign || is_mapping_index(index, PdoDirection::Tx)) ? PdoDirection::Tx : PdoDirection::Rx;
}

}  // namespace

PdoConfig::PdoConfig(ObjectStore& store, const od::DeviceDescription& device)
    : store_(store),
      max_rx_(sm_max(device, kOutputsSm)),
      max_tx_(sm_max(device, kInputsSm)),
      outputs_(mapping_capacity(store.dictionary())),
      inputs_(mapping_capacity(store.dictionary())) {
  for (const od::Object& o : store.dictionary().objects()) {
    if (is_mapping_index(o.index) || o.index == kRxPdoAssign || o.index == kTxPdoAssign) {
      store.set_hooks(o.index, this);
    }
  }
  rebuild();
}

Expected<void, SdoAbort> PdoConfig::check_entry(PdoDirection d, std::uint32_t value, bool fixed) const noexcept {
  const PdoMappingEntry m = PdoMappingEntry::decode(value);
  if (m.is_gap()) return {};
  const ObjectStore::Slot* s = store_.slot(m.index, m.subindex);
  if (!s) return fail(SdoAbort::NotMappable);
  const od::Access a = s->entry->access;
  if (!(d == PdoDirection::Rx ? a.rx_mappable() : a.tx_mappable())) return fail(SdoAbort::NotMappable);
  const bool low_part = fixed && m.bit_length < s->entry->bit_length && !od::is_string(s->entry->type);
  if (s->entry->bit_length != m.bit_length && !low_part) return fail(SdoAbort::NotMappable);
  return {};
}

Expected<std::uint32_t, SdoAbort> PdoConfig::mapping_bits(PdoDirection d, std::uint16_t index, std::uint8_t count,
                                                          std::uint8_t sub, std::uint32_t value) const noexcept {
  std::uint32_t bits = 0;
  for (std::uint8_t k = 1; k <= count; ++k) {
    const ObjectStore::Slot* s = store_.slot(index, k);
    if (!s) return fail(SdoAbort::ValueTooHigh);
    const std::uint32_t v = (k == sub) ? value : store_.get<std::uint32_t>(*s);
    if (auto ok = check_entry(d, v, k != sub && !s->entry->access.writable()); !ok) return fail(ok.error());
    bits += PdoMappingEntry::decode(v).bit_length;
  }
  return bits;
}

Expected<std::uint32_t, SdoAbort> PdoConfig::assigned_bits(PdoDirection d, std::uint8_t count, std::uint8_t sub,
                                                           std::uint16_t pdo, std::uint16_t changed_mapping,
                                                           std::uint32_t changed_bits) const noexcept {
  const std::uint16_t assign = assign_index(d);
  std::uint32_t bits = 0;
  for (std::uint8_t k = 1; k <= count; ++k) {
    const ObjectStore::Slot* s = store_.slot(assign, k);
    if (!s) return fail(SdoAbort::ValueTooHigh);
    const std::uint16_t index = (k == sub) ? pdo : store_.get<std::uint16_t>(*s);
    if (!is_mapping_index(index, d) || !store_.contains(index)) return fail(SdoAbort::ValueRange);
    if (index == changed_mapping) {
      bits += changed_bits;
      continue;
    }
    auto b = mapping_bits(d, index, store_.get<std::uint8_t>(index, 0));
    if (!b) return b;
    bits += *b;
  }
  return bits;
}

Expected<void, SdoAbort> PdoConfig::on_write(ObjectStore&, const WriteRequest& r) noexcept {
  // PDO mapping and assignment change in PreOp only (ETG.1000.6 §5.6.7.4.7).
  if (r.state != od::EsmState::PreOp) return fail(SdoAbort::DataTransferDeviceState);
  const PdoDirection d = direction_of(r.index);
  if (is_mapping_index(r.index)) return check_mapping_write(d, r);
  return check_assign_write(d, r);
}

Expected<void, SdoAbort> PdoConfig::check_mapping_write(PdoDirection d, const WriteRequest& r) const noexcept {
  const std::uint32_t value = static_cast<std::uint32_t>(load_bits(r.data, 32, false));
  if (r.subindex != 0) {
    if (store_.get<std::uint8_t>(r.index, 0) != 0) return fail(SdoAbort::SubindexZeroMustBeZero);
    if (value == 0) return {};  // clearing an entry
    return check_entry(d, value);
  }
  const auto count = static_cast<std::uint8_t>(value);
  if (count == 0) return {};
  auto bits = mapping_bits(d, r.index, count);
  if (!bits) return fail(bits.error());
  if (*bits > max_bytes(d) * 8u) return fail(SdoAbort::PdoLengthExceeded);
  // If this PDO is assigned, the SM's total must still fit.
  const std::uint8_t assigned = store_.get<std::uint8_t>(assign_index(d), 0);
  auto total = assigned_bits(d, assigned, 0, 0, r.index, *bits);
  if (total && *total > max_bytes(d) * 8u) return fail(SdoAbort::PdoLengthExceeded);
  return {};
}

Expected<void, SdoAbort> PdoConfig::check_assign_write(PdoDirection d, const WriteRequest& r) const noexcept {
  if (r.subindex != 0) {
    if (store_.get<std::uint8_t>(r.index, 0) != 0) return fail(SdoAbort::SubindexZeroMustBeZero);
    const auto pdo = static_cast<std::uint16_t>(load_bits(r.data, 16, false));
    if (pdo != 0 && (!is_mapping_index(pdo, d) || !store_.contains(pdo))) return fail(SdoAbort::ValueRange);
    return {};
  }
  const auto count = static_cast<std::uint8_t>(load_bits(r.data, 8, false));
  auto bits = assigned_bits(d, count);
  if (!bits) return fail(bits.error());
  if (*bits > max_bytes(d) * 8u) return fail(SdoAbort::PdoLengthExceeded);
  return {};
}

void PdoConfig::after_write(ObjectStore&, std::uint16_t, std::uint8_t) noexcept { rebuild(); }

void PdoConfig::build(PdoDirection d, ProcessDataImage& image) noexcept {
  image.clear();
  const std::uint16_t assign = assign_index(d);
  const std::uint8_t pdos = store_.get<std::uint8_t>(assign, 0);
  for (std::uint8_t k = 1; k <= pdos; ++k) {
    const std::uint16_t pdo = store_.get<std::uint16_t>(assign, k);
    const std::uint8_t entries = store_.get<std::uint8_t>(pdo, 0);
    for (std::uint8_t j = 1; j <= entries; ++j) {
      const PdoMappingEntry m = PdoMappingEntry::decode(store_.get<std::uint32_t>(pdo, j));
      ObjectStore::Slot* s = m.is_gap() ? nullptr : store_.slot(m.index, m.subindex);
      if (!image.add(m.bit_length, s)) return;
    }
  }
}

void PdoConfig::rebuild() noexcept {
  build(PdoDirection::Rx, outputs_);
  build(PdoDirection::Tx, inputs_);
}

Expected<void, SdoAbort> PdoConfig::validate(PdoDirection d) const noexcept {
  auto bits = assigned_bits(d, store_.get<std::uint8_t>(assign_index(d), 0));
  if (!bits) return fail(bits.error());
  if (*bits > max_bytes(d) * 8u) return fail(SdoAbort::PdoLengthExceeded);
  return {};
}

esc::AlStatusCode PdoConfig::check_safeop(esc::Pdi& pdi) noexcept {
  rebuild();
  if (store_.contains(kRxPdoAssign) && !validate(PdoDirection::Rx)) return esc::AlStatusCode::InvalidOutputMapping;
  if (store_.contains(kTxPdoAssign) && !validate(PdoDirection::Tx)) return esc::AlStatusCode::InvalidInputMapping;
  auto sm_matches = [&](unsigned sm, std::uint32_t bytes) {
    const std::uint16_t r = esc::reg::sync_manager(sm);
    const std::uint16_t length = pdi.read_u16(static_cast<std::uint16_t>(r + esc::reg::sm::kLength));
    const bool enabled = pdi.read_u8(static_cast<std::uint16_t>(r + esc::reg::sm::kActivate)) & bits::kSmActivateEnable;
    if (bytes == 0) return !enabled || length == 0;
    return enabled && length == bytes;
  };
  if (!sm_matches(kOutputsSm, outputs_.byte_length())) return esc::AlStatusCode::InvalidOutputConfiguration;
  if (!sm_matches(kInputsSm, inputs_.byte_length())) return esc::AlStatusCode::InvalidInputConfiguration;
  return esc::AlStatusCode::NoError;
}

}  // namespace ecat::coe
