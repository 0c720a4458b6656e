#include "slave/drive_application.hpp"

namespace ecat::slave {

std::unique_ptr<Application> make_drive_application(const od::DeviceDescription& device, coe::CoeServer& coe) {
  (void)device;
  (void)coe;
  return nullptr;  // replaced by the ds402 binding below once it lands
}

}  // namespace ecat::slave
