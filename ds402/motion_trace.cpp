#include "ds402/motion_trace.hpp"

#include <fstream>

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
  if (!f) return fail("cannot open " + path + " for writing");
  write_csv(f);
  if (!f) return fail("cannot write " + path);
  return {};
}

}  // namespace ecat::ds402
