// Runs xmllint against the ETG ESI schema (both copies in shared/esi-schema)
// for the ESI writer tests; tests skip when xmllint is not installed.
#pragma once

#include <string>

namespace ecat::esi::test {

bool have_xmllint();
// xmllint and both ETG schema copies (outside the repo, in ../shared) present.
bool can_validate_esi();
// Returns xmllint's combined output; `ok` is set when the file validates.
std::string xmllint_schema(const std::string& file, const std::string& schema, bool& ok);
// The two ESI schema entry points: 1.14 and 1.17.
std::string esi_schema_v114();
std::string esi_schema_v117();
// Writes `text` to ECAT_BINARY_DIR/test-output/<name> and returns the path.
std::string write_test_file(const std::string& name, const std::string& text);

}  // namespace ecat::esi::test
