// A plain-SVG plot of a motion trace: position, velocity and torque (demand
// and actual) in three stacked panels over time, with a band showing the
// PDS state and the mode of operation. No plotting library.
#pragma once

#include <span>
#include <string>

#include "common/expected.hpp"
#include "ds402/motion_trace.hpp"

namespace ecat::ds402 {

std::string svg_plot(std::span<const TraceRow> rows, const std::string& title = "ds402 motion trace");
Expected<void, std::string> write_svg_plot(std::span<const TraceRow> rows, const std::string& path,
                                           const std::string& title = "ds402 motion trace");

}  // namespace ecat::ds402
