// The import's own judge (issue 32 item 1): read_esi_string() writes the
// device file of what it imported and runs the device-file loader on it; a
// refusal is reported at the vendor file's line of the element it concerns
// (the Object, its SubItem's object, the RxPdo/TxPdo), not at a line of a
// device file the user never sees.
#pragma once

#include <string>
#include <vector>

#include "esi/device_error.hpp"
#include "od/device.hpp"

namespace ecat::esi {

// `refusal` is the loader's error on `device_xml` (written from `d`);
// `vendor_file`, `device_line` (the Device element) and `sm_lines` (its Sm
// elements, in order) name the ESI.
LoadError vendor_refusal(const LoadError& refusal, const std::string& device_xml, const od::DeviceDescription& d,
                         const std::string& vendor_file, SourcePos device_line, const std::vector<SourcePos>& sm_lines);

}  // namespace ecat::esi
