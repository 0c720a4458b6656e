#include "esi_xmllint.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>

namespace ecat::esi::test {

bool have_xmllint() { return std::system("xmllint --version > /dev/null 2>&1") == 0; }

bool can_validate_esi() {
  return have_xmllint() && std::filesystem::exists(esi_schema_v114()) &&
         std::filesystem::exists(esi_schema_v117());
}

std::string xmllint_schema(const std::string& file, const std::string& schema, bool& ok) {
  const std::string cmd = "xmllint --noout --schema '" + schema + "' '" + file + "' 2>&1";
  std::string out;
  FILE* p = popen(cmd.c_str(), "r");
  if (!p) {
    ok = false;
    return "popen failed";
  }
  char buf[512];
  while (std::fgets(buf, sizeof buf, p)) out += buf;
  ok = pclose(p) == 0;
  return out;
}

std::string esi_schema_v114() { return std::string(ECAT_SHARED_DIR) + "/esi-schema/EtherCATInfo.xsd"; }
std::string esi_schema_v117() {
  return std::string(ECAT_SHARED_DIR) + "/esi-schema/v1.17/EtherCATInfo.xsd";
}

std::string write_test_file(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::path(ECAT_BINARY_DIR) / "test-output";
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

}  // namespace ecat::esi::test
