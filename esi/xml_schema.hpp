// Validation of a device file against xml/schema/device.xsd with libxml2
// (the embedded copy, esi/xml_embedded.hpp), so unknown elements and
// attributes, bad numbers and wrong order are reported with their line.
#pragma once

#include <memory>
#include <string_view>

#include "common/expected.hpp"
#include "esi/device_error.hpp"

namespace ecat::esi {

// Holds one parsed schema; parse once, validate many files.
class SchemaValidator {
 public:
  // Parses the XSD text; an invalid schema makes every validate() fail.
  explicit SchemaValidator(std::string_view xsd);
  ~SchemaValidator();
  SchemaValidator(const SchemaValidator&) = delete;
  SchemaValidator& operator=(const SchemaValidator&) = delete;

  // Checks `xml` (the text of file `file_name`). Returns the first violation
  // as "file:line: schema: ...".
  Expected<void, LoadError> validate(std::string_view xml, std::string_view file_name) const;

 private:
  struct Impl;
  std::unique_ptr<Impl> impl_;
};

}  // namespace ecat::esi
