// The precompiled header of every GoogleTest program (cmake/EcatLibrary.cmake,
// ecat_test; option ECAT_PCH): GoogleTest and the standard headers most test
// files include, parsed once per program instead of once per file (about 40 %
// of a test file's compile time: docs/build-times.md). Each file still includes
// what it uses; a build with -DECAT_PCH=OFF checks that it does.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cstdint>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include <fmt/format.h>
#include <tl/expected.hpp>
