// Per-cycle record of the drive's demand and actual values for plots and
// offline checks. Capacity is fixed at construction, so recording in the
// cyclic path never allocates; rows past the capacity are counted, not kept.
#pragma once

#include <cstddef>
#include <cstdint>
#include <istream>
#include <ostream>
#include <span>
#include <string>
#include <vector>

#include "common/expected.hpp"
#include "ds402/objects.hpp"

namespace ecat::ds402 {

struct TraceRow {
  double time_s = 0;
  std::int8_t mode = 0;            // 6061h
  std::uint16_t controlword = 0;   // 6040h
  std::uint16_t statusword = 0;    // 6041h
  std::int32_t position_demand = 0;  // 6062h
  std::int32_t position_actual = 0;  // 6064h
  std::int32_t velocity_demand = 0;  // 606Bh
  std::int32_t velocity_actual = 0;  // 606Ch
  std::int16_t torque_demand = 0;    // 6074h
  std::int16_t torque_actual = 0;    // 6077h
};

class MotionTrace {
 public:
  explicit MotionTrace(std::size_t capacity) { rows_.reserve(capacity); }

  void record(double time_s, const DriveInputs& in, const DriveOutputs& out) noexcept;

  std::span<const TraceRow> rows() const noexcept { return rows_; }
  std::size_t dropped() const noexcept { return dropped_; }

  // CSV with a header line; times in seconds, the rest as the objects hold them.
  void write_csv(std::ostream& os) const;
  Expected<void, std::string> write_csv(const std::string& path) const;

 private:
  std::vector<TraceRow> rows_;
  std::size_t dropped_ = 0;
};

// Reads a CSV written by write_csv back (e.g. to plot it later). A wrong
// header, a short row or a value that is not a number is an error naming the line.
Expected<std::vector<TraceRow>, std::string> read_trace_csv(std::istream& is);
Expected<std::vector<TraceRow>, std::string> read_trace_csv(const std::string& path);

inline constexpr const char* kTraceCsvHeader =
    "time_s,mode,controlword,statusword,position_demand,position_actual,velocity_demand,velocity_actual,"
    "torque_demand,torque_actual";

}  // namespace ecat::ds402
