// ESI (EtherCAT Slave Information, ETG.2000) writer: one EtherCATInfo document
// for a device description, valid against the ETG schema (1.14 and 1.17).
// Deterministic: the same model always gives the same bytes (no timestamps,
// no paths), so ESI -> model -> ESI is byte-identical.
#pragma once

#include <string>

#include "od/device.hpp"

namespace ecat::esi {

std::string write_esi(const od::DeviceDescription& device);

}  // namespace ecat::esi
