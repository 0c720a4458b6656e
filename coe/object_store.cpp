#include "coe/object_store.hpp"

#include <algorithm>
#include <limits>
#include <vector>

#include "coe/pdo_mapping.hpp"

namespace ecat::coe {
namespace {

std::uint32_t capacity_of(const od::Entry& e, const ObjectStore::Options& options) noexcept {
  if (od::is_string(e.type)) {
    if (e.bit_length > 0) return (e.bit_length + 7u) / 8u;
    // A const string of unbounded length never changes (od::Access::is_const):
    // its default is all it will ever hold. Reserving variable_capacity
    // (64 KiB) for each cost the CiA 301 profile's 1008h/1009h/100Ah 192 KiB
    // per slave (issue 16: 10,000 I/O slaves in one process).
    if (e.access.is_const) return static_cast<std::uint32_t>(e.default_value.size());
    return options.variable_capacity;
  }
  return std::max<std::uint32_t>(1, (e.bit_length + 7u) / 8u);
}

// Copied by the PDO images every cycle: a mappable number.
bool is_cyclic(const ObjectStore::Slot& s) noexcept {
  return !s.variable() && (s.entry->access.rx_mappable() || s.entry->access.tx_mappable());
}

// A number's default, at most 4 bytes (an assignment's PDO index, a
// mapping's entry, a count); 0 for a missing entry.
std::uint32_t default_word(const ObjectStore::Slot* s) noexcept {
  if (s == nullptr) return 0;
  const od::Value& v = s->entry->default_value;
  const std::size_t n = std::min<std::size_t>(v.size(), sizeof(std::uint32_t));
  return static_cast<std::uint32_t>(load_bits({v.data(), n}, static_cast<unsigned>(n * 8), false));
}

constexpr std::uint32_t kLastSubindex = std::numeric_limits<std::uint8_t>::max();

}  // namespace

// The numbers the dictionary's default PDO assignment maps, in the order
// their images hold them: each assignment object 1C10h+n in turn, its PDOs
// in order, each PDO's entries in order (gaps and repeats left out).
std::vector<ObjectStore::Slot*> ObjectStore::default_image_order() {
  std::vector<Slot*> order;
  std::vector<bool> listed(slots_.size(), false);
  for (std::uint16_t a = kSmPdoAssignBase; a < kSmPdoAssignBase + kSmPdoAssignCount; ++a) {
    const std::uint32_t pdos = default_word(slot(a, 0));
    for (std::uint32_t p = 1; p <= pdos && p <= kLastSubindex; ++p) {
      const auto pdo = static_cast<std::uint16_t>(default_word(slot(a, static_cast<std::uint8_t>(p))));
      if (!is_mapping_index(pdo)) continue;
      const std::uint32_t n = default_word(slot(pdo, 0));
      for (std::uint32_t e = 1; e <= n && e <= kLastSubindex; ++e) {
        const PdoMappingEntry m = PdoMappingEntry::decode(default_word(slot(pdo, static_cast<std::uint8_t>(e))));
        Slot* t = m.is_gap() ? nullptr : slot(m.index, m.subindex);
        if (t == nullptr || t->variable() || listed[static_cast<std::size_t>(t - slots_.data())]) continue;
        listed[static_cast<std::size_t>(t - slots_.data())] = true;
        order.push_back(t);
      }
    }
  }
  return order;
}

ObjectStore::ObjectStore(const od::Dictionary& dictionary, Options options) : dictionary_(dictionary) {
  // Exact sizes up front: one store per slave, thousands in a chain (issue 16).
  std::size_t entries = 0;
  for (const od::Object& o : dictionary.objects()) entries += o.entries.size();
  slots_.reserve(entries);
  objects_.reserve(dictionary.size());
  for (const od::Object& o : dictionary.objects()) {
    ObjectRange r;
    r.index = o.index;
    r.first = static_cast<std::uint32_t>(slots_.size());
    for (const od::Entry& e : o.entries) {
      Slot s;
      s.entry = &e;
      s.is_string = od::is_string(e.type) ? 1 : 0;
      s.capacity = std::min(capacity_of(e, options), kMaxCapacity) & kMaxCapacity;
      max_capacity_ = std::max(max_capacity_, s.capacity);
      slots_.push_back(s);
    }
    r.count = static_cast<std::uint16_t>(o.entries.size());
    objects_.push_back(r);
  }
  // The values the cyclic copies touch every cycle first and side by side:
  // those the default PDO assignment maps in the order of their images (a
  // copy plan then moves each run of them as one block, coe::ProcessData),
  // the other PDO-mappable numbers, then the rest. A drive's process data
  // then lies in a few cache lines instead of across the whole buffer
  // (issue 30 item 1: the lines a drive touches per cycle at 1000 drives).
  std::uint32_t offset = 0;
  std::vector<bool> placed(slots_.size(), false);
  auto place = [&](Slot& s) {
    if (s.variable()) offset += kLengthPrefix;
    s.offset = offset;
    offset += s.capacity;
    placed[static_cast<std::size_t>(&s - slots_.data())] = true;
  };
  for (Slot* s : default_image_order()) place(*s);
  for (bool cyclic : {true, false}) {
    for (Slot& s : slots_) {
      if (!placed[static_cast<std::size_t>(&s - slots_.data())] && is_cyclic(s) == cyclic) place(s);
    }
  }
  buffer_.assign(offset, 0);
  reset_to_defaults();
}

void ObjectStore::load_default(Slot& s) noexcept {
  const od::Value& d = s.entry->default_value;
  std::uint8_t* p = buffer_.data() + s.offset;
  std::fill(p, p + s.capacity, std::uint8_t{0});
  const std::size_t n = std::min<std::size_t>(d.size(), s.capacity);
  std::copy_n(d.begin(), n, p);
  if (s.variable()) store_le<std::uint32_t>(p - kLengthPrefix, static_cast<std::uint32_t>(n));
}

std::uint16_t ObjectStore::index_of(const Slot& s) const noexcept {
  const auto at = static_cast<std::uint32_t>(&s - slots_.data());
  auto it = std::upper_bound(objects_.begin(), objects_.end(), at,
                             [](std::uint32_t a, const ObjectRange& r) { return a < r.first; });
  return it == objects_.begin() ? 0 : std::prev(it)->index;
}

void ObjectStore::reset_to_defaults() noexcept {
  ++generation_;
  for (Slot& s : slots_) load_default(s);
}

const ObjectStore::ObjectRange* ObjectStore::range(std::uint16_t index) const noexcept {
  auto it = std::lower_bound(objects_.begin(), objects_.end(), index,
                             [](const ObjectRange& r, std::uint16_t i) { return r.index < i; });
  return (it != objects_.end() && it->index == index) ? &*it : nullptr;
}

bool ObjectStore::contains(std::uint16_t index) const noexcept { return range(index) != nullptr; }

bool ObjectStore::set_hooks(std::uint16_t index, ObjectHooks* hooks) noexcept {
  auto* r = const_cast<ObjectRange*>(range(index));
  if (!r) return false;
  r->hooks = hooks;
  return true;
}

ObjectHooks* ObjectStore::hooks(std::uint16_t index) const noexcept {
  const ObjectRange* r = range(index);
  return r ? r->hooks : nullptr;
}

const ObjectStore::Slot* ObjectStore::slot(std::uint16_t index, std::uint8_t subindex) const noexcept {
  const ObjectRange* r = range(index);
  if (!r) return nullptr;
  auto first = slots_.begin() + r->first;
  auto last = first + r->count;
  auto it = std::lower_bound(first, last, subindex,
                             [](const Slot& s, std::uint8_t sub) { return s.entry->subindex < sub; });
  return (it != last && it->entry->subindex == subindex) ? &*it : nullptr;
}

ObjectStore::Slot* ObjectStore::slot(std::uint16_t index, std::uint8_t subindex) noexcept {
  return const_cast<Slot*>(static_cast<const ObjectStore*>(this)->slot(index, subindex));
}

ConstBytes ObjectStore::value(std::uint16_t index, std::uint8_t subindex) const noexcept {
  const Slot* s = slot(index, subindex);
  return s ? value(*s) : ConstBytes{};
}

Expected<void, SdoAbort> ObjectStore::assign(std::uint16_t index, std::uint8_t subindex,
                                             ConstBytes data) noexcept {
  Slot* s = slot(index, subindex);
  if (!s) return fail(missing(index));
  return assign(*s, data);
}

Expected<void, SdoAbort> ObjectStore::assign(Slot& s, ConstBytes data) noexcept {
  if (data.size() > s.capacity) return fail(SdoAbort::LengthTooHigh);
  if (!s.variable() && data.size() < s.capacity) return fail(SdoAbort::LengthTooLow);
  std::uint8_t* p = buffer_.data() + s.offset;
  ++generation_;
  if (!data.empty()) std::memcpy(p, data.data(), data.size());
  if (s.variable()) {
    std::fill(p + data.size(), p + s.capacity, std::uint8_t{0});
    store_le<std::uint32_t>(p - kLengthPrefix, static_cast<std::uint32_t>(data.size()));
  }
  return {};
}

Expected<std::size_t, SdoAbort> ObjectStore::read(std::uint16_t index, std::uint8_t subindex,
                                                  Bytes out) noexcept {
  Slot* s = slot(index, subindex);
  if (!s) return fail(missing(index));
  if (ObjectHooks* h = hooks(index)) h->on_read(*this, index, subindex);
  const std::uint32_t n = length(*s);
  if (out.size() < n) return fail(SdoAbort::ObjectLengthExceedsMailbox);
  if (n > 0) std::memcpy(out.data(), buffer_.data() + s->offset, n);
  return std::size_t{n};
}

Expected<void, SdoAbort> ObjectStore::check(const Slot& s, ConstBytes data) const noexcept {
  const od::Entry& e = *s.entry;
  if (data.size() > s.capacity) return fail(SdoAbort::LengthTooHigh);
  if (!s.variable() && data.size() < s.capacity) return fail(SdoAbort::LengthTooLow);
  if (!is_numeric(e.type)) return {};
  // Bit fields and booleans must fit their bit length (CiA 301 §7.1.4).
  if (e.bit_length < 8 * data.size() && e.bit_length < 64) {
    if ((load_bits(data, static_cast<unsigned>(8 * data.size()), false) >> e.bit_length) != 0) {
      return fail(SdoAbort::ValueRange);
    }
  }
  if (e.has_max() && compare_values(e.type, data, e.max_value) > 0) return fail(SdoAbort::ValueTooHigh);
  if (e.has_min() && compare_values(e.type, data, e.min_value) < 0) return fail(SdoAbort::ValueTooLow);
  return {};
}

Expected<void, SdoAbort> ObjectStore::write(const WriteRequest& request) noexcept {
  Slot* s = slot(request.index, request.subindex);
  if (!s) return fail(missing(request.index));
  if (auto ok = check(*s, request.data); !ok) return ok;
  ObjectHooks* h = hooks(request.index);
  if (h) {
    if (auto ok = h->on_write(*this, request); !ok) return ok;
  }
  if (auto ok = assign(*s, request.data); !ok) return ok;
  service_writes_.add({request.index, request.subindex});
  if (h) h->after_write(*this, request.index, request.subindex);
  return {};
}

}  // namespace ecat::coe
