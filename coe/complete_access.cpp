#include "coe/complete_access.hpp"

#include <algorithm>
#include <cstring>

#include "coe/bit_copy.hpp"

namespace ecat::coe {
namespace {

constexpr std::size_t kSub0SlotBits = 16;  // sub 0 value + pad byte (ETG.1000.6 §5.6.2.1.2)

std::size_t align_for(const od::Entry& e, std::size_t bit) noexcept {
  return (e.bit_length % 8 == 0) ? (bit + 7) / 8 * 8 : bit;
}

bool in_image(const od::Entry& e, std::uint8_t count) noexcept { return e.subindex >= 1 && e.subindex <= count; }

bool is_composite(const od::Object& o) noexcept { return o.code != od::ObjectCode::Var; }

}  // namespace

Expected<std::size_t, SdoAbort> complete_access_size(const od::Object& object, bool from_sub0,
                                                     std::uint8_t count) noexcept {
  std::size_t bit = from_sub0 ? kSub0SlotBits : 0;
  for (const od::Entry& e : object.entries) {
    if (!in_image(e, count)) continue;
    if (od::is_string(e.type) && e.bit_length == 0) return fail(SdoAbort::CompleteAccessVariableLength);
    bit = align_for(e, bit) + e.bit_length;
  }
  return (bit + 7) / 8;
}

std::size_t max_complete_access_size(const od::Dictionary& dictionary) noexcept {
  std::size_t n = 0;
  for (const od::Object& o : dictionary.objects()) {
    if (!is_composite(o)) continue;
    if (auto s = complete_access_size(o, true, o.max_subindex())) n = std::max(n, *s);
  }
  return n;
}

Expected<std::size_t, SdoAbort> complete_access_upload(ObjectStore& store, std::uint16_t index,
                                                       bool from_sub0, Bytes out,
                                                       od::EsmState state) noexcept {
  const ObjectStore::Slot* s0 = store.slot(index, 0);
  if (!s0) return fail(SdoAbort::NoObject);
  const od::Object* found = store.dictionary().find(index);
  if (!found) return fail(SdoAbort::NoObject);
  const od::Object& object = *found;
  if (!is_composite(object)) return fail(SdoAbort::UnsupportedAccess);
  if (ObjectHooks* h = store.hooks(index)) h->on_read(store, index, 0);
  const std::uint8_t count = store.get<std::uint8_t>(*s0);
  auto size = complete_access_size(object, from_sub0, count);
  if (!size) return size;
  if (*size > out.size()) return fail(SdoAbort::ObjectLengthExceedsMailbox);
  std::fill(out.begin(), out.begin() + static_cast<std::ptrdiff_t>(*size), std::uint8_t{0});
  std::size_t bit = 0;
  if (from_sub0) {
    out[0] = count;
    bit = kSub0SlotBits;
  }
  for (const od::Entry& e : object.entries) {
    if (!in_image(e, count)) continue;
    bit = align_for(e, bit);
    if (e.access.readable_in(state)) {
      if (ObjectHooks* h = store.hooks(index)) h->on_read(store, index, e.subindex);
      put_bits(out.data(), bit, store.value(index, e.subindex).data(), e.bit_length);
    } else if (e.access.readable()) {
      return fail(SdoAbort::DataTransferDeviceState);
    }  // write-only: stays 0
    bit += e.bit_length;
  }
  return *size;
}

Expected<void, SdoAbort> complete_access_download(ObjectStore& store, std::uint16_t index, bool from_sub0,
                                                  ConstBytes data, od::EsmState state,
                                                  Bytes scratch) noexcept {
  ObjectStore::Slot* s0 = store.slot(index, 0);
  if (!s0) return fail(SdoAbort::NoObject);
  const od::Object* found = store.dictionary().find(index);
  if (!found) return fail(SdoAbort::NoObject);
  const od::Object& object = *found;
  if (!is_composite(object)) return fail(SdoAbort::UnsupportedAccess);
  const bool write_sub0 = from_sub0 && s0->entry->access.writable_in(state);
  if (from_sub0 && data.empty()) return fail(SdoAbort::LengthTooLow);
  const std::uint8_t count = from_sub0 ? data[0] : store.get<std::uint8_t>(*s0);
  if (from_sub0 && !write_sub0 && count != store.get<std::uint8_t>(*s0)) {
    return fail(s0->entry->access.writable() ? SdoAbort::DataTransferDeviceState : SdoAbort::ReadOnly);
  }
  if (count > object.max_subindex()) return fail(SdoAbort::ValueTooHigh);
  auto size = complete_access_size(object, from_sub0, count);
  if (!size) return fail(size.error());
  if (data.size() > *size) return fail(SdoAbort::LengthTooHigh);
  if (data.size() < *size) return fail(SdoAbort::LengthTooLow);

  // Keep the old values so a refusal half way leaves the object unchanged.
  std::size_t used = 0;
  for (const od::Entry& e : object.entries) {
    const ConstBytes v = store.value(index, e.subindex);
    if (used + v.size() > scratch.size()) return fail(SdoAbort::OutOfMemory);
    std::memcpy(scratch.data() + used, v.data(), v.size());
    used += v.size();
  }
  auto restore = [&](SdoAbort abort) -> Expected<void, SdoAbort> {
    std::size_t at = 0;
    for (const od::Entry& e : object.entries) {
      ObjectStore::Slot* s = store.slot(index, e.subindex);
      const std::uint32_t n = store.length(*s);
      (void)store.assign(*s, {scratch.data() + at, n});
      at += n;
    }
    if (ObjectHooks* h = store.hooks(index)) h->after_write(store, index, 0);
    return fail(abort);
  };

  const std::uint8_t zero = 0;
  if (write_sub0) {
    if (auto ok = store.write({index, 0, {&zero, 1}, state}); !ok) return restore(ok.error());
  }
  std::size_t bit = from_sub0 ? kSub0SlotBits : 0;
  std::uint8_t value[8]{};
  for (const od::Entry& e : object.entries) {
    if (!in_image(e, count)) continue;
    bit = align_for(e, bit);
    const std::size_t bytes = (e.bit_length + 7u) / 8u;
    if (e.access.writable_in(state)) {
      if (bytes <= sizeof value) {
        get_bits(value, data.data(), bit, e.bit_length);
        if (auto ok = store.write({index, e.subindex, {value, bytes}, state}); !ok) return restore(ok.error());
      } else if (bit % 8 == 0) {
        if (auto ok = store.write({index, e.subindex, data.subspan(bit / 8, bytes), state}); !ok) {
          return restore(ok.error());
        }
      } else {
        return restore(SdoAbort::UnsupportedAccess);
      }
    } else if (e.access.writable()) {
      return restore(SdoAbort::DataTransferDeviceState);
    }  // read-only entries are skipped (ETG.1000.6 as SOES applies it)
    bit += e.bit_length;
  }
  if (write_sub0) {
    if (auto ok = store.write({index, 0, {&count, 1}, state}); !ok) return restore(ok.error());
  }
  return {};
}

}  // namespace ecat::coe
