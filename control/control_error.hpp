// The errors the control interface replies with (docs/control.md "Errors"):
// a stable code a test can compare, and a message a person can read.
#pragma once

#include <string>
#include <string_view>

namespace ecat::control {

struct ControlError {
  std::string code;     // e.g. "unknown_slave", "out_of_range"
  std::string message;  // one line: what is wrong and what would be right
};

namespace error_code {
inline constexpr std::string_view kBadJson = "bad_json";
inline constexpr std::string_view kBadRequest = "bad_request";
inline constexpr std::string_view kUnknownCommand = "unknown_command";
inline constexpr std::string_view kUnknownSlave = "unknown_slave";
inline constexpr std::string_view kUnknownObject = "unknown_object";
inline constexpr std::string_view kUnknownSubindex = "unknown_subindex";
inline constexpr std::string_view kUnknownPdoEntry = "unknown_pdo_entry";
inline constexpr std::string_view kReadOnly = "read_only";
inline constexpr std::string_view kBadValue = "bad_value";
inline constexpr std::string_view kOutOfRange = "out_of_range";
inline constexpr std::string_view kUnknownFault = "unknown_fault";
inline constexpr std::string_view kFaultRefused = "fault_refused";
inline constexpr std::string_view kNoFaults = "no_faults";
inline constexpr std::string_view kNotSimulated = "not_simulated";
inline constexpr std::string_view kNotStreaming = "not_streaming";
inline constexpr std::string_view kLineTooLong = "line_too_long";
}  // namespace error_code

inline ControlError control_error(std::string_view code, std::string message) {
  return ControlError{std::string(code), std::move(message)};
}

}  // namespace ecat::control
