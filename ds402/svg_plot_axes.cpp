#include "ds402/svg_plot_axes.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <sstream>

namespace ecat::ds402 {

namespace {
constexpr double kWidth = 1000, kLeft = 70, kRight = 20, kTop = 40;
constexpr double kPanel = 170, kGap = 30, kBand = 18;
constexpr std::size_t kMaxPoints = 1200;  // per polyline
constexpr std::array<const char*, 4> kColours = {"#1f77b4", "#d62728", "#2ca02c", "#9467bd"};

double px(double v) { return std::round(v * 10.0) / 10.0; }
const char* colour(std::size_t axis) { return kColours[axis % kColours.size()]; }

struct Quantity {
  const char* label;
  double (*demand)(const TraceRow&);
  double (*actual)(const TraceRow&);
};
constexpr std::array<Quantity, 3> kQuantities = {{
    {"position (6062h / 6064h + n·800h)", [](const TraceRow& r) -> double { return r.position_demand; },
     [](const TraceRow& r) -> double { return r.position_actual; }},
    {"velocity (606Bh / 606Ch + n·800h)", [](const TraceRow& r) -> double { return r.velocity_demand; },
     [](const TraceRow& r) -> double { return r.velocity_actual; }},
    {"torque, per mille (6074h / 6077h + n·800h)", [](const TraceRow& r) -> double { return r.torque_demand; },
     [](const TraceRow& r) -> double { return r.torque_actual; }},
}};

struct Frame {
  double t0 = 0, t1 = 0;
  double x(double t) const { return kLeft + (t1 > t0 ? (t - t0) / (t1 - t0) : 0) * (kWidth - kLeft - kRight); }
};

void band(std::ostringstream& o, std::span<const TraceRow> rows, double y0, const Frame& f) {
  std::size_t start = 0;
  for (std::size_t i = 1; i <= rows.size(); ++i) {
    const bool end = i == rows.size();
    if (!end && svg_detail::state_name(rows[i].statusword) == svg_detail::state_name(rows[start].statusword) &&
        rows[i].mode == rows[start].mode) {
      continue;
    }
    const double xa = f.x(rows[start].time_s), xb = f.x(rows[end ? i - 1 : i].time_s);
    const std::string_view st = svg_detail::state_name(rows[start].statusword);
    const std::string_view md = svg_detail::mode_name(rows[start].mode);
    o << "<rect x='" << px(xa) << "' y='" << y0 << "' width='" << px(std::max(0.5, xb - xa)) << "' height='" << kBand
      << "' fill='" << svg_detail::colour_for(st) << "' stroke='white'><title>" << st << ' ' << md
      << "</title></rect>\n";
    if (xb - xa > 60) o << "<text x='" << px(xa + 3) << "' y='" << y0 + 13 << "' font-size='10'>" << st << ' ' << md << "</text>\n";
    start = i;
  }
}

void panel(std::ostringstream& o, std::span<const AxisTrace> axes, double y0, const Quantity& q, const Frame& f) {
  double lo = 0, hi = 0;
  for (const AxisTrace& a : axes) {
    for (const TraceRow& r : a.rows) lo = std::min({lo, q.demand(r), q.actual(r)}), hi = std::max({hi, q.demand(r), q.actual(r)});
  }
  if (hi - lo < 1) hi = lo + 1;
  const double pad = (hi - lo) * 0.05;
  lo -= pad;
  hi += pad;
  const double w = kWidth - kLeft - kRight;
  auto y = [&](double v) { return y0 + kPanel - (v - lo) / (hi - lo) * kPanel; };
  o << "<rect x='" << kLeft << "' y='" << y0 << "' width='" << w << "' height='" << kPanel
    << "' fill='none' stroke='#888'/>\n";
  o << "<text x='" << kLeft + 4 << "' y='" << y0 + 14 << "' font-size='12'>" << q.label << "</text>\n";
  o << "<text x='" << kLeft - 4 << "' y='" << y0 + 10 << "' font-size='10' text-anchor='end'>" << std::lround(hi) << "</text>\n";
  o << "<text x='" << kLeft - 4 << "' y='" << y0 + kPanel << "' font-size='10' text-anchor='end'>" << std::lround(lo) << "</text>\n";
  for (std::size_t k = 0; k < axes.size(); ++k) {
    const auto rows = axes[k].rows;
    const std::size_t stride = std::max<std::size_t>(1, (rows.size() + kMaxPoints - 1) / kMaxPoints);
    for (const bool demand : {true, false}) {
      o << "<polyline fill='none' stroke='" << colour(k) << "' stroke-width='1.2'"
        << (demand ? " stroke-dasharray='4 3' stroke-opacity='0.6'" : "") << " points='";
      for (std::size_t i = 0; i < rows.size(); i += stride) {
        o << px(f.x(rows[i].time_s)) << ',' << px(y(demand ? q.demand(rows[i]) : q.actual(rows[i]))) << ' ';
      }
      o << "'><title>" << axes[k].name << (demand ? " demand" : " actual") << "</title></polyline>\n";
    }
  }
}
}  // namespace

std::string svg_plot_axes(std::span<const AxisTrace> axes, const std::string& title) {
  std::ostringstream o;
  o.precision(6);
  const double bands = static_cast<double>(axes.size()) * (kBand + 4);
  const double height = kTop + bands + 3 * (kPanel + kGap) + 20;
  o << "<svg xmlns='http://www.w3.org/2000/svg' width='" << kWidth << "' height='" << height << "' viewBox='0 0 "
    << kWidth << ' ' << height << "' font-family='sans-serif'>\n";
  o << "<rect width='100%' height='100%' fill='white'/>\n";
  o << "<text x='" << kLeft << "' y='20' font-size='15'>" << title << "</text>\n";
  o << "<text x='" << kWidth - kRight << "' y='20' font-size='11' text-anchor='end'>";
  for (std::size_t k = 0; k < axes.size(); ++k) o << "<tspan fill='" << colour(k) << "'>" << axes[k].name << "</tspan> ";
  o << "(dashed: demand, solid: actual)</text>\n";
  Frame f;
  bool any = false;
  for (const AxisTrace& a : axes) {
    if (a.rows.empty()) continue;
    f.t0 = any ? std::min(f.t0, a.rows.front().time_s) : a.rows.front().time_s;
    f.t1 = any ? std::max(f.t1, a.rows.back().time_s) : a.rows.back().time_s;
    any = true;
  }
  if (!any) {
    o << "<text x='" << kLeft << "' y='" << kTop + 20 << "'>no data</text>\n</svg>\n";
    return o.str();
  }
  double y0 = kTop;
  for (std::size_t k = 0; k < axes.size(); ++k) {
    o << "<text x='" << kLeft - 4 << "' y='" << y0 + 13 << "' font-size='10' text-anchor='end' fill='" << colour(k)
      << "'>" << axes[k].name << "</text>\n";
    band(o, axes[k].rows, y0, f);
    y0 += kBand + 4;
  }
  y0 += 10;
  for (const Quantity& q : kQuantities) {
    panel(o, axes, y0, q, f);
    y0 += kPanel + kGap;
  }
  o << "<text x='" << kLeft << "' y='" << height - 6 << "' font-size='10'>" << f.t0 << " s</text>\n";
  o << "<text x='" << kWidth - kRight << "' y='" << height - 6 << "' font-size='10' text-anchor='end'>" << f.t1
    << " s</text>\n";
  o << "</svg>\n";
  return o.str();
}

Expected<void, std::string> write_svg_plot_axes(std::span<const AxisTrace> axes, const std::string& path,
                                                const std::string& title) {
  std::ofstream file(path);
  if (!file) return fail("cannot open " + path + " for writing");
  file << svg_plot_axes(axes, title);
  if (!file) return fail("cannot write " + path);
  return {};
}

}  // namespace ecat::ds402
