// What runs above the PDI of one virtual slave, as the firmware of a real
// slave would: the EtherCAT state machine, the CoE server (mailbox, SDO,
// PDOs, parameters), the synchronisation logic that decides when the
// application cycle runs, and the application itself (a CiA402 drive when
// the device is one). Built once; poll() allocates nothing.
#pragma once

#include <memory>
#include <optional>
#include <vector>

#include "coe/coe_server.hpp"
#include "coe/sync_controller.hpp"
#include "common/clock.hpp"
#include "esc/dc/vcd_trace.hpp"
#include "esc/esc.hpp"
#include "esc/esm.hpp"
#include "od/device.hpp"
#include "slave/application.hpp"
#include "slave/slave_options.hpp"
#include "slave/slave_stats.hpp"

namespace ecat::slave {

class Firmware {
 public:
  Firmware(esc::Esc& esc, const od::DeviceDescription& device, const SlaveOptions& options);
  Firmware(const Firmware&) = delete;
  Firmware& operator=(const Firmware&) = delete;

  // One pass of the firmware main loop at `now`; returns when it next needs
  // to run by time alone.
  std::optional<Nanoseconds> poll(Nanoseconds now) noexcept;

  esc::Esm& esm() noexcept { return esm_; }
  coe::CoeServer& coe() noexcept { return coe_; }
  coe::SyncController& sync() noexcept { return sync_; }
  Application* application() noexcept { return app_.get(); }
  const std::vector<std::string>& warnings() const noexcept { return coe_.warnings(); }

  void attach_trace(esc::VcdProbe& probe) noexcept;
  SlaveStatus status() const noexcept;

 private:
  void application_cycle(Nanoseconds now) noexcept;

  esc::Esc& esc_;
  esc::Esm esm_;
  coe::CoeServer coe_;
  coe::SyncController sync_;
  std::unique_ptr<Application> app_;
  esc::VcdProbe* trace_ = nullptr;
  std::optional<Nanoseconds> last_cycle_;
  std::uint64_t cycles_ = 0;
};

}  // namespace ecat::slave
