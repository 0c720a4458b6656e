// A plain-SVG plot of several axes' motion traces side by side (a
// multi-axis drive): one PDS state/mode band per axis, then position,
// velocity and torque panels with each axis' demand (dashed) and actual
// value (solid) in that axis' colour. No plotting library.
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <string_view>

#include "common/expected.hpp"
#include "ds402/motion_trace.hpp"

namespace ecat::ds402 {

struct AxisTrace {
  std::string name;  // "axis 1"
  std::span<const TraceRow> rows;
};

std::string svg_plot_axes(std::span<const AxisTrace> axes, const std::string& title = "ds402 motion trace");
Expected<void, std::string> write_svg_plot_axes(std::span<const AxisTrace> axes, const std::string& path,
                                                const std::string& title = "ds402 motion trace");

// The labels svg_plot uses (ds402/svg_plot.cpp).
namespace svg_detail {
std::string_view state_name(std::uint16_t statusword);
std::string_view mode_name(std::int8_t mode);
std::string_view colour_for(std::string_view state);
}  // namespace svg_detail

}  // namespace ecat::ds402
