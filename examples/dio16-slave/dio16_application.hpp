// The firmware application of the DIO16 terminal (dio16.xml): what runs in
// each cycle between the stack copying SM2 into 7000h and copying 6000h into
// SM3 (slave::Application). A real terminal would switch 16 output drivers
// and sample 16 input pins here; this one has a loopback plug fitted, so
// input n reads output n, and a master sees its outputs come back.
#pragma once

#include <cstdint>

#include "coe/object_store.hpp"
#include "slave/application.hpp"

namespace dio16 {

inline constexpr std::uint16_t kDigitalInputs = 0x6000;
inline constexpr std::uint16_t kDigitalOutputs = 0x7000;
inline constexpr std::uint8_t kChannels = 16;

class Dio16Application final : public ecat::slave::Application {
 public:
  explicit Dio16Application(ecat::coe::ObjectStore& objects) noexcept : objects_(objects) {}

  void cycle(ecat::Nanoseconds dt, bool outputs_valid) noexcept override {
    (void)dt;
    for (std::uint8_t channel = 1; channel <= kChannels; ++channel) {
      // Outside Op the outputs are not valid and stay in their safe state,
      // off (ETG.1000.6 §6.4.1).
      const bool on = outputs_valid && objects_.get<std::uint8_t>(kDigitalOutputs, channel) != 0;
      (void)objects_.set<std::uint8_t>(kDigitalInputs, channel, on ? 1 : 0);
    }
    ++cycles_;
  }

  std::uint64_t cycles() const noexcept { return cycles_; }

 private:
  ecat::coe::ObjectStore& objects_;
  std::uint64_t cycles_ = 0;
};

}  // namespace dio16
