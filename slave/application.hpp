// The application a slave runs in its cycle, between reading the outputs
// from SM2 into the objects and writing the inputs to SM3 (ETG.1000.6
// §5.6.7.4.3). A CiA402 drive is one; a device with no drive has none.
#pragma once

#include <cstddef>
#include <string>

#include "common/clock.hpp"
#include "common/expected.hpp"
#include "esc/al_status_code.hpp"

namespace ecat::ds402 {
class Drive;
}

namespace ecat::slave {

class Application {
 public:
  virtual ~Application() = default;
  // One cycle: `dt` since the previous one; `outputs_valid` is true in Op.
  virtual void cycle(Nanoseconds dt, bool outputs_valid) noexcept = 0;
  // The ESM changed state (e.g. leaving Op: outputs are no longer valid).
  virtual void on_state(esc::AlState state) noexcept { (void)state; }
  // The CiA 402 drive of axis `axis` (0-based), for applications that run
  // drives; nullptr otherwise (slave::FaultCatalogue's drive faults).
  virtual ds402::Drive* drive(std::size_t axis) noexcept {
    (void)axis;
    return nullptr;
  }
  // Motion trace / plot, for applications that record one.
  virtual bool has_motion_trace() const noexcept { return false; }
  // Writes it; an error names the file and says why (a short write included).
  virtual Expected<void, std::string> write_plot(const std::string& path) const {
    return fail(path + ": this slave records no motion trace");
  }
};

}  // namespace ecat::slave
