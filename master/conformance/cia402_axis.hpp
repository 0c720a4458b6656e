// One CiA 402 axis driven by the conformance suite the way a motion master
// drives it (CiA 402-2 §8.1 power drive system FSA, IEC 61800-7-201): the
// controlword and set points in the process data where the slave maps them
// (its 1C12h/1C13h assignment read over SDO), over SDO where it does not;
// one process-data cycle per millisecond of waiting. Emergencies that arrive
// between cycles are kept with their raw bytes (ETG.1000.6 §5.6.4,
// shared/spec/coe-mailbox.md §9).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "master/conformance/suite.hpp"

namespace ecat::master::conformance {

namespace cia402 {
inline constexpr std::uint16_t kControlword = 0x6040;
inline constexpr std::uint16_t kStatusword = 0x6041;
inline constexpr std::uint16_t kQuickStopOption = 0x605A;
inline constexpr std::uint16_t kShutdownOption = 0x605B;
inline constexpr std::uint16_t kDisableOperationOption = 0x605C;
inline constexpr std::uint16_t kHaltOption = 0x605D;
inline constexpr std::uint16_t kFaultReactionOption = 0x605E;
inline constexpr std::uint16_t kModes = 0x6060;
inline constexpr std::uint16_t kModesDisplay = 0x6061;
inline constexpr std::uint16_t kErrorCode = 0x603F;
inline constexpr std::uint16_t kPositionActual = 0x6064;
inline constexpr std::uint16_t kFollowingErrorWindow = 0x6065;
inline constexpr std::uint16_t kFollowingErrorTimeout = 0x6066;
inline constexpr std::uint16_t kVelocityActual = 0x606C;
inline constexpr std::uint16_t kTargetTorque = 0x6071;
inline constexpr std::uint16_t kTorqueActual = 0x6077;
inline constexpr std::uint16_t kTargetPosition = 0x607A;
inline constexpr std::uint16_t kTargetVelocity = 0x60FF;
inline constexpr std::uint16_t kSupportedModes = 0x6502;
inline constexpr std::uint16_t kErrorRegister = 0x1001;

// Controlword commands (CiA 402-2 §8.1.3 Table 30 / ds402 docs).
inline constexpr std::uint16_t kDisableVoltage = 0x0000;
inline constexpr std::uint16_t kQuickStop = 0x0002;
inline constexpr std::uint16_t kShutdown = 0x0006;
inline constexpr std::uint16_t kSwitchOn = 0x0007;
inline constexpr std::uint16_t kEnableOperation = 0x000F;
inline constexpr std::uint16_t kFaultReset = 0x0080;

// Modes of operation (CiA 402-2 §8.4.1 6060h).
inline constexpr std::int8_t kCsp = 8;
inline constexpr std::int8_t kCsv = 9;
inline constexpr std::int8_t kCst = 10;

// Statusword bits (CiA 402-2 §8.1.3 / §8.4.2).
inline constexpr std::uint16_t kBitTargetReached = 1u << 10;
inline constexpr std::uint16_t kBitFollowsCommand = 1u << 12;  // CSx: drive follows the command value
inline constexpr std::uint16_t kBitFollowingError = 1u << 13;

enum class State : std::uint8_t {
  NotReady,
  SwitchOnDisabled,
  ReadyToSwitchOn,
  SwitchedOn,
  OperationEnabled,
  QuickStopActive,
  FaultReactionActive,
  Fault,
  Unknown,
};

// The state a statusword shows (CiA 402-2 Table 30 masks 0x4F / 0x6F).
State decode(std::uint16_t statusword) noexcept;
std::string name(State s);
}  // namespace cia402

struct RawEmergency {
  std::vector<std::uint8_t> payload;  // from the CoE header on
  std::uint16_t code() const noexcept;
  std::uint8_t error_register() const noexcept;
};

class Cia402Axis {
 public:
  explicit Cia402Axis(Context& ctx) : ctx_(ctx) {}
  Cia402Axis(const Cia402Axis&) = delete;
  Cia402Axis& operator=(const Cia402Axis&) = delete;
  // Writes back the option codes / windows a case changed, drops the power
  // stage (controlword 0).
  ~Cia402Axis();

  // Checks the device has 6040h/6041h (nullopt when it does; a skip with the
  // device's answer otherwise), brings it to Op with a zero controlword and
  // finds the mapped objects.
  std::optional<CaseResult> open();

  std::uint16_t statusword();
  cia402::State state() { return cia402::decode(statusword()); }
  void command(std::uint16_t controlword);
  // Runs `cycles` process-data cycles, one millisecond apart.
  void run(unsigned cycles);
  // Sends `controlword` and cycles until the statusword shows `want` (at
  // most `max_cycles`); the state seen last.
  cia402::State command_until(std::uint16_t controlword, cia402::State want, unsigned max_cycles = kMaxCycles);
  // Shutdown, switch on, enable operation in turn; an error names the step.
  Expected<void, std::string> enable();
  // The path from Switch on disabled to `target` (Ready to switch on,
  // Switched on or Operation enabled); an error names where it stopped.
  Expected<void, std::string> reach(cia402::State target);

  bool mapped_out(std::uint16_t index) const { return out_byte(index).has_value(); }
  bool mapped_in(std::uint16_t index) const { return in_byte(index).has_value(); }
  // Writes a set point / mode: process data when mapped, else SDO.
  Expected<void, SdoError> set(std::uint16_t index, std::int64_t value, std::size_t bytes);
  // Reads an actual value: process data when mapped, else SDO (signed).
  Expected<std::int64_t, SdoError> get(std::uint16_t index, std::size_t bytes);
  // SDO write that the destructor undoes (the old value is read first).
  Expected<void, SdoError> change(std::uint16_t index, std::uint8_t sub, std::uint32_t value, std::size_t bytes);

  // 6502h bit for mode m (1..10 standard modes; bit m-1).
  std::optional<std::uint32_t> supported_modes();
  // Sets the mode and cycles until 6061h shows it; the mode seen last.
  std::int64_t select_mode(std::int8_t mode, unsigned max_cycles = 50);

  const std::vector<RawEmergency>& emergencies() const noexcept { return emergencies_; }
  void collect_emergencies();
  void keep_emergencies(const CoeClient& coe);

  static constexpr unsigned kMaxCycles = 500;

 private:
  struct Mapped {
    std::uint16_t index = 0;
    std::uint32_t byte = 0;
  };
  std::optional<std::uint32_t> out_byte(std::uint16_t index) const;
  std::optional<std::uint32_t> in_byte(std::uint16_t index) const;
  void locate();

  struct Restore {
    std::uint16_t index;
    std::uint8_t sub;
    std::uint32_t value;
    std::size_t bytes;
  };
  Context& ctx_;
  std::vector<Mapped> outputs_, inputs_;
  std::vector<Restore> restore_;
  std::vector<RawEmergency> emergencies_;
  bool open_ = false;
};

}  // namespace ecat::master::conformance
