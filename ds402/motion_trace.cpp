#include "ds402/motion_trace.hpp"

#include <array>
#include <cerrno>
#include <charconv>
#include <cstring>
#include <cstdlib>
#include <type_traits>
#include <fstream>
#include <limits>
#include <string_view>

#include <fmt/format.h>

namespace ecat::ds402 {

void MotionTrace::record(double time_s, const DriveInputs& in, const DriveOutputs& out) noexcept {
  if (rows_.size() == rows_.capacity()) {
    ++dropped_;
    return;
  }
  rows_.push_back(TraceRow{time_s, out.modes_of_operation_display, in.controlword, out.statusword,
                           out.position_demand, out.position_actual, out.velocity_demand, out.velocity_actual,
                           out.torque_demand, out.torque_actual});
}

void MotionTrace::write_csv(std::ostream& os) const {
  os << kTraceCsvHeader << '\n';
  for (const TraceRow& r : rows_) {
    os << r.time_s << ',' << int{r.mode} << ',' << r.controlword << ',' << r.statusword << ','
       << r.position_demand << ',' << r.position_actual << ',' << r.velocity_demand << ',' << r.velocity_actual
       << ',' << r.torque_demand << ',' << r.torque_actual << '\n';
  }
}

Expected<void, std::string> MotionTrace::write_csv(const std::string& path) const {
  std::ofstream f(path);
  if (!f) return fail(fmt::format("cannot open {} for writing: {}", path, std::strerror(errno)));
  write_csv(f);
  // A write the buffer still holds fails only when it is flushed: close and check.
  f.close();
  if (!f) return fail(fmt::format("cannot write {}: {}", path, std::strerror(errno)));
  return {};
}

namespace {
template <typename T>
bool parse(std::string_view field, T& out) {
  if constexpr (std::is_floating_point_v<T>) {
    const std::string tmp(field);  // from_chars for double is not everywhere yet
    char* end = nullptr;
    out = std::strtod(tmp.c_str(), &end);
    return !tmp.empty() && end == tmp.c_str() + tmp.size();
  } else {
    long long v = 0;
    const auto [p, ec] = std::from_chars(field.data(), field.data() + field.size(), v);
    if (ec != std::errc{} || p != field.data() + field.size()) return false;
    if (v < std::numeric_limits<T>::min() || v > std::numeric_limits<T>::max()) return false;
    out = static_cast<T>(v);
    return true;
  }
}
}  // namespace

Expected<std::vector<TraceRow>, std::string> read_trace_csv(std::istream& is) {
  std::string line;
  if (!std::getline(is, line) || line != kTraceCsvHeader) return fail(std::string("line 1: not a ds402 trace header"));
  std::vector<TraceRow> rows;
  int number = 1;
  while (std::getline(is, line)) {
    ++number;
    if (line.empty()) continue;
    std::string_view rest(line);
    std::array<std::string_view, 10> f;
    std::size_t n = 0;
    while (n < f.size()) {
      const std::size_t comma = rest.find(',');
      f[n++] = rest.substr(0, comma);
      if (comma == std::string_view::npos) {
        rest = {};
        break;
      }
      rest.remove_prefix(comma + 1);
    }
    TraceRow r;
    const bool ok = n == f.size() && rest.empty() && parse(f[0], r.time_s) && parse(f[1], r.mode) &&
                    parse(f[2], r.controlword) && parse(f[3], r.statusword) && parse(f[4], r.position_demand) &&
                    parse(f[5], r.position_actual) && parse(f[6], r.velocity_demand) &&
                    parse(f[7], r.velocity_actual) && parse(f[8], r.torque_demand) && parse(f[9], r.torque_actual);
    if (!ok) return fail("line " + std::to_string(number) + ": expected 10 numeric fields");
    rows.push_back(r);
  }
  return rows;
}

Expected<std::vector<TraceRow>, std::string> read_trace_csv(const std::string& path) {
  std::ifstream f(path);
  if (!f) return fail("cannot open " + path);
  auto rows = read_trace_csv(f);
  if (!rows) return fail(path + ": " + rows.error());
  return rows;
}

}  // namespace ecat::ds402
