// Writer of our own device format (docs/device-format.md, xml/schema/
// device.xsd) from the model, so an imported vendor ESI can be kept and edited
// as a device file: ESI -> model -> device XML -> model -> ESI is stable.
// Every object is written explicitly (no Include), so nothing the loader
// would derive can differ from the model.
#pragma once

#include <string>

#include "od/device.hpp"

namespace ecat::esi {

std::string write_device_xml(const od::DeviceDescription& device);

}  // namespace ecat::esi
