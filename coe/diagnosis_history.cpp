#include "coe/diagnosis_history.hpp"

#include <algorithm>

#include "coe/object_store.hpp"

namespace ecat::coe {

DiagnosisHistory::Message DiagnosisHistory::from_emergency(std::uint16_t error_code) noexcept {
  Message m;
  m.diag_code = kDiagCodeEmergency | (std::uint32_t{error_code} << 16);
  m.type = Type::Error;
  return m;
}

DiagnosisHistory::Message DiagnosisHistory::from_al_status(std::uint16_t al_status_code) noexcept {
  Message m;
  m.diag_code = kDiagCodeAlStatus | (std::uint32_t{al_status_code} << 16);
  m.type = Type::Error;
  m.parameters[0] = {kTypeUnsigned16, al_status_code};
  m.parameter_count = 1;
  return m;
}

std::size_t DiagnosisHistory::encode(const Message& m, Nanoseconds time_stamp, Bytes out) noexcept {
  ByteWriter w(out);
  const std::size_t params = std::min(m.parameter_count, kMaxParameters);
  w.u32(m.diag_code);
  w.u16(static_cast<std::uint16_t>(static_cast<unsigned>(m.type) | kMessageLocalTimeStamp |
                                   (params << kParameterCountShift)));
  w.u16(m.text_id);
  w.u64(static_cast<std::uint64_t>(std::max(time_stamp, Nanoseconds{0}).count()));
  for (std::size_t i = 0; i < params; ++i) {
    const Parameter& p = m.parameters[i];
    w.u16(p.data_type);
    switch (p.data_type) {
      case kTypeUnsigned8: w.u8(static_cast<std::uint8_t>(p.value)); break;
      case kTypeUnsigned16: w.u16(static_cast<std::uint16_t>(p.value)); break;
      default: w.u32(p.value); break;
    }
  }
  return w.ok() ? w.position() : 0;
}

DiagnosisHistory::DiagnosisHistory(ObjectStore& store) noexcept : store_(store) {
  const ObjectStore::Slot* max = store.slot(kIndex, kMaxMessages);
  if (!max || !store.slot(kIndex, kFlags)) return;
  std::size_t n = 0;
  const std::size_t wanted = store.get<std::uint8_t>(*max);
  while (n < wanted && store.slot(kIndex, subindex_of(n)) != nullptr) ++n;
  capacity_ = n;
  if (capacity_ == 0) return;
  seq_.assign(capacity_, 0);
  (void)store.set_hooks(kIndex, this);
  if (store.slot(kActualTimeStampIndex, 0) != nullptr) (void)store.set_hooks(kActualTimeStampIndex, this);
  clear_all();
}

std::uint16_t DiagnosisHistory::flags() const noexcept { return store_.get<std::uint16_t>(kIndex, kFlags); }

void DiagnosisHistory::set_flags(std::uint16_t f) noexcept { (void)store_.set<std::uint16_t>(kIndex, kFlags, f); }

void DiagnosisHistory::clear_all() noexcept {
  std::fill(seq_.begin(), seq_.end(), 0);
  newest_seq_ = 0;
  acknowledged_seq_ = 0;
  newest_ = 0;
  newest_read_ = false;
  overwritten_ack_ = false;
  overflow_ = false;
  for (std::size_t s = 0; s < capacity_; ++s) (void)store_.assign(kIndex, subindex_of(s), {});
  set_flags(static_cast<std::uint16_t>(flags() & ~kFlagOverflow));
  publish_state();
}

void DiagnosisHistory::publish_state() noexcept {
  const bool ack_mode = (flags() & kFlagAcknowledgeMode) != 0;
  const std::uint8_t newest = newest_seq_ == 0 ? 0 : subindex_of(newest_);
  std::uint8_t acknowledged = 0;
  if (acknowledged_seq_ > 0 && !overwritten_ack_) {
    for (std::size_t s = 0; s < capacity_; ++s) {
      if (seq_[s] == acknowledged_seq_) acknowledged = subindex_of(s);
    }
  }
  const bool available = ack_mode ? newest_seq_ > acknowledged_seq_ : (newest_seq_ > 0 && !newest_read_);
  (void)store_.set<std::uint8_t>(kIndex, kNewestMessage, newest);
  (void)store_.set<std::uint8_t>(kIndex, kNewestAcknowledged, acknowledged);
  (void)store_.set<std::uint8_t>(kIndex, kNewMessagesAvailable, available ? 1 : 0);
}

bool DiagnosisHistory::add(const Message& m, Nanoseconds now, bool* emergency) noexcept {
  if (emergency) *emergency = false;
  if (!present()) return false;
  const std::uint16_t f = flags();
  const std::uint16_t disabled = m.type == Type::Info      ? kFlagDisableInfo
                                 : m.type == Type::Warning ? kFlagDisableWarning
                                                           : kFlagDisableError;
  if ((f & disabled) != 0) return false;
  const std::size_t slot = newest_seq_ == 0 ? 0 : (newest_ + 1) % capacity_;
  const bool unacknowledged = seq_[slot] != 0 && seq_[slot] > acknowledged_seq_;
  if (unacknowledged) {
    overflow_ = true;
    set_flags(static_cast<std::uint16_t>(f | kFlagOverflow));
    if ((f & kFlagAcknowledgeMode) != 0) return false;  // full of unacknowledged messages: dropped
  }
  if (seq_[slot] != 0 && seq_[slot] == acknowledged_seq_) overwritten_ack_ = true;
  std::array<std::uint8_t, kHeaderBytes + kMaxParameters * (2 + 4)> raw{};
  const std::size_t n = encode(m, now, raw);
  ObjectStore::Slot* s = store_.slot(kIndex, subindex_of(slot));
  if (!s || n == 0 || !store_.assign(*s, {raw.data(), std::min<std::size_t>(n, s->capacity)})) return false;
  seq_[slot] = next_seq_++;
  newest_ = slot;
  newest_seq_ = seq_[slot];
  newest_read_ = false;
  publish_state();
  if (emergency) *emergency = (f & kFlagEmergency) != 0;
  return true;
}

void DiagnosisHistory::on_read(ObjectStore& store, std::uint16_t index, std::uint8_t subindex) noexcept {
  if (index == kActualTimeStampIndex) {
    (void)store.set<std::uint64_t>(kActualTimeStampIndex, 0, static_cast<std::uint64_t>(std::max(now_, Nanoseconds{0}).count()));
    return;
  }
  if (index != kIndex || newest_seq_ == 0 || subindex != subindex_of(newest_)) return;
  if (!newest_read_) {
    newest_read_ = true;
    publish_state();
  }
}

Expected<void, SdoAbort> DiagnosisHistory::on_write(ObjectStore& store, const WriteRequest& request) noexcept {
  (void)store;
  if (request.index != kIndex || request.data.empty()) return {};
  if (request.subindex == kNewestAcknowledged) {
    const std::uint8_t v = request.data[0];
    if (v == 0) return {};  // clears every message (after_write)
    if (v < kFirstMessage) return fail(SdoAbort::ValueTooLow);
    if (v >= kFirstMessage + capacity_) return fail(SdoAbort::ValueTooHigh);
    if (seq_[v - kFirstMessage] == 0) return fail(SdoAbort::ValueRange);  // no message there
  } else if (request.subindex == kFlags && request.data.size() >= 2) {
    const auto f = static_cast<std::uint16_t>(request.data[0] | (request.data[1] << 8));
    if ((f & ~(kFlagsWritable | kFlagOverflow)) != 0) return fail(SdoAbort::ValueRange);  // reserved bits
  }
  return {};
}

void DiagnosisHistory::after_write(ObjectStore& store, std::uint16_t index, std::uint8_t subindex) noexcept {
  if (index != kIndex) return;
  if (subindex == kNewestAcknowledged) {
    const std::uint8_t v = store.get<std::uint8_t>(kIndex, kNewestAcknowledged);
    if (v == 0) {
      clear_all();
      return;
    }
    acknowledged_seq_ = seq_[v - kFirstMessage];
    overwritten_ack_ = false;
    publish_state();
  } else if (subindex == kFlags) {
    // Bit 5 is the slave's: a write keeps it as it was.
    const std::uint16_t written = store.get<std::uint16_t>(kIndex, kFlags);
    set_flags(static_cast<std::uint16_t>((written & kFlagsWritable) | (overflow_ ? kFlagOverflow : 0)));
    publish_state();
  }
}

}  // namespace ecat::coe
