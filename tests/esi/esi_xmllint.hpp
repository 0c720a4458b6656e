// Runs xmllint against the ETG ESI schema for the ESI writer tests. The
// schema files come from ECAT_ESI_SCHEMAS (colon-separated paths of
// EtherCATInfo.xsd) in the environment, else from the CMake cache variable
// of the same name (default: 1.14 and 1.17 in ../shared/esi-schema). Tests
// skip when xmllint is missing or the default schema is absent; a schema a
// user named that does not exist fails the test (xmllint says so).
#pragma once

#include <string>
#include <vector>

namespace ecat::esi::test {

bool have_xmllint();
// xmllint present, and either ECAT_ESI_SCHEMAS is set or the default
// schema files exist.
bool can_validate_esi();
// Why can_validate_esi() is false, for the skip message.
std::string why_no_esi_schema();
// The EtherCATInfo.xsd files to validate against, in order (not empty
// when can_validate_esi()).
std::vector<std::string> esi_schemas();
// Returns xmllint's combined output; `ok` is set when the file validates.
std::string xmllint_schema(const std::string& file, const std::string& schema, bool& ok);
// Writes `text` to ECAT_BINARY_DIR/test-output/<name> and returns the path.
std::string write_test_file(const std::string& name, const std::string& text);

}  // namespace ecat::esi::test
