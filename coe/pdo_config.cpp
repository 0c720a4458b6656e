#include "coe/pdo_config.hpp"

#include <algorithm>

#include "coe/sm_bits.hpp"
#include "esc/registers.hpp"
#include "od/process_directions.hpp"

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

// The process-data SMs of the device: SM n of type Outputs/Inputs with
// assignment 1C10h+n. A device described without SMs (built in code) gets
// SM2 outputs / SM3 inputs, the ETG.1000.6 default.
std::vector<SmLayout> process_sms(const od::DeviceDescription& device, std::size_t capacity) {
  std::vector<SmLayout> out;
  for (std::size_t n = 0; n < device.sync_managers.size(); ++n) {
    const od::SmType t = device.sync_managers[n].type;
    if (t != od::SmType::Outputs && t != od::SmType::Inputs) continue;
    const bool rx = t == od::SmType::Outputs;
    out.push_back(SmLayout{static_cast<std::uint8_t>(n), rx ? PdoDirection::Rx : PdoDirection::Tx,
                           static_cast<std::uint16_t>(kSmPdoAssignBase + n), sm_max(device, static_cast<unsigned>(n)),
                           od::has_process_data(device, rx), ProcessDataImage(capacity)});
  }
  if (out.empty()) {
    out.push_back(SmLayout{kOutputsSm, PdoDirection::Rx, kRxPdoAssign, sm_max(device, kOutputsSm), true,
                           ProcessDataImage(capacity)});
    out.push_back(SmLayout{kInputsSm, PdoDirection::Tx, kTxPdoAssign, sm_max(device, kInputsSm), true,
                           ProcessDataImage(capacity)});
  }
  return out;
}

}  // namespace

PdoConfig::PdoConfig(ObjectStore& store, const od::DeviceDescription& device)
    : store_(store), sms_(process_sms(device, mapping_capacity(store.dictionary()))) {
  for (const od::Object& o : store.dictionary().objects()) {
    if (is_mapping_index(o.index) || sm_of_assign(o.index) != nullptr) store.set_hooks(o.index, this);
  }
  rebuild();
}

const SmLayout* PdoConfig::sm_of_assign(std::uint16_t index) const noexcept {
  for (const SmLayout& sm : sms_) {
    if (sm.assign == index) return &sm;
  }
  return nullptr;
}

const ProcessDataImage& PdoConfig::outputs() const noexcept {
  for (const SmLayout& sm : sms_) {
    if (sm.direction == PdoDirection::Rx) return sm.image;
  }
  return empty_;
}

const ProcessDataImage& PdoConfig::inputs() const noexcept {
  for (const SmLayout& sm : sms_) {
    if (sm.direction == PdoDirection::Tx) return sm.image;
  }
  return empty_;
}

std::uint32_t PdoConfig::max_bytes(PdoDirection d) const noexcept {
  std::uint32_t n = 0;
  for (const SmLayout& sm : sms_) {
    if (sm.direction == d) n = std::max(n, sm.max_bytes);
  }
  return n;
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
  for (unsigned k = 1; k <= count; ++k) {  // unsigned: a count of 255 must end
    const ObjectStore::Slot* s = store_.slot(index, static_cast<std::uint8_t>(k));
    if (!s) return fail(SdoAbort::ValueTooHigh);
    const std::uint32_t v = (k == sub) ? value : store_.get<std::uint32_t>(*s);
    if (auto ok = check_entry(d, v, k != sub && !s->entry->access.writable()); !ok) return fail(ok.error());
    bits += PdoMappingEntry::decode(v).bit_length;
  }
  return bits;
}

Expected<std::uint32_t, SdoAbort> PdoConfig::assigned_bits(const SmLayout& sm, std::uint8_t count, std::uint8_t sub,
                                                           std::uint16_t pdo, std::uint16_t changed_mapping,
                                                           std::uint32_t changed_bits) const noexcept {
  const std::uint16_t assign = sm.assign;
  const PdoDirection d = sm.direction;
  std::uint32_t bits = 0;
  for (unsigned k = 1; k <= count; ++k) {  // unsigned: a count of 255 must end
    const ObjectStore::Slot* s = store_.slot(assign, static_cast<std::uint8_t>(k));
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
  if (is_mapping_index(r.index)) {
    return check_mapping_write(is_mapping_index(r.index, PdoDirection::Tx) ? PdoDirection::Tx : PdoDirection::Rx, r);
  }
  const SmLayout* sm = sm_of_assign(r.index);
  if (sm == nullptr) return {};  // hooks are set on mapping and assignment objects only
  return check_assign_write(*sm, r);
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
  // If this PDO is assigned, each SM's total must still fit.
  for (const SmLayout& sm : sms_) {
    if (sm.direction != d || !store_.contains(sm.assign)) continue;
    const std::uint8_t assigned = store_.get<std::uint8_t>(sm.assign, 0);
    auto total = assigned_bits(sm, assigned, 0, 0, r.index, *bits);
    if (total && *total > sm.max_bytes * 8u) return fail(SdoAbort::PdoLengthExceeded);
  }
  return {};
}

Expected<void, SdoAbort> PdoConfig::check_assign_write(const SmLayout& sm, const WriteRequest& r) const noexcept {
  const PdoDirection d = sm.direction;
  if (r.subindex != 0) {
    if (store_.get<std::uint8_t>(r.index, 0) != 0) return fail(SdoAbort::SubindexZeroMustBeZero);
    const auto pdo = static_cast<std::uint16_t>(load_bits(r.data, 16, false));
    if (pdo != 0 && (!is_mapping_index(pdo, d) || !store_.contains(pdo))) return fail(SdoAbort::ValueRange);
    return {};
  }
  const auto count = static_cast<std::uint8_t>(load_bits(r.data, 8, false));
  auto bits = assigned_bits(sm, count);
  if (!bits) return fail(bits.error());
  if (*bits > sm.max_bytes * 8u) return fail(SdoAbort::PdoLengthExceeded);
  return {};
}

void PdoConfig::after_write(ObjectStore&, std::uint16_t, std::uint8_t) noexcept { rebuild(); }

void PdoConfig::build(SmLayout& sm) noexcept {
  ProcessDataImage& image = sm.image;
  image.clear();
  if (!store_.contains(sm.assign)) return;
  const std::uint8_t pdos = store_.get<std::uint8_t>(sm.assign, 0);
  for (unsigned k = 1; k <= pdos; ++k) {  // unsigned: counts of 255 must end
    const std::uint16_t pdo = store_.get<std::uint16_t>(sm.assign, static_cast<std::uint8_t>(k));
    const std::uint8_t entries = store_.get<std::uint8_t>(pdo, 0);
    for (unsigned j = 1; j <= entries; ++j) {
      const PdoMappingEntry m = PdoMappingEntry::decode(store_.get<std::uint32_t>(pdo, static_cast<std::uint8_t>(j)));
      ObjectStore::Slot* s = m.is_gap() ? nullptr : store_.slot(m.index, m.subindex);
      if (!image.add(m.bit_length, s)) return;
    }
  }
}

void PdoConfig::rebuild() noexcept {
  for (SmLayout& sm : sms_) build(sm);
  if (rebuilds_ != nullptr) ++*rebuilds_;
}

Expected<void, SdoAbort> PdoConfig::validate(const SmLayout& sm) const noexcept {
  auto bits = assigned_bits(sm, store_.get<std::uint8_t>(sm.assign, 0));
  if (!bits) return fail(bits.error());
  if (*bits > sm.max_bytes * 8u) return fail(SdoAbort::PdoLengthExceeded);
  return {};
}

Expected<void, SdoAbort> PdoConfig::validate(PdoDirection d) const noexcept {
  for (const SmLayout& sm : sms_) {
    if (sm.direction != d || !store_.contains(sm.assign)) continue;
    if (auto ok = validate(sm); !ok) return ok;
  }
  return {};
}

// ETG.1000.6 §6.4.1 / SSC CheckSmSettings, per SM: the mappings first
// (0025h outputs, 0024h inputs), then each SM's length and enable against
// its layout (001Dh outputs, 001Eh inputs). An SM of a direction the device
// has no process data for is not checked (SSC without MAX_PD_OUTPUT_SIZE).
esc::AlStatusCode PdoConfig::check_safeop(esc::Pdi& pdi) noexcept {
  rebuild();
  for (const PdoDirection d : {PdoDirection::Rx, PdoDirection::Tx}) {
    for (const SmLayout& sm : sms_) {
      if (sm.direction != d || !sm.checked || !store_.contains(sm.assign) || validate(sm)) continue;
      return d == PdoDirection::Rx ? esc::AlStatusCode::InvalidOutputMapping : esc::AlStatusCode::InvalidInputMapping;
    }
  }
  auto sm_matches = [&](unsigned n, std::uint32_t bytes) {
    const std::uint16_t r = esc::reg::sync_manager(n);
    const std::uint16_t length = pdi.read_u16(static_cast<std::uint16_t>(r + esc::reg::sm::kLength));
    const bool enabled = pdi.read_u8(static_cast<std::uint16_t>(r + esc::reg::sm::kActivate)) & bits::kSmActivateEnable;
    if (bytes == 0) return !enabled || length == 0;
    return enabled && length == bytes;
  };
  for (const PdoDirection d : {PdoDirection::Rx, PdoDirection::Tx}) {
    for (const SmLayout& sm : sms_) {
      if (sm.direction != d || !sm.checked || sm_matches(sm.sm, sm.image.byte_length())) continue;
      return d == PdoDirection::Rx ? esc::AlStatusCode::InvalidOutputConfiguration
                                   : esc::AlStatusCode::InvalidInputConfiguration;
    }
  }
  return esc::AlStatusCode::NoError;
}

}  // namespace ecat::coe
