// Turns the merged DeviceSpec into od::DeviceDescription: derives the
// objects that follow from identity, sync managers and PDOs
// (esi/device_derive.cpp), builds and checks every object
// (esi/device_objects.cpp), then the sync managers and PDOs
// (esi/device_checks.cpp). Throws LoadFailure with file:line.
#pragma once

#include "esi/device_spec.hpp"
#include "od/device.hpp"

namespace ecat::esi {

od::DeviceDescription build_device(DeviceSpec spec);

// Steps of build_device, each in its own file.
void derive_objects(DeviceSpec& spec);                        // device_derive.cpp
void derive_axes(DeviceSpec& spec);                           // device_axes.cpp
od::AxisLayout axis_layout(const DeviceSpec& spec);           // device_axes.cpp
void derive_modules(DeviceSpec& spec);                        // device_modules.cpp
void build_modules(const DeviceSpec& spec, od::DeviceDescription& dev);  // device_modules.cpp
od::Pdo build_module_pdo(const PdoSpec& spec, od::DeviceDescription& dev);  // device_checks.cpp
od::Object build_object(std::uint16_t index, const ObjectSpec& spec);  // device_objects.cpp
void build_layout(const DeviceSpec& spec, od::DeviceDescription& dev);  // device_layout.cpp
void build_pdos(const DeviceSpec& spec, od::DeviceDescription& dev);    // device_checks.cpp
void check_sync_manager_memory(const DeviceSpec& spec, const od::DeviceDescription& dev);  // device_checks.cpp

// 6502h bits of <Drive modes> (CiA 402: bit 0 PP ... bit 9 CST).
std::uint32_t drive_mode_bits(const ElementSpec& drive);  // device_layout.cpp

}  // namespace ecat::esi
