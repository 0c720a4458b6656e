#include "ds402/svg_plot.hpp"

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <fstream>
#include <sstream>
#include <string_view>

#include <fmt/format.h>

#include "ds402/statusword.hpp"
#include "ds402/svg_plot_axes.hpp"

namespace ecat::ds402 {

namespace {
constexpr double kWidth = 1000, kLeft = 70, kRight = 20, kTop = 40;
constexpr double kPanel = 170, kGap = 30, kBand = 22;
constexpr std::size_t kMaxPoints = 1200;  // per polyline

// One decimal is finer than a pixel.
double px(double v) { return std::round(v * 10.0) / 10.0; }

struct Series {
  std::string_view name;
  std::int32_t TraceRow::*member32 = nullptr;
  std::int16_t TraceRow::*member16 = nullptr;
  double value(const TraceRow& r) const { return member32 ? r.*member32 : r.*member16; }
};

}  // namespace

namespace svg_detail {
std::string_view state_name(std::uint16_t sw) {
  if ((sw & sw::kStateMaskNoQs) == sw::kFaultState) return "Fault";
  if ((sw & sw::kStateMaskNoQs) == sw::kFaultReactionActiveState) return "Fault reaction";
  if ((sw & sw::kStateMaskNoQs) == sw::kSwitchOnDisabledState) return "Switch on disabled";
  if ((sw & sw::kStateMask) == sw::kReadyToSwitchOnState) return "Ready";
  if ((sw & sw::kStateMask) == sw::kSwitchedOnState) return "Switched on";
  if ((sw & sw::kStateMask) == sw::kOperationEnabledState) return "Op. enabled";
  if ((sw & sw::kStateMask) == sw::kQuickStopActiveState) return "Quick stop";
  return "Not ready";
}

std::string_view mode_name(std::int8_t m) {
  switch (m) {
    case 1: return "PP";
    case 3: return "PV";
    case 4: return "PT";
    case 6: return "HM";
    case 7: return "IP";
    case 8: return "CSP";
    case 9: return "CSV";
    case 10: return "CST";
    default: return "-";
  }
}

std::string_view colour_for(std::string_view state) {
  if (state == "Op. enabled") return "#d9f2d9";
  if (state == "Quick stop") return "#ffe7b3";
  if (state == "Fault" || state == "Fault reaction") return "#f8c9c9";
  return "#e6e6e6";
}
}  // namespace svg_detail

namespace {
using svg_detail::colour_for;
using svg_detail::mode_name;
using svg_detail::state_name;

void panel(std::ostringstream& o, std::span<const TraceRow> rows, double y0, std::string_view label,
           const Series& demand, const Series& actual, double t0, double t1) {
  double lo = 0, hi = 0;
  for (const TraceRow& r : rows) {
    lo = std::min({lo, demand.value(r), actual.value(r)});
    hi = std::max({hi, demand.value(r), actual.value(r)});
  }
  if (hi - lo < 1) hi = lo + 1;
  const double pad = (hi - lo) * 0.05;
  lo -= pad;
  hi += pad;
  const double w = kWidth - kLeft - kRight;
  auto x = [&](double t) { return kLeft + (t1 > t0 ? (t - t0) / (t1 - t0) : 0) * w; };
  auto y = [&](double v) { return y0 + kPanel - (v - lo) / (hi - lo) * kPanel; };
  o << "<rect x='" << kLeft << "' y='" << y0 << "' width='" << w << "' height='" << kPanel
    << "' fill='none' stroke='#888'/>\n";
  o << "<text x='" << kLeft + 4 << "' y='" << y0 + 14 << "' font-size='12'>" << label << "</text>\n";
  o << "<text x='" << kLeft - 4 << "' y='" << y0 + 10 << "' font-size='10' text-anchor='end'>"
    << std::lround(hi) << "</text>\n";
  o << "<text x='" << kLeft - 4 << "' y='" << y0 + kPanel << "' font-size='10' text-anchor='end'>"
    << std::lround(lo) << "</text>\n";
  if (lo < 0 && hi > 0) {
    o << "<line x1='" << kLeft << "' x2='" << kLeft + w << "' y1='" << px(y(0)) << "' y2='" << px(y(0))
      << "' stroke='#ccc'/>\n";
  }
  const std::size_t stride = std::max<std::size_t>(1, (rows.size() + kMaxPoints - 1) / kMaxPoints);
  for (const Series* s : {&demand, &actual}) {
    o << "<polyline fill='none' stroke='" << (s == &demand ? "#1f77b4" : "#d62728")
      << "' stroke-width='1.2' points='";
    for (std::size_t i = 0; i < rows.size(); i += stride) {
      o << px(x(rows[i].time_s)) << ',' << px(y(s->value(rows[i]))) << ' ';
    }
    o << "'><title>" << s->name << "</title></polyline>\n";
  }
}
}  // namespace

std::string svg_plot(std::span<const TraceRow> rows, const std::string& title) {
  std::ostringstream o;
  o.precision(6);
  const double height = kTop + kBand + 3 * (kPanel + kGap) + 20;
  o << "<svg xmlns='http://www.w3.org/2000/svg' width='" << kWidth << "' height='" << height
    << "' viewBox='0 0 " << kWidth << ' ' << height << "' font-family='sans-serif'>\n";
  o << "<rect width='100%' height='100%' fill='white'/>\n";
  o << "<text x='" << kLeft << "' y='20' font-size='15'>" << title << "</text>\n";
  o << "<text x='" << kWidth - kRight << "' y='20' font-size='11' text-anchor='end'>"
    << "<tspan fill='#1f77b4'>demand</tspan> / <tspan fill='#d62728'>actual</tspan></text>\n";
  if (rows.empty()) {
    o << "<text x='" << kLeft << "' y='" << kTop + 20 << "'>no data</text>\n</svg>\n";
    return o.str();
  }
  const double t0 = rows.front().time_s, t1 = rows.back().time_s;
  const double w = kWidth - kLeft - kRight;
  auto x = [&](double t) { return kLeft + (t1 > t0 ? (t - t0) / (t1 - t0) : 0) * w; };
  // State/mode band: one rectangle per run of equal (state, mode).
  std::size_t start = 0;
  for (std::size_t i = 1; i <= rows.size(); ++i) {
    const bool end = i == rows.size();
    if (!end && state_name(rows[i].statusword) == state_name(rows[start].statusword) &&
        rows[i].mode == rows[start].mode) {
      continue;
    }
    const double xa = x(rows[start].time_s), xb = x(rows[end ? i - 1 : i].time_s);
    const std::string_view st = state_name(rows[start].statusword);
    o << "<rect x='" << px(xa) << "' y='" << kTop << "' width='" << px(std::max(0.5, xb - xa)) << "' height='" << kBand
      << "' fill='" << colour_for(st) << "' stroke='white'><title>" << st << ' ' << mode_name(rows[start].mode)
      << "</title></rect>\n";
    if (xb - xa > 60) {
      o << "<text x='" << px(xa + 3) << "' y='" << kTop + 15 << "' font-size='10'>" << st << ' '
        << mode_name(rows[start].mode) << "</text>\n";
    }
    start = i;
  }
  double y0 = kTop + kBand + 10;
  panel(o, rows, y0, "position (6062h / 6064h)", Series{"6062h", &TraceRow::position_demand, nullptr},
        Series{"6064h", &TraceRow::position_actual, nullptr}, t0, t1);
  y0 += kPanel + kGap;
  panel(o, rows, y0, "velocity (606Bh / 606Ch)", Series{"606Bh", &TraceRow::velocity_demand, nullptr},
        Series{"606Ch", &TraceRow::velocity_actual, nullptr}, t0, t1);
  y0 += kPanel + kGap;
  panel(o, rows, y0, "torque, per mille (6074h / 6077h)", Series{"6074h", nullptr, &TraceRow::torque_demand},
        Series{"6077h", nullptr, &TraceRow::torque_actual}, t0, t1);
  o << "<text x='" << kLeft << "' y='" << height - 6 << "' font-size='10'>" << t0 << " s</text>\n";
  o << "<text x='" << kWidth - kRight << "' y='" << height - 6 << "' font-size='10' text-anchor='end'>" << t1
    << " s</text>\n";
  o << "</svg>\n";
  return o.str();
}

Expected<void, std::string> write_svg_plot(std::span<const TraceRow> rows, const std::string& path,
                                           const std::string& title) {
  std::ofstream f(path);
  if (!f) return fail(fmt::format("cannot open {} for writing: {}", path, std::strerror(errno)));
  f << svg_plot(rows, title);
  // A write the buffer still holds fails only when it is flushed: close and check.
  f.close();
  if (!f) return fail(fmt::format("cannot write {}: {}", path, std::strerror(errno)));
  return {};
}

}  // namespace ecat::ds402
