#include "master/conformance/od_walk.hpp"

namespace ecat::master::conformance {

namespace {
constexpr std::uint16_t kVisibleString = 0x0009;
constexpr std::uint16_t kOctetString = 0x000A;
constexpr std::uint16_t kUnicodeString = 0x000B;
constexpr std::uint16_t kDomain = 0x000F;
}  // namespace

std::size_t sdo_size(std::uint16_t data_type, std::uint16_t bit_length) {
  if (data_type == kVisibleString || data_type == kOctetString || data_type == kUnicodeString ||
      data_type == kDomain) {
    return 0;
  }
  return (bit_length + 7u) / 8u;
}

bool is_signed_type(std::uint16_t t) { return t == 0x0002 || t == 0x0003 || t == 0x0004; }
bool is_integer_type(std::uint16_t t) { return is_signed_type(t) || t == 0x0005 || t == 0x0006 || t == 0x0007; }

Expected<std::optional<WalkedEntry>, SdoError> walk_od(Context& ctx, std::uint16_t from, std::uint8_t value_info,
                                                       const std::function<bool(const WalkedEntry&)>& visit) {
  CoeClient coe = ctx.coe();
  auto list = coe.od_list();
  if (!list) return fail(list.error());
  std::size_t objects = 0;
  for (std::uint16_t index : *list) {
    if (index < from) continue;
    if (ctx.options().max_objects != 0 && objects++ >= ctx.options().max_objects) break;
    auto od = coe.object_description(index);
    if (!od) continue;
    const std::uint8_t last = od->object_code == kObjectCodeVar ? 0 : od->max_subindex;
    for (unsigned sub = 0; sub <= last; ++sub) {
      auto e = coe.entry_description(index, static_cast<std::uint8_t>(sub), value_info);
      if (!e) continue;
      WalkedEntry w{*od, *e};
      if (visit(w)) return std::optional<WalkedEntry>(w);
    }
  }
  return std::optional<WalkedEntry>{};
}

}  // namespace ecat::master::conformance
