// Several CiA 402 axes in one vendor ESI (docs/twins.md "Axes of a
// multi-axis ESI"). ETG.2000 has no element for axes: a multi-axis drive's
// ESI lists every axis' objects and PDOs. CiA 402-1 §6 places axis n's
// objects at the axis-1 index + (n-1)·800h, so a controlword/statusword pair
// at 6840h/6841h, 7040h/7041h, ... names axes 2, 3, ...; the PDOs that map
// axis 2's objects against those that map axis 1's give the per-axis PDO
// offset. The reader keeps the layout in od::DriveProfile::axes, so the twin
// runs one CiA 402 state machine per axis and its device file says <Drive
// axes="N">.
#pragma once

#include <optional>
#include <string>

#include "od/device.hpp"

namespace ecat::esi {

// Sets d.drive->axes when the dictionary holds more than one axis laid out as
// CiA 402-1 §6 has it. A multi-axis file that does not fit the layout (an axis
// lacks an object or a PDO of axis 1, the PDOs of the axes lie at no one
// offset) keeps one axis; the returned text says why (the caller warns).
// Nothing for a single-axis device, a device without CiA 402 or a modular one.
std::optional<std::string> recover_axes(od::DeviceDescription& d);

}  // namespace ecat::esi
