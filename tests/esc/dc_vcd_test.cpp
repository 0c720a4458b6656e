// VCD trace: exact text of a small dump (IEEE 1364 §18 format), time clamped
// to be monotonic, marker pulses for SM events, ESM state as a 4-bit vector.
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "esc/dc/vcd_trace.hpp"

namespace ecat::esc {
namespace {

std::string contents(std::FILE* f) {
  std::rewind(f);
  std::string out;
  for (int c = std::fgetc(f); c != EOF; c = std::fgetc(f)) out.push_back(static_cast<char>(c));
  return out;
}

TEST(VcdTrace, WritesHeaderAndValueChanges) {
  std::FILE* f = std::tmpfile();
  ASSERT_NE(f, nullptr);
  ManualClock clock;
  {
    const std::vector<std::string> names{"drive 1", "io"};
    VcdTrace trace(f, names, clock);
    trace.probe(0).on_sync(0, true, Nanoseconds{1000});
    trace.probe(1).sm_event(2, Nanoseconds{1500});
    trace.probe(0).app_cycle(true, Nanoseconds{1600});
    trace.probe(0).on_sync(0, false, Nanoseconds{2000});
    trace.probe(0).on_sync(1, true, Nanoseconds{1900});  // late report: clamped to 2000
    clock.set(Nanoseconds{2500});
    trace.probe(1).on_state_changed(AlState::SafeOp, AlState::Op, AlStatusCode::NoError);
  }
  const std::string expected =
      "$version ecatslave $end\n$timescale 1ns $end\n$scope module chain $end\n"
      "$scope module drive_1 $end\n"
      "$var wire 1 ! sync0 $end\n$var wire 1 \" sync1 $end\n$var wire 1 # sm2_event $end\n"
      "$var wire 1 $ sm3_event $end\n$var wire 1 % app_cycle $end\n$var wire 4 & esm_state $end\n"
      "$upscope $end\n"
      "$scope module io $end\n"
      "$var wire 1 ' sync0 $end\n$var wire 1 ( sync1 $end\n$var wire 1 ) sm2_event $end\n"
      "$var wire 1 * sm3_event $end\n$var wire 1 + app_cycle $end\n$var wire 4 , esm_state $end\n"
      "$upscope $end\n$upscope $end\n$enddefinitions $end\n#0\n$dumpvars\n"
      "0!\n0\"\n0#\n0$\n0%\nb0001 &\n0'\n0(\n0)\n0*\n0+\nb0001 ,\n$end\n"
      "#1000\n1!\n#1500\n1)\n#1600\n1%\n#1700\n0)\n#2000\n0!\n1\"\n#2500\nb1000 ,\n";
  EXPECT_EQ(contents(f), expected);
  std::fclose(f);
}

}  // namespace
}  // namespace ecat::esc
