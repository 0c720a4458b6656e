// The demonstration run behind docs/ds402-run.svg: enable -> homing -> PP ->
// CSP -> quick stop -> loss of sync fault -> reset. Checks the states seen
// and writes the trace as CSV and SVG into the build tree; with
// ECAT_UPDATE_DOCS=1 in the environment it also refreshes docs/ds402-run.svg.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <numbers>
#include <sstream>
#include <vector>

#include "ds402/controlword.hpp"
#include "ds402/motion_trace.hpp"
#include "ds402/statusword.hpp"
#include "ds402/svg_plot.hpp"
#include "harness.hpp"

namespace ecat::ds402::test {
namespace {

constexpr std::uint16_t kEnableOp = 0x000F;

struct DemoRun {
  Harness h;
  MotionTrace trace{20000};
  double t = 0;
  std::vector<PdsState> states;
  void step() {
    h.step();
    t += 0.001;
    trace.record(t, h.in, h.out);
    if (states.empty() || states.back() != h.drive.state()) states.push_back(h.drive.state());
  }
  void run(int n) {
    for (int i = 0; i < n; ++i) step();
  }
  void command(std::uint16_t c) {
    h.in.controlword = c;
    step();
  }
  template <typename F>
  bool until(F f, int limit) {
    for (int i = 0; i < limit; ++i) {
      step();
      if (f()) return true;
    }
    return false;
  }
};

TEST(Demo, EnableHomingPpCspQuickStopFaultReset) {
  DemoRun r;
  auto& in = r.h.in;
  in.homing_method = 24;
  in.homing_speed_switch = 400000;
  in.homing_speed_zero = 40000;
  in.homing_acceleration = 4000000;
  in.profile_velocity = 600000;
  in.profile_acceleration = 3000000;
  in.profile_deceleration = 3000000;
  in.quick_stop_deceleration = 6000000;
  in.quick_stop_option = 6;  // stay in Quick stop active
  in.fault_reaction_option = 2;
  in.modes_of_operation = 6;
  r.run(20);
  r.command(0x0006);
  r.command(0x0007);
  r.command(kEnableOp);
  r.run(50);
  r.command(kEnableOp | cw::kHomingStart);
  ASSERT_TRUE(r.until([&] { return r.h.bit(sw::kHomingAttained); }, 10000));
  r.run(100);
  // Profile position: out and back.
  in.modes_of_operation = 1;
  r.command(kEnableOp);
  for (std::int32_t target : {500000, -200000}) {
    in.target_position = target;
    r.command(kEnableOp | cw::kNewSetPoint);
    r.command(kEnableOp);
    ASSERT_TRUE(r.until([&] { return r.h.bit(sw::kTargetReached); }, 10000));
    r.run(100);
  }
  // Cyclic synchronous position: the master streams a sine around -200000.
  in.modes_of_operation = 8;
  in.target_position = r.h.out.position_actual;
  const double base = in.target_position;
  for (int i = 0; i < 1500; ++i) {
    in.target_position = static_cast<std::int32_t>(base + 250000.0 * std::sin(2 * std::numbers::pi * i / 1000.0));
    r.step();
  }
  // Quick stop while moving, then back to operation (transition 16).
  r.command(0x000B);
  ASSERT_TRUE(r.until([&] { return r.h.bit(sw::kTargetReached); }, 2000));
  r.run(100);
  in.target_position = r.h.out.position_actual;
  r.command(kEnableOp);
  EXPECT_EQ(r.h.drive.state(), PdsState::OperationEnabled);
  for (int i = 0; i < 300; ++i) {
    in.target_position += 300;
    r.step();
  }
  // The sync layer reports lost sync: fault, quick-stop reaction, reset.
  in.sync_lost = true;
  ASSERT_TRUE(r.until([&] { return r.h.drive.state() == PdsState::Fault; }, 3000));
  in.sync_lost = false;
  r.run(100);
  r.command(0x0000);
  r.command(cw::kFaultReset);
  r.run(100);
  EXPECT_EQ(r.h.drive.state(), PdsState::SwitchOnDisabled);

  const std::vector<PdsState> expected{
      PdsState::SwitchOnDisabled, PdsState::ReadyToSwitchOn,     PdsState::SwitchedOn,
      PdsState::OperationEnabled, PdsState::QuickStopActive,     PdsState::OperationEnabled,
      PdsState::FaultReactionActive, PdsState::Fault,            PdsState::SwitchOnDisabled};
  EXPECT_EQ(r.states, expected);
  EXPECT_EQ(r.trace.dropped(), 0u);

  const std::string dir = ECAT_BINARY_DIR;
  ASSERT_TRUE(r.trace.write_csv(dir + "/ds402-run.csv"));
  ASSERT_TRUE(write_svg_plot(r.trace.rows(), dir + "/ds402-run.svg", "ds402: enable, homing, PP, CSP, quick stop, fault, reset"));
  std::ifstream csv(dir + "/ds402-run.csv");
  std::string header;
  std::getline(csv, header);
  EXPECT_EQ(header, kTraceCsvHeader);
  const std::string svg = svg_plot(r.trace.rows(), "x");
  EXPECT_EQ(svg.rfind("<svg xmlns='http://www.w3.org/2000/svg'", 0), 0u);
  EXPECT_NE(svg.find("Quick stop"), std::string::npos);
  EXPECT_NE(svg.find("Fault"), std::string::npos);
  std::size_t polylines = 0;
  for (std::size_t p = svg.find("<polyline"); p != std::string::npos; p = svg.find("<polyline", p + 1)) ++polylines;
  EXPECT_EQ(polylines, 6u);
  if (const char* update = std::getenv("ECAT_UPDATE_DOCS"); update && std::string(update) == "1") {
    ASSERT_TRUE(write_svg_plot(r.trace.rows(), std::string(ECAT_SOURCE_DIR) + "/docs/ds402-run.svg",
                               "ds402: enable, homing, PP, CSP, quick stop, fault, reset"));
  }
}

TEST(MotionTrace, CsvRoundTripAndBadInput) {
  MotionTrace t(3);
  DriveInputs in;
  DriveOutputs out;
  in.controlword = 0x001F;
  out.statusword = 0x1237;
  out.modes_of_operation_display = -2;
  out.position_actual = -123456;
  out.torque_actual = -321;
  t.record(0.25, in, out);
  std::stringstream ss;
  t.write_csv(ss);
  auto rows = read_trace_csv(ss);
  ASSERT_TRUE(rows) << rows.error();
  ASSERT_EQ(rows->size(), 1u);
  EXPECT_DOUBLE_EQ((*rows)[0].time_s, 0.25);
  EXPECT_EQ((*rows)[0].mode, -2);
  EXPECT_EQ((*rows)[0].controlword, 0x001F);
  EXPECT_EQ((*rows)[0].statusword, 0x1237);
  EXPECT_EQ((*rows)[0].position_actual, -123456);
  EXPECT_EQ((*rows)[0].torque_actual, -321);

  std::stringstream bad_header("time,x\n");
  EXPECT_EQ(read_trace_csv(bad_header).error(), "line 1: not a ds402 trace header");
  std::stringstream short_row(std::string(kTraceCsvHeader) + "\n0,1,2\n");
  EXPECT_EQ(read_trace_csv(short_row).error(), "line 2: expected 10 numeric fields");
  std::stringstream junk(std::string(kTraceCsvHeader) + "\n0,1,2,3,4,5,6,7,8,x9\n");
  EXPECT_FALSE(read_trace_csv(junk));
  std::stringstream overflow(std::string(kTraceCsvHeader) + "\n0,1,2,3,4,5,6,7,99999,9\n");
  EXPECT_FALSE(read_trace_csv(overflow));  // 6074h is 16 bits
  EXPECT_FALSE(read_trace_csv(std::string("/nonexistent/trace.csv")));
}

TEST(SvgPlot, EmptyTraceStillGivesAnSvg) {
  const std::string svg = svg_plot({}, "empty");
  EXPECT_NE(svg.find("no data"), std::string::npos);
  EXPECT_NE(svg.find("</svg>"), std::string::npos);
}

TEST(MotionTrace, KeepsItsCapacity) {
  MotionTrace t(2);
  DriveInputs in;
  DriveOutputs out;
  out.position_actual = 7;
  t.record(0.0, in, out);
  t.record(0.001, in, out);
  t.record(0.002, in, out);
  EXPECT_EQ(t.rows().size(), 2u);
  EXPECT_EQ(t.dropped(), 1u);
  std::ostringstream os;
  t.write_csv(os);
  EXPECT_EQ(os.str(), std::string(kTraceCsvHeader) + "\n0,0,0,0,0,7,0,0,0,0\n0.001,0,0,0,0,7,0,0,0,0\n");
}

}  // namespace
}  // namespace ecat::ds402::test
