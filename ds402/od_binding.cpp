#include "ds402/od_binding.hpp"

#include <bit>
#include <cstring>
#include <tuple>
#include <type_traits>

#include <utility>

#include "common/le.hpp"

namespace ecat::ds402 {

namespace {

template <typename S, typename T>
struct Field {
  std::uint16_t index;
  std::uint8_t subindex;
  T S::*member;
};
template <typename S, typename T>
constexpr Field<S, T> f(std::uint16_t index, std::uint8_t subindex, T S::*member) {
  return {index, subindex, member};
}

using I = DriveInputs;
using O = DriveOutputs;

// CiA 402-2 object numbers (§8-§14).
constexpr auto kInputs = std::make_tuple(
    f(0x6040, 0, &I::controlword), f(0x6060, 0, &I::modes_of_operation), f(0x607A, 0, &I::target_position),
    f(0x60FF, 0, &I::target_velocity), f(0x6071, 0, &I::target_torque), f(0x60B0, 0, &I::position_offset),
    f(0x60B1, 0, &I::velocity_offset), f(0x60B2, 0, &I::torque_offset), f(0x6081, 0, &I::profile_velocity),
    f(0x6083, 0, &I::profile_acceleration), f(0x6084, 0, &I::profile_deceleration),
    f(0x6085, 0, &I::quick_stop_deceleration), f(0x6087, 0, &I::torque_slope),
    f(0x607F, 0, &I::max_profile_velocity), f(0x6080, 0, &I::max_motor_speed), f(0x6098, 0, &I::homing_method),
    f(0x6099, 1, &I::homing_speed_switch), f(0x6099, 2, &I::homing_speed_zero),
    f(0x609A, 0, &I::homing_acceleration), f(0x607C, 0, &I::home_offset), f(0x607D, 1, &I::software_limit_min),
    f(0x607D, 2, &I::software_limit_max), f(0x6072, 0, &I::max_torque), f(0x60E0, 0, &I::positive_torque_limit),
    f(0x60E1, 0, &I::negative_torque_limit), f(0x6065, 0, &I::following_error_window),
    f(0x6066, 0, &I::following_error_timeout), f(0x6067, 0, &I::position_window),
    f(0x6068, 0, &I::position_window_time), f(0x606D, 0, &I::velocity_window),
    f(0x606E, 0, &I::velocity_window_time), f(0x606F, 0, &I::velocity_threshold),
    f(0x6070, 0, &I::velocity_threshold_time), f(0x605A, 0, &I::quick_stop_option),
    f(0x605B, 0, &I::shutdown_option), f(0x605C, 0, &I::disable_operation_option), f(0x605D, 0, &I::halt_option),
    f(0x605E, 0, &I::fault_reaction_option), f(0x60B8, 0, &I::touch_probe_function),
    f(0x608F, 1, &I::encoder_increments), f(0x608F, 2, &I::motor_revolutions),
    f(0x6091, 1, &I::gear_motor_revolutions), f(0x6091, 2, &I::gear_shaft_revolutions), f(0x6092, 1, &I::feed),
    f(0x6092, 2, &I::feed_shaft_revolutions), f(0x60C1, 1, &I::ip_position), f(0x60C2, 1, &I::ip_period_value),
    f(0x60C2, 2, &I::ip_period_index), f(0x6042, 0, &I::vl_target_velocity), f(0x6046, 1, &I::vl_min_amount),
    f(0x6046, 2, &I::vl_max_amount), f(0x6048, 1, &I::vl_acceleration_delta_speed),
    f(0x6048, 2, &I::vl_acceleration_delta_time), f(0x6049, 1, &I::vl_deceleration_delta_speed),
    f(0x6049, 2, &I::vl_deceleration_delta_time), f(0x604A, 1, &I::vl_quick_stop_delta_speed),
    f(0x604A, 2, &I::vl_quick_stop_delta_time), f(0x604B, 1, &I::vl_setpoint_numerator),
    f(0x604B, 2, &I::vl_setpoint_denominator), f(0x604C, 1, &I::vl_dimension_numerator),
    f(0x604C, 2, &I::vl_dimension_denominator), f(0x604E, 0, &I::vl_velocity_reference),
    f(0x604F, 0, &I::vl_ramp_function_time), f(0x6050, 0, &I::vl_slow_down_time),
    f(0x6051, 0, &I::vl_quick_stop_time), f(0x60C4, 2, &I::ip_buffer_actual_size),
    f(0x60C4, 3, &I::ip_buffer_organisation), f(0x60C4, 4, &I::ip_buffer_position),
    f(0x60C4, 6, &I::ip_buffer_access));

constexpr auto kOutputs = std::make_tuple(
    f(0x6041, 0, &O::statusword), f(0x6061, 0, &O::modes_of_operation_display), f(0x6062, 0, &O::position_demand),
    f(0x6063, 0, &O::position_actual_internal), f(0x6064, 0, &O::position_actual),
    f(0x606B, 0, &O::velocity_demand), f(0x606C, 0, &O::velocity_actual), f(0x6074, 0, &O::torque_demand),
    f(0x6077, 0, &O::torque_actual), f(0x60F4, 0, &O::following_error), f(0x60FC, 0, &O::position_demand_internal),
    f(0x603F, 0, &O::error_code), f(0x60B9, 0, &O::touch_probe_status), f(0x60BA, 0, &O::touch_probe_1_positive),
    f(0x60BB, 0, &O::touch_probe_1_negative), f(0x60BC, 0, &O::touch_probe_2_positive),
    f(0x60BD, 0, &O::touch_probe_2_negative), f(0x60FD, 0, &O::digital_inputs),
    f(0x6502, 0, &O::supported_drive_modes), f(0x60C4, 4, &O::ip_buffer_position), f(0x6043, 0, &O::vl_velocity_demand),
    f(0x6044, 0, &O::vl_velocity_actual));

static_assert(std::tuple_size_v<decltype(kInputs)> == DriveBinding::kInputCount);
static_assert(std::tuple_size_v<decltype(kOutputs)> == DriveBinding::kOutputCount);

template <typename Tuple, typename Fn, std::size_t... N>
void each(const Tuple& t, Fn&& fn, std::index_sequence<N...>) {
  (fn(std::get<N>(t), N), ...);
}
template <typename Tuple, typename Fn>
void each(const Tuple& t, Fn&& fn) {
  each(t, fn, std::make_index_sequence<std::tuple_size_v<Tuple>>{});
}

template <typename T>
T load_field(const std::uint8_t* p) noexcept {
  return static_cast<T>(load_le<std::make_unsigned_t<T>>(p));
}
template <typename T>
void store_field(std::uint8_t* p, T v) noexcept {
  store_le(p, static_cast<std::make_unsigned_t<T>>(v));
}

void copy_value(std::uint8_t* field, const std::uint8_t* bytes, std::uint8_t size) noexcept {
  switch (size) {
    case 1: *field = *bytes; break;
    case 2: std::memcpy(field, bytes, 2); break;
    case 4: std::memcpy(field, bytes, 4); break;
    default: std::memcpy(field, bytes, 8); break;
  }
}

constexpr std::uint16_t kErrorRegister = 0x1001;
constexpr std::uint16_t kIpDataRecord = 0x60C1;  // sub 1: the position record
constexpr std::uint8_t kIpDataRecordPosition = 1;
constexpr std::uint16_t kSupportedHomingMethods = 0x60E3;
constexpr std::uint16_t kSupportedDriveModes = 0x6502;
// EMCY byte 3 (the first manufacturer-specific byte) of a multi-axis device:
// the axis number (docs/ds402.md "Several axes").
constexpr std::size_t kEmcyAxisByte = 0;

}  // namespace

DriveBinding::DriveBinding(coe::ObjectStore& store, coe::Emergency* emergency) noexcept
    : DriveBinding(store, emergency, od::AxisLayout{}, 1) {}

DriveBinding::DriveBinding(coe::ObjectStore& store, coe::Emergency* emergency, const od::AxisLayout& layout,
                           unsigned axis) noexcept
    : store_(store), values_(store.values()), emergency_(emergency), layout_(layout), axis_(axis),
      multi_axis_(layout.axes > 1) {
  each(kInputs, [&](const auto& fld, std::size_t i) {
    using T = std::remove_cvref_t<decltype(std::declval<I&>().*fld.member)>;
    in_[i] = store_.slot(layout_.object_index(axis_, fld.index), fld.subindex);
    in_at_[i] = value_at<T>(in_[i]);
  });
  each(kOutputs, [&](const auto& fld, std::size_t i) {
    using T = std::remove_cvref_t<decltype(std::declval<O&>().*fld.member)>;
    out_[i] = store_.slot(layout_.object_index(axis_, fld.index), fld.subindex);
    out_at_[i] = value_at<T>(out_[i]);
  });
  error_register_ = store_.slot(kErrorRegister, 0);
  ip_record_ = store_.slot(layout_.object_index(axis_, kIpDataRecord), kIpDataRecordPosition);
}

// The entry's offset when its value bytes hold exactly a T (integral).
template <typename T>
std::uint32_t DriveBinding::value_at(const coe::ObjectStore::Slot* s) const noexcept {
  if (s == nullptr) return kAbsent;
  const bool same_width = std::is_integral_v<T> && s->capacity == sizeof(T) && store_.length(*s) == sizeof(T);
  return same_width ? s->offset : kConvert;
}

Expected<void, coe::SdoAbort> IpRecordHook::on_write(coe::ObjectStore& store,
                                                     const coe::WriteRequest& request) noexcept {
  (void)store;
  if (request.subindex == kIpDataRecordPosition) written_ = true;
  return {};
}

void DriveBinding::publish(const DriveConfig& config) {
  hooks_.install(store_, config, layout_, axis_);
  if (ip_record_ != nullptr) store_.set_hooks(layout_.object_index(axis_, kIpDataRecord), &ip_record_hook_);
  if (config.homing_current_threshold_index != 0) {
    homing_current_threshold_ = store_.slot(layout_.object_index(axis_, config.homing_current_threshold_index), 0);
  }
  if (auto* s = store_.slot(layout_.object_index(axis_, kSupportedDriveModes), 0)) {
    store_.set(*s, config.supported_modes);
  }
  const std::uint16_t homing_methods = layout_.object_index(axis_, kSupportedHomingMethods);
  const coe::ObjectStore::Slot* count = store_.slot(homing_methods, 0);
  if (!count) return;
  std::uint8_t sub = 0;
  for (int m = -128; m < 128; ++m) {
    if (!config.supports_homing(static_cast<std::int8_t>(m))) continue;
    coe::ObjectStore::Slot* s = store_.slot(homing_methods, static_cast<std::uint8_t>(sub + 1));
    if (!s) break;
    store_.set(*s, static_cast<std::int16_t>(m));
    ++sub;
  }
}

template <std::size_t N>
void DriveBinding::read_input(DriveInputs& in) const noexcept {
  const auto& fld = std::get<N>(kInputs);
  using T = std::remove_cvref_t<decltype(in.*fld.member)>;
  const std::uint32_t at = in_at_[N];
  if (at < kConvert) {
    in.*fld.member = load_field<T>(values_ + at);
  } else if (at == kConvert) {
    in.*fld.member = store_.get<T>(*in_[N]);
  }
}

void DriveBinding::read(DriveInputs& in) const noexcept {
  [&]<std::size_t... N>(std::index_sequence<N...>) {
    (read_input<N>(in), ...);
  }(std::make_index_sequence<kInputCount>{});
  if (homing_current_threshold_) in.homing_current_threshold = store_.get<std::uint32_t>(*homing_current_threshold_);
}

// One typed read per input, callable through a table.
template <std::size_t N>
void DriveBinding::read_one(const DriveBinding& b, DriveInputs& in) noexcept {
  b.read_input<N>(in);
}

void DriveBinding::read_cycle(DriveInputs& in, std::span<const coe::PdoItem> rx_pdo) noexcept {
  if (store_.generation() != seen_ || rx_pdo.data() != rx_pdo_.data() || rx_pdo.size() != rx_pdo_.size()) {
    read_all(in, rx_pdo);
    in.ip_record_new = std::exchange(ip_record_written_, false) || ip_record_mapped_;
    return;
  }
  in.ip_record_new = std::exchange(ip_record_written_, false) || ip_record_mapped_;
  auto* base = reinterpret_cast<std::uint8_t*>(&in);
  const std::uint8_t* const values = values_;
  const std::size_t count = mapped_count_;
  for (std::size_t k = 0; k < count; ++k) {
    const Mapped m = mapped_[k];
    if (m.size != 0) {
      copy_value(base + m.field_offset, values + m.at, m.size);
    } else {
      reader(m.input)(*this, in);
    }
  }
}

// Every entry, and which of them `rx_pdo` maps (set-up and after changes only).
// A mapped entry of its field's width is copied as bytes on a little-endian
// host (the same as load_field: the two's complement bits of the value).
DriveBinding::Reader DriveBinding::reader(std::size_t i) noexcept {
  static constexpr auto kReaders = []<std::size_t... N>(std::index_sequence<N...>) {
    return std::array<Reader, kInputCount>{&DriveBinding::read_one<N>...};
  }(std::make_index_sequence<kInputCount>{});
  return kReaders[i];
}

void DriveBinding::read_all(DriveInputs& in, std::span<const coe::PdoItem> rx_pdo) noexcept {
  read(in);
  seen_ = store_.generation();
  rx_pdo_ = rx_pdo;
  mapped_count_ = 0;
  ip_record_mapped_ = false;
  for (const coe::PdoItem& item : rx_pdo) ip_record_mapped_ = ip_record_mapped_ || (ip_record_ && item.entry == ip_record_);
  const DriveInputs layout{};
  const auto* base = reinterpret_cast<const std::uint8_t*>(&layout);
  each(kInputs, [&](const auto& fld, std::size_t i) {
    if (in_[i] == nullptr) return;
    for (const coe::PdoItem& item : rx_pdo) {
      if (item.entry != in_[i]) continue;
      Mapped& m = mapped_[mapped_count_++];
      m = Mapped{};
      m.input = static_cast<std::uint8_t>(i);
      if (std::endian::native == std::endian::little && in_at_[i] < kConvert) {
        m.at = in_at_[i];
        m.field_offset = static_cast<std::uint16_t>(reinterpret_cast<const std::uint8_t*>(&(layout.*fld.member)) - base);
        m.size = static_cast<std::uint8_t>(sizeof(layout.*fld.member));
      }
      break;
    }
  });
}

void DriveBinding::write(const DriveOutputs& out, EmcyQueue& emergencies, Nanoseconds now) noexcept {
  // The outputs, 1001h and the emergency objects are no inputs: writing them
  // leaves the inputs read_cycle() saw unchanged.
  const bool inputs_current = store_.generation() == seen_;
  write_objects(out, emergencies, now);
  if (inputs_current) seen_ = store_.generation();
}

void DriveBinding::write_axis(const DriveOutputs& out, EmcyQueue& emergencies, Nanoseconds now,
                              std::uint8_t other_axes) noexcept {
  // Its own copy of write_objects' loop: sharing it costs the single-axis
  // cycle a call (the loop is no longer inlined there).
  std::uint8_t* const values = values_;  // the stores below may alias values_ (bytes)
  each(kOutputs, [&](const auto& fld, std::size_t i) {
    const std::uint32_t a = out_at_[i];
    if (a < kConvert) {
      store_field(values + a, out.*fld.member);
    } else if (a == kConvert) {
      store_.set(*out_[i], out.*fld.member);
    }
  });
  if (!emergency_) {
    if (error_register_) store_.set(*error_register_, static_cast<std::uint8_t>(out.error_register | other_axes));
    while (!emergencies.empty()) {  // nobody to send them to
      (void)emergencies.pop();
      ++emergencies_lost_;
    }
    return;
  }
  // empty() first: an empty pop() through the optional stalled every cycle
  // (its flag stored as a byte, read back wider; issue 30).
  while (!emergencies.empty()) {
    std::optional<EmcyRequest> r = emergencies.pop();
    if (multi_axis_) r->manufacturer[kEmcyAxisByte] = static_cast<std::uint8_t>(axis_);
    const auto reg = static_cast<std::uint8_t>(r->error_register | other_axes);
    if (!emergency_->raise(r->error_code, reg, r->manufacturer, now)) ++emergencies_lost_;
  }
}

void DriveBinding::write_objects(const DriveOutputs& out, EmcyQueue& emergencies, Nanoseconds now) noexcept {
  std::uint8_t* const values = values_;  // the stores below may alias values_ (bytes)
  each(kOutputs, [&](const auto& fld, std::size_t i) {
    const std::uint32_t a = out_at_[i];
    if (a < kConvert) {
      store_field(values + a, out.*fld.member);
    } else if (a == kConvert) {
      store_.set(*out_[i], out.*fld.member);
    }
  });
  if (!emergency_) {
    if (error_register_) store_.set(*error_register_, out.error_register);
    while (!emergencies.empty()) {  // nobody to send them to
      (void)emergencies.pop();
      ++emergencies_lost_;
    }
    return;
  }
  // empty() first: an empty pop() through the optional stalled every cycle
  // (its flag stored as a byte, read back wider; issue 30).
  while (!emergencies.empty()) {
    std::optional<EmcyRequest> r = emergencies.pop();
    if (!emergency_->raise(r->error_code, r->error_register, r->manufacturer, now)) ++emergencies_lost_;
  }
}

std::size_t DriveBinding::bound_inputs() const noexcept {
  std::size_t n = 0;
  for (const auto* s : in_) n += s != nullptr;
  return n;
}
std::size_t DriveBinding::bound_outputs() const noexcept {
  std::size_t n = 0;
  for (const auto* s : out_) n += s != nullptr;
  return n;
}

}  // namespace ecat::ds402
