// The CiA402 drive as a slave application: the ds402 drive and its plant,
// bound to the slave's object dictionary (ds402::DriveBinding), stepped in
// every application cycle, its emergencies sent through the CoE server.
#pragma once

#include <memory>
#include <string>

#include "common/expected.hpp"

#include "coe/coe_server.hpp"
#include "od/device.hpp"
#include "slave/application.hpp"

namespace ecat::slave {

// Whether the device's drive can be simulated (its plant parameters are
// known and in range); a message naming the parameter otherwise.
Expected<void, std::string> check_drive(const od::DeviceDescription& device);

// A drive application for a device with a Drive profile; nullptr for a
// device without one (it then has no application, only its objects).
// `motion_trace` keeps per-cycle rows for --plot.
std::unique_ptr<Application> make_drive_application(const od::DeviceDescription& device, coe::CoeServer& coe,
                                                    bool motion_trace);

}  // namespace ecat::slave
