// What ecat-conform runs against: a transport, the clock that times it, and
// a way to let time pass with the bus idle. The in-process target (a virtual
// slave built from a device file) is created through make_in_process_target,
// implemented with slave::Chain; the wire targets through raw socket or UDP.
#pragma once

#include <memory>
#include <optional>
#include <string>

#include "common/clock.hpp"
#include "common/expected.hpp"
#include "master/conformance/suite.hpp"
#include "od/device.hpp"
#include "slave/slave_options.hpp"
#include "transport/transport.hpp"

namespace ecat::conform {

class Target {
 public:
  virtual ~Target() = default;
  virtual transport::Transport& transport() = 0;
  virtual const Clock& clock() const = 0;
  // Let `d` pass without frames (in-process: advance the simulated time and
  // run the slaves; on a wire: sleep).
  virtual void wait(Nanoseconds d) = 0;
  // Switch the slave off and on again (the reg.powerup_* cases); false when
  // the target cannot (a wire: the suite skips those cases and says why).
  virtual bool power_cycle() { return false; }
  // Identity from the device file, when the target was made from one.
  virtual std::optional<master::conformance::ExpectedIdentity> identity() const { return std::nullopt; }
  // The device file the target was made from (the ESI source), if any.
  virtual const od::DeviceDescription* device() const { return nullptr; }
  virtual std::string description() const = 0;
};

// A virtual slave from `device_file` (the integrator's slave::Chain), on a
// ManualClock that advances `frame_time` per frame; its firmware reaches
// the ESC through `pdi` (direct, or SPI framing to an emulated LAN9252 /
// ET1100 SPI slave).
Expected<std::unique_ptr<Target>, std::string> make_in_process_target(const std::string& device_file,
                                                                      slave::PdiKind pdi = slave::PdiKind::Direct);
Expected<std::unique_ptr<Target>, std::string> make_raw_socket_target(const std::string& interface_name);
Expected<std::unique_ptr<Target>, std::string> make_udp_target(const std::string& address);

// Cases that compare a device file (what the ESI is generated from) with
// what the slave reports over the bus: SII and object dictionary.
std::vector<master::conformance::Case> device_file_cases(const od::DeviceDescription& device);

// DC Sync0 settings when the device's ESI offers only DC OpModes (dc_mode.cpp),
// for a master cycle of `master_cycle_ns`; nullopt: the suite runs free run.
std::optional<master::conformance::DcSync0> dc_only_mode(const od::DeviceDescription& device,
                                                         std::uint32_t master_cycle_ns);

}  // namespace ecat::conform
