#include "apps/ecat-master/cia402_motion.hpp"

#include <cmath>

#include "common/le.hpp"

namespace ecat::app {
namespace {

// CiA402 objects (IEC 61800-7-201 §6).
constexpr std::uint16_t kControlword = 0x6040;
constexpr std::uint16_t kStatusword = 0x6041;
constexpr std::uint16_t kModesOfOperation = 0x6060;
constexpr std::uint16_t kPositionActualValue = 0x6064;
constexpr std::uint16_t kTargetPosition = 0x607A;
constexpr std::uint8_t kCyclicSynchronousPosition = 8;

// Statusword state patterns (mask, value), CiA402 Table 30.
constexpr std::uint16_t kMaskWide = 0x006F;
constexpr std::uint16_t kMaskNarrow = 0x004F;
constexpr std::uint16_t kSwitchOnDisabled = 0x0040;
constexpr std::uint16_t kReadyToSwitchOn = 0x0021;
constexpr std::uint16_t kSwitchedOn = 0x0023;
constexpr std::uint16_t kOperationEnabled = 0x0027;
constexpr std::uint16_t kFaultBit = 0x0008;

// Controlword commands, CiA402 Table 27.
constexpr std::uint16_t kShutdown = 0x0006;
constexpr std::uint16_t kSwitchOn = 0x0007;
constexpr std::uint16_t kEnableOperation = 0x000F;
constexpr std::uint16_t kFaultReset = 0x0080;

// Share of the run spent moving; the rest holds the target.
constexpr double kMoveShare = 0.6;
constexpr double kPi = 3.14159265358979323846;

}  // namespace

Cia402Motion::Cia402Motion(master::Master& master, std::size_t slave, const PdoLocator& pdos)
    : master_(master), slave_(slave) {
  auto cw = pdos.output_byte(kControlword);
  auto tp = pdos.output_byte(kTargetPosition);
  auto sw = pdos.input_byte(kStatusword);
  auto ap = pdos.input_byte(kPositionActualValue);
  auto mo = pdos.output_byte(kModesOfOperation);
  usable_ = cw && tp && sw && ap;
  if (!usable_) return;
  controlword_ = *cw;
  target_ = *tp;
  statusword_ = *sw;
  actual_ = *ap;
  has_mode_ = mo.has_value();
  mode_ = mo.value_or(0);
}

std::uint16_t Cia402Motion::statusword() const noexcept {
  return load_le<std::uint16_t>(master_.inputs(slave_).data() + statusword_);
}

std::int32_t Cia402Motion::actual_position() const noexcept {
  return static_cast<std::int32_t>(load_le<std::uint32_t>(master_.inputs(slave_).data() + actual_));
}

bool Cia402Motion::operation_enabled() const noexcept {
  return (statusword() & kMaskWide) == kOperationEnabled;
}

void Cia402Motion::cycle(std::uint64_t cycle, std::uint64_t cycles, std::int32_t distance) noexcept {
  std::uint8_t* out = master_.outputs(slave_).data();
  const std::uint16_t sw = statusword();
  std::uint16_t cw = kShutdown;
  std::int32_t target = actual_position();
  if (sw & kFaultBit) {
    // A rising edge of bit 7 resets the fault.
    cw = last_controlword_ == kFaultReset ? 0 : kFaultReset;
    enabled_ = false;
  } else if ((sw & kMaskNarrow) == kSwitchOnDisabled) {
    cw = kShutdown;
  } else if ((sw & kMaskWide) == kReadyToSwitchOn) {
    cw = kSwitchOn;
  } else if ((sw & kMaskWide) == kSwitchedOn) {
    cw = kEnableOperation;
  } else if ((sw & kMaskWide) == kOperationEnabled) {
    cw = kEnableOperation;
    if (!enabled_) {
      enabled_ = true;
      enabled_at_ = cycle;
      start_position_ = actual_position();
    }
    // Cosine ramp from the start position over the moving share of the run.
    const double span = std::max(1.0, kMoveShare * static_cast<double>(cycles));
    const double p = std::min(1.0, static_cast<double>(cycle - enabled_at_) / span);
    const double s = 0.5 - 0.5 * std::cos(kPi * p);
    target = start_position_ + static_cast<std::int32_t>(std::lround(s * distance));
  }
  store_le<std::uint16_t>(out + controlword_, cw);
  store_le<std::uint32_t>(out + target_, static_cast<std::uint32_t>(target));
  if (has_mode_) out[mode_] = kCyclicSynchronousPosition;
  last_controlword_ = cw;
}

}  // namespace ecat::app
