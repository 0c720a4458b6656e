// Validation of a device file against xml/schema/device.xsd with libxml2
// (the embedded copy, esi/xml_embedded.hpp), so unknown elements and
// attributes, bad numbers and wrong order are reported with their line.
#pragma once

#include <string_view>

#include "common/expected.hpp"
#include "esi/device_error.hpp"

namespace ecat::esi {

// Checks `xml` (the text of file `file_name`) against the XSD text `xsd`.
// Returns the first violation as "file:line: schema: ...".
Expected<void, LoadError> validate_against_schema(std::string_view xml, std::string_view file_name,
                                                  std::string_view xsd);

}  // namespace ecat::esi
