// A drive with several CiA 402 axes behind one ESC (od::AxisLayout): one
// ds402::Drive with its own state machine, modes, plant and faults per axis,
// each bound to that axis' objects (CiA 402-1 §6, +800h per axis) and
// stepped in the same application cycle, in axis order.
#pragma once

#include <memory>

#include "coe/coe_server.hpp"
#include "ds402/drive_config.hpp"
#include "ds402/plant.hpp"
#include "od/axis_layout.hpp"
#include "slave/application.hpp"

namespace ecat::slave {

// Every axis gets `config` and `plant` (the device file describes one drive
// type); `motion_trace` keeps per-cycle rows of each axis for --plot.
std::unique_ptr<Application> make_multi_axis_application(const ds402::DriveConfig& config,
                                                         const ds402::PlantParameters& plant,
                                                         const od::AxisLayout& layout, coe::CoeServer& coe,
                                                         bool motion_trace);

}  // namespace ecat::slave
