#include "coe/sdo_info.hpp"

#include <algorithm>

#include "coe/coe_header.hpp"

namespace ecat::coe {
namespace {

constexpr std::size_t kPrefix = CoeHeader::kSize + info::kHeaderSize;

void write_header(ByteWriter& w, std::uint8_t opcode, bool incomplete, std::uint16_t fragments_left) noexcept {
  CoeHeader::write(w, CoeService::SdoInformation);
  w.u8(static_cast<std::uint8_t>(opcode | (incomplete ? info::kIncomplete : 0)));
  w.u8(0);
  w.u16(fragments_left);
}

void write_name(ByteWriter& w, const std::string& name) noexcept {
  const std::size_t n = std::min(name.size(), w.remaining());
  w.bytes({reinterpret_cast<const std::uint8_t*>(name.data()), n});
}

bool any_entry(const od::Object& o, std::uint16_t bits) noexcept {
  return std::any_of(o.entries.begin(), o.entries.end(), [bits](const od::Entry& e) { return e.access.bits & bits; });
}

}  // namespace

bool SdoInfo::in_list(const od::Object& object, info::ListType type) noexcept {
  switch (type) {
    case info::ListType::All: return true;
    case info::ListType::RxPdoMappable: return any_entry(object, od::Access::kRxPdoMappable);
    case info::ListType::TxPdoMappable: return any_entry(object, od::Access::kTxPdoMappable);
    case info::ListType::Backup: return any_entry(object, od::Access::kBackup);
    case info::ListType::Settings: return any_entry(object, od::Access::kSetting);
    case info::ListType::Counts: return false;
  }
  return false;
}

Expected<std::size_t, MailboxError> SdoInfo::handle(ConstBytes request, Bytes reply) noexcept {
  pending_ = false;
  if (reply.size() < kPrefix + sizeof(std::uint32_t)) return fail(MailboxError::NoMoreMemory);
  ByteReader r(request);
  const std::uint8_t opcode = r.u8() & info::kOpcodeMask;
  r.skip(3);  // reserved, fragments left
  if (!r.ok()) return fail(MailboxError::SizeTooShort);
  std::size_t n = 0;
  switch (opcode) {
    case info::kGetOdListRequest: n = od_list(r, reply); break;
    case info::kGetObjectDescriptionRequest: n = object_description(r, reply); break;
    case info::kGetEntryDescriptionRequest: n = entry_description(r, reply); break;
    default: return fail(MailboxError::ServiceNotSupported);
  }
  if (n == 0) return fail(MailboxError::SizeTooShort);
  return n;
}

std::size_t SdoInfo::error(Bytes reply, SdoAbort code) noexcept {
  ByteWriter w(reply);
  write_header(w, info::kErrorRequest, false, 0);
  w.u32(to_u32(code));
  return w.position();
}

std::size_t SdoInfo::od_list(ByteReader& r, Bytes reply) noexcept {
  const std::uint16_t type = r.u16();
  if (!r.ok()) return 0;
  const auto objects = store_.dictionary().objects();
  if (type == static_cast<std::uint16_t>(info::ListType::Counts)) {
    ByteWriter w(reply);
    write_header(w, info::kGetOdListResponse, false, 0);
    w.u16(type);
    for (std::uint16_t t = 1; t <= info::kListTypeCount; ++t) {
      w.u16(static_cast<std::uint16_t>(std::count_if(objects.begin(), objects.end(), [t](const od::Object& o) {
        return in_list(o, static_cast<info::ListType>(t));
      })));
    }
    return w.ok() ? w.position() : error(reply, SdoAbort::ObjectLengthExceedsMailbox);
  }
  if (type > info::kListTypeCount) return error(reply, SdoAbort::UnsupportedAccess);
  list_ = static_cast<info::ListType>(type);
  const std::size_t total = static_cast<std::size_t>(std::count_if(
      objects.begin(), objects.end(), [this](const od::Object& o) { return in_list(o, list_); }));
  // First fragment carries the list type; the later ones indices only.
  const std::size_t first = (reply.size() - kPrefix - sizeof(std::uint16_t)) / sizeof(std::uint16_t);
  const std::size_t later = (reply.size() - kPrefix) / sizeof(std::uint16_t);
  std::size_t fragments = 1;
  if (total > first) fragments += (total - first + later - 1) / later;
  fragments_left_ = static_cast<std::uint16_t>(fragments - 1);
  position_ = 0;
  return write_list_fragment(reply, true);
}

std::size_t SdoInfo::write_list_fragment(Bytes reply, bool first) noexcept {
  ByteWriter w(reply);
  write_header(w, info::kGetOdListResponse, fragments_left_ > 0, fragments_left_);
  if (first) w.u16(static_cast<std::uint16_t>(list_));
  const auto objects = store_.dictionary().objects();
  while (position_ < objects.size() && w.remaining() >= sizeof(std::uint16_t)) {
    const od::Object& o = objects[position_++];
    if (in_list(o, list_)) w.u16(o.index);
  }
  pending_ = fragments_left_ > 0;
  if (fragments_left_ > 0) --fragments_left_;
  return w.position();
}

std::size_t SdoInfo::next_fragment(Bytes reply) noexcept {
  if (!pending_ || reply.size() < kPrefix + sizeof(std::uint16_t)) return 0;
  return write_list_fragment(reply, false);
}

std::size_t SdoInfo::object_description(ByteReader& r, Bytes reply) noexcept {
  const std::uint16_t index = r.u16();
  if (!r.ok()) return 0;
  const od::Object* o = store_.dictionary().find(index);
  if (!o) return error(reply, SdoAbort::NoObject);
  ByteWriter w(reply);
  write_header(w, info::kGetObjectDescriptionResponse, false, 0);
  w.u16(index);
  const bool var = o->code == od::ObjectCode::Var;
  w.u16(static_cast<std::uint16_t>(var ? o->entries.front().type : o->type));
  w.u8(var ? 0 : o->max_subindex());
  w.u8(static_cast<std::uint8_t>(o->code));
  write_name(w, o->name);
  return w.position();
}

std::size_t SdoInfo::entry_description(ByteReader& r, Bytes reply) noexcept {
  const std::uint16_t index = r.u16();
  const std::uint8_t sub = r.u8();
  const std::uint8_t wanted = r.u8();
  if (!r.ok()) return 0;
  if (!store_.contains(index)) return error(reply, SdoAbort::NoObject);
  const ObjectStore::Slot* s = store_.slot(index, sub);
  if (!s) return error(reply, SdoAbort::NoSubindex);
  const od::Entry& e = *s->entry;
  // Optional elements are sent only when the entry has them; the reply's
  // value info says which ones follow. No numeric unit is kept, so no unit.
  const bool fixed = !od::is_string(e.type);
  std::uint8_t given = wanted & (info::kValueInfoAccess | info::kValueInfoCategory | info::kValueInfoMappable);
  if ((wanted & info::kValueInfoDefault) && fixed && !e.default_value.empty()) given |= info::kValueInfoDefault;
  if ((wanted & info::kValueInfoMinimum) && fixed && e.has_min()) given |= info::kValueInfoMinimum;
  if ((wanted & info::kValueInfoMaximum) && fixed && e.has_max()) given |= info::kValueInfoMaximum;
  ByteWriter w(reply);
  write_header(w, info::kGetEntryDescriptionResponse, false, 0);
  w.u16(index);
  w.u8(sub);
  w.u8(given);
  w.u16(static_cast<std::uint16_t>(e.type));
  w.u16(e.bit_length);
  w.u16(e.access.bits & info::kObjectAccessMask);
  const std::size_t width = (e.bit_length + 7u) / 8u;
  auto value = [&](const od::Value& v) {
    for (std::size_t i = 0; i < width; ++i) w.u8(i < v.size() ? v[i] : 0);
  };
  if (given & info::kValueInfoDefault) value(e.default_value);
  if (given & info::kValueInfoMinimum) value(e.min_value);
  if (given & info::kValueInfoMaximum) value(e.max_value);
  write_name(w, e.name);
  return w.ok() ? w.position() : error(reply, SdoAbort::ObjectLengthExceedsMailbox);
}

}  // namespace ecat::coe
