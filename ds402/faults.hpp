// Faults the simulated drive detects, with the error code (603Fh, CiA 402-2
// §8.4.11 / the drive manual), the error register bits (1001h, CiA 301
// §7.5.2.2) and the emergency requests (CiA 301 §7.2.7, ETG.1000.6 §5.6.4)
// the binding forwards to CoE.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <optional>
#include <string_view>

namespace ecat::ds402 {

enum class FaultKind : std::uint8_t {
  FollowingError,
  SoftwareLimit,
  PositiveLimitSwitch,
  NegativeLimitSwitch,
  OverSpeed,
  OverTorque,
  SyncLost,
};
inline constexpr std::size_t kFaultKinds = 7;

std::string_view to_string(FaultKind k) noexcept;

// 1001h bits.
namespace error_register {
inline constexpr std::uint8_t kGeneric = 0x01;
inline constexpr std::uint8_t kCurrent = 0x02;
inline constexpr std::uint8_t kVoltage = 0x04;
inline constexpr std::uint8_t kTemperature = 0x08;
inline constexpr std::uint8_t kCommunication = 0x10;
inline constexpr std::uint8_t kDeviceProfile = 0x20;
inline constexpr std::uint8_t kManufacturer = 0x80;
}  // namespace error_register

struct FaultCode {
  std::uint16_t error_code = 0;     // 603Fh and the EMCY error code
  std::uint8_t error_register = 0;  // 1001h bits besides "generic"
};
using FaultCodes = std::array<FaultCode, kFaultKinds>;

// CiA 402 / CiA 301 codes: 8611h following error, 8612h reference limit,
// FF03h/FF04h limit switch (manufacturer range; CiA 402 has no code of its
// own), 8400h velocity controller (over-speed), 8311h excess torque, 8700h
// sync controller.
constexpr FaultCodes cia402_fault_codes() noexcept {
  using namespace error_register;
  return {{{0x8611, kDeviceProfile},
           {0x8612, kDeviceProfile},
           {0xFF03, kManufacturer},
           {0xFF04, kManufacturer},
           {0x8400, kDeviceProfile},
           {0x8311, kCurrent},
           {0x8700, kCommunication}}};
}

// The 1001h bits an error code's class sets besides "generic" (CiA 301
// §7.2.7.1 Table 21 code classes, §7.5.2.2): 2xxxh current, 3xxxh voltage,
// 4xxxh temperature, 81xxh communication, FFxxh manufacturer; the other
// classes (e.g. 73xxh sensor, 86xxh control) set the device profile bit,
// as the drive's own faults (cia402_fault_codes) do for CiA 402 codes.
constexpr std::uint8_t error_register_for(std::uint16_t error_code) noexcept {
  using namespace error_register;
  switch (error_code >> 12) {
    case 0x2:
      return kCurrent;
    case 0x3:
      return kVoltage;
    case 0x4:
      return kTemperature;
    case 0x8:
      if ((error_code >> 8) == 0x81) return kCommunication;
      return kDeviceProfile;
    case 0xF:
      if ((error_code >> 8) == 0xFF) return kManufacturer;
      return kDeviceProfile;
    default:
      return kDeviceProfile;
  }
}

// EMCY error code 0000h: "error reset or no error" (CiA 301 Table 21).
inline constexpr std::uint16_t kEmcyErrorReset = 0x0000;

struct EmcyRequest {
  std::uint16_t error_code = 0;
  std::uint8_t error_register = 0;
  std::array<std::uint8_t, 5> manufacturer{};  // EMCY bytes 3-7
};

// Fixed-capacity FIFO of emergency requests; the oldest is kept when full
// (the newer one is counted as dropped).
class EmcyQueue {
 public:
  static constexpr std::size_t kCapacity = 8;
  bool push(const EmcyRequest& r) noexcept {
    if (size_ == kCapacity) {
      ++dropped_;
      return false;
    }
    items_[(head_ + size_) % kCapacity] = r;
    ++size_;
    return true;
  }
  std::optional<EmcyRequest> pop() noexcept {
    if (size_ == 0) return std::nullopt;
    EmcyRequest r = items_[head_];
    head_ = (head_ + 1) % kCapacity;
    --size_;
    return r;
  }
  std::size_t size() const noexcept { return size_; }
  bool empty() const noexcept { return size_ == 0; }
  std::uint32_t dropped() const noexcept { return dropped_; }

 private:
  std::array<EmcyRequest, kCapacity> items_{};
  std::size_t head_ = 0;
  std::size_t size_ = 0;
  std::uint32_t dropped_ = 0;
};

}  // namespace ecat::ds402
