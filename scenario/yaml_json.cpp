#include "scenario/yaml_json.hpp"

#include <cerrno>
#include <cstdlib>
#include <string>

namespace ecat::scenario {
namespace {

using nlohmann::json;

// A plain scalar as YAML 1.2's core schema reads it (plus 0x/0o integers).
json plain_scalar(const std::string& s) {
  if (s.empty() || s == "~" || s == "null" || s == "Null" || s == "NULL") return nullptr;
  if (s == "true" || s == "True" || s == "TRUE") return true;
  if (s == "false" || s == "False" || s == "FALSE") return false;
  std::string digits = s;
  if (digits.size() > 2 && digits[0] == '0' && (digits[1] == 'o' || digits[1] == 'O')) digits.erase(1, 1);
  errno = 0;
  char* end = nullptr;
  const bool negative = !digits.empty() && digits[0] == '-';
  if (negative) {
    const long long v = std::strtoll(digits.c_str(), &end, 0);
    if (errno == 0 && end && *end == '\0') return v;
  } else if (!digits.empty() && digits[0] != '+') {
    const unsigned long long v = std::strtoull(digits.c_str(), &end, 0);
    if (errno == 0 && end && *end == '\0') {
      if (v <= static_cast<unsigned long long>(INT64_MAX)) return static_cast<std::int64_t>(v);
      return v;
    }
  }
  errno = 0;
  end = nullptr;
  const double d = std::strtod(s.c_str(), &end);
  if (errno == 0 && end && *end == '\0' && s.find_first_of("0123456789") != std::string::npos) return d;
  return s;
}

}  // namespace

json to_json(const YAML::Node& node) {
  switch (node.Type()) {
    case YAML::NodeType::Null:
    case YAML::NodeType::Undefined:
      return nullptr;
    case YAML::NodeType::Scalar:
      // "!" is the tag of a quoted scalar: a string, whatever it holds.
      if (node.Tag() == "!") return node.Scalar();
      return plain_scalar(node.Scalar());
    case YAML::NodeType::Sequence: {
      json a = json::array();
      for (const YAML::Node& item : node) a.push_back(to_json(item));
      return a;
    }
    case YAML::NodeType::Map: {
      json o = json::object();
      for (const auto& kv : node) o[kv.first.Scalar()] = to_json(kv.second);
      return o;
    }
  }
  return nullptr;
}

}  // namespace ecat::scenario
