// YAML (yaml-cpp) to JSON (nlohmann) for scenario files: a scenario's `do`
// is a control-interface request (docs/control.md), so a step written in
// YAML becomes exactly the JSON a client would send. Plain scalars become
// integers (decimal, 0x hex, 0o/0 octal as strtoll reads them), booleans
// (true/false), null (null, ~, empty), numbers or strings; a quoted scalar
// is always a string.
#pragma once

#include <nlohmann/json.hpp>
#include <yaml-cpp/yaml.h>

namespace ecat::scenario {

nlohmann::json to_json(const YAML::Node& node);

}  // namespace ecat::scenario
