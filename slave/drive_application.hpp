// The CiA402 drive as a slave application: the ds402 drive and its plant,
// bound to the slave's object dictionary (ds402::DriveBinding), stepped in
// every application cycle, its emergencies sent through the CoE server.
#pragma once

#include <memory>

#include "coe/coe_server.hpp"
#include "od/device.hpp"
#include "slave/application.hpp"

namespace ecat::slave {

// A drive application for a device with a Drive profile; nullptr for a
// device without one (it then has no application, only its objects).
std::unique_ptr<Application> make_drive_application(const od::DeviceDescription& device, coe::CoeServer& coe);

}  // namespace ecat::slave
