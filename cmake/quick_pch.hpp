// The precompiled header of the libraries in build type Quick
// (cmake/EcatLibrary.cmake; scripts/quickstart's first build): the headers
// most library files include. Not installed, not part of any layer.
#pragma once

#include <algorithm>
#include <array>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <tl/expected.hpp>
