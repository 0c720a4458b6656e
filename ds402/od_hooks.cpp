#include "ds402/od_hooks.hpp"

#include <array>

#include "coe/value.hpp"

namespace ecat::ds402 {

namespace {
constexpr std::uint16_t kModesOfOperation = 0x6060;
constexpr std::uint16_t kHomingMethod = 0x6098;
constexpr std::uint16_t kQuickStopOption = 0x605A;
constexpr std::uint16_t kShutdownOption = 0x605B;
constexpr std::uint16_t kDisableOperationOption = 0x605C;
constexpr std::uint16_t kHaltOption = 0x605D;
constexpr std::uint16_t kFaultReactionOption = 0x605E;
constexpr std::array<std::uint16_t, DriveObjectHooks::kGuardedCount> kGuarded{kModesOfOperation,       kHomingMethod, kQuickStopOption,
                                                kShutdownOption,         kDisableOperationOption,
                                                kHaltOption,             kFaultReactionOption};
}  // namespace

std::size_t DriveObjectHooks::install(coe::ObjectStore& store, const DriveConfig& config,
                                      const od::AxisLayout& layout, unsigned axis) {
  config_ = config;
  std::size_t n = 0;
  for (std::size_t k = 0; k < kGuarded.size(); ++k) {
    at_[k] = layout.object_index(axis, kGuarded[k]);
    n += store.set_hooks(at_[k], this) ? 1 : 0;
  }
  return n;
}

Expected<void, coe::SdoAbort> DriveObjectHooks::on_write(coe::ObjectStore& store,
                                                         const coe::WriteRequest& request) noexcept {
  (void)store;
  if (request.subindex != 0 || request.data.empty() || request.data.size() > 8) return {};
  const auto bits = static_cast<unsigned>(request.data.size() * 8);
  const auto value = static_cast<std::int64_t>(coe::load_bits(request.data, bits, true));
  bool ok = true;
  std::uint16_t index = 0;  // the profile's index of the object written (axis 1)
  for (std::size_t k = 0; k < kGuarded.size(); ++k) {
    if (at_[k] == request.index) index = kGuarded[k];
  }
  switch (index) {
    case kModesOfOperation: ok = value == 0 || (value >= INT8_MIN && value <= INT8_MAX &&
                                                config_.supports_mode(static_cast<std::int8_t>(value)));
      break;
    case kHomingMethod:
      ok = value >= INT8_MIN && value <= INT8_MAX && config_.supports_homing(static_cast<std::int8_t>(value));
      break;
    case kQuickStopOption: ok = config_.quick_stop.allows(static_cast<std::int16_t>(value)); break;
    case kShutdownOption: ok = config_.shutdown.allows(static_cast<std::int16_t>(value)); break;
    case kDisableOperationOption: ok = config_.disable_operation.allows(static_cast<std::int16_t>(value)); break;
    case kHaltOption: ok = config_.halt.allows(static_cast<std::int16_t>(value)); break;
    case kFaultReactionOption: ok = config_.fault_reaction.allows(static_cast<std::int16_t>(value)); break;
    default: break;
  }
  if (!ok) return fail(coe::SdoAbort::ValueRange);
  return {};
}

}  // namespace ecat::ds402
