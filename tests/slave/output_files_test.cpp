// Issue 19: output files of a run (SVG motion plot, VCD trace) whose writes
// fail or come up short are reported as errors naming the file, and a failed
// plot is never reported as "no drive has a motion trace". /dev/full takes
// the open and refuses every write (ENOSPC), as a full disk or an exhausted
// memory lock would.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>

#include "ds402/motion_trace.hpp"
#include "ds402/svg_plot.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {
namespace {

constexpr const char* kFull = "/dev/full";

bool device_full_exists() { return std::filesystem::exists(kFull); }

TEST(OutputFiles, PlotOfAChainWithATracingDriveReportsTheFailedWrite) {
  if (!device_full_exists()) GTEST_SKIP() << "no /dev/full";
  InProcess p;
  auto d = esi::load_default_device();
  ASSERT_TRUE(d);
  slave::SlaveOptions o;
  o.motion_trace = true;
  p.add(*d, o);
  ASSERT_EQ(p.bring_up(), "");
  auto ok = p.chain.write_plot(kFull);
  ASSERT_FALSE(ok);
  EXPECT_NE(ok.error().find(kFull), std::string::npos) << ok.error();
  EXPECT_NE(ok.error().find("cannot write"), std::string::npos) << ok.error();
  EXPECT_EQ(ok.error().find("no drive"), std::string::npos) << ok.error();
  // Written where it can be: the whole document.
  const auto path = std::filesystem::temp_directory_path() / ("ecat-plot-" + std::to_string(::getpid()) + ".svg");
  ASSERT_TRUE(p.chain.write_plot(path.string()));
  std::ifstream f(path);
  const std::string svg((std::istreambuf_iterator<char>(f)), std::istreambuf_iterator<char>());
  std::filesystem::remove(path);
  EXPECT_EQ(svg.substr(svg.size() - 7), "</svg>\n");
}

TEST(OutputFiles, PlotWithoutADriveSaysSoAndNamesTheFile) {
  InProcess p;
  p.add_default();  // no --plot: the drive keeps no trace
  auto ok = p.chain.write_plot("run.svg");
  ASSERT_FALSE(ok);
  EXPECT_EQ(ok.error(), "run.svg: not written: no slave of the chain records a motion trace (a CiA402 drive as the first slave does)");
}

TEST(OutputFiles, ShortSvgAndCsvWritesAreErrors) {
  if (!device_full_exists()) GTEST_SKIP() << "no /dev/full";
  // Small enough to stay in the stream's buffer until it is closed.
  ds402::MotionTrace trace(2);
  trace.record(0.0, {}, {});
  auto svg = ds402::write_svg_plot(trace.rows(), kFull, "t");
  ASSERT_FALSE(svg);
  EXPECT_EQ(svg.error().rfind("cannot write /dev/full", 0), 0u) << svg.error();
  auto csv = trace.write_csv(kFull);
  ASSERT_FALSE(csv);
  EXPECT_EQ(csv.error().rfind("cannot write /dev/full", 0), 0u) << csv.error();
}

TEST(OutputFiles, VcdTraceWriteFailureIsReportedAtShutdown) {
  if (!device_full_exists()) GTEST_SKIP() << "no /dev/full";
  InProcess p;
  p.add_default();
  ASSERT_TRUE(p.chain.open_trace(kFull));
  p.advance(std::chrono::milliseconds(1));
  auto ok = p.chain.shutdown();
  ASSERT_FALSE(ok);
  EXPECT_EQ(ok.error().rfind("cannot write /dev/full", 0), 0u) << ok.error();
}

}  // namespace
}  // namespace ecat::test
