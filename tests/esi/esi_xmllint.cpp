#include "esi_xmllint.hpp"

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string_view>

namespace ecat::esi::test {
namespace {

constexpr const char* kSchemasVariable = "ECAT_ESI_SCHEMAS";

std::vector<std::string> split_paths(std::string_view list) {
  std::vector<std::string> out;
  while (!list.empty()) {
    const auto colon = list.find(':');
    const auto item = list.substr(0, colon);
    if (!item.empty()) out.emplace_back(item);
    if (colon == std::string_view::npos) break;
    list.remove_prefix(colon + 1);
  }
  return out;
}

const char* named_by_user() {
  const char* v = std::getenv(kSchemasVariable);
  return v && *v ? v : nullptr;
}

}  // namespace

bool have_xmllint() { return std::system("xmllint --version > /dev/null 2>&1") == 0; }

std::vector<std::string> esi_schemas() {
  if (const char* user = named_by_user()) return split_paths(user);
  std::vector<std::string> present;
  for (auto& path : split_paths(ECAT_ESI_SCHEMAS))
    if (std::filesystem::exists(path)) present.push_back(std::move(path));
  return present;
}

bool can_validate_esi() { return have_xmllint() && !esi_schemas().empty(); }

std::string why_no_esi_schema() {
  if (!have_xmllint()) return "xmllint is not installed";
  return std::string("no ETG ESI schema at ") + ECAT_ESI_SCHEMAS +
         " (set ECAT_ESI_SCHEMAS=/path/EtherCATInfo.xsd[:more] or configure -DECAT_ESI_SCHEMAS=...)";
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

std::string write_test_file(const std::string& name, const std::string& text) {
  const auto dir = std::filesystem::path(ECAT_BINARY_DIR) / "test-output";
  std::filesystem::create_directories(dir);
  const auto path = dir / name;
  std::ofstream(path, std::ios::binary) << text;
  return path.string();
}

}  // namespace ecat::esi::test
