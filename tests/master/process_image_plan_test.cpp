// The process image cut into logical datagrams and frames (master/
// process_image_plan.hpp): exact addresses, lengths, frames and expected WKCs
// for images of 1, 2 and several frames, SOEM's segment rule (a slave's span
// that fits one datagram is not split, masters.md §1.4) and the per-ESC WKC
// counting of ETG.1000.4 §5.4.3.
#include <gtest/gtest.h>

#include "master/process_image_plan.hpp"

namespace ecat::master::test {
namespace {

// Layout as Master::configure_process_data makes it: all outputs in slave
// order, then all inputs.
std::vector<FmmuSpan> layout(std::uint32_t slaves, std::uint32_t out, std::uint32_t in) {
  std::vector<FmmuSpan> spans;
  std::uint32_t at = 0;
  for (std::uint32_t i = 0; i < slaves; ++i, at += out) spans.push_back({at, out, i, true});
  for (std::uint32_t i = 0; i < slaves; ++i, at += in) spans.push_back({at, in, i, false});
  return spans;
}

struct Want {
  Command command;
  std::uint32_t logical;
  std::uint16_t length;
  std::uint16_t wkc;
  std::uint32_t frame;
};

void expect_plan(const ProcessImagePlan& plan, std::size_t frames, const std::vector<Want>& want) {
  EXPECT_EQ(plan.frames, frames);
  ASSERT_EQ(plan.datagrams.size(), want.size());
  for (std::size_t i = 0; i < want.size(); ++i) {
    SCOPED_TRACE(i);
    EXPECT_EQ(plan.datagrams[i].command, want[i].command);
    EXPECT_EQ(plan.datagrams[i].logical, want[i].logical);
    EXPECT_EQ(plan.datagrams[i].length, want[i].length);
    EXPECT_EQ(plan.datagrams[i].expected_wkc, want[i].wkc);
    EXPECT_EQ(plan.datagrams[i].frame, want[i].frame);
  }
}

TEST(ProcessImagePlan, SmallImageIsOneLrwInOneFrame) {
  const std::vector<FmmuSpan> spans{{0, 10, 0, true}, {10, 20, 1, true}, {30, 30, 2, true},
                                    {60, 5, 0, false}, {65, 6, 1, false}, {71, 7, 2, false}};
  auto plan = plan_process_image(spans, 60, 78, true);
  ASSERT_TRUE(plan.has_value());
  expect_plan(*plan, 1, {{Command::Lrw, 0, 78, 9, 0}});  // 2 x 3 writers + 3 readers
}

TEST(ProcessImagePlan, TwoFramesCutAtASlaveBoundary) {
  // 40 slaves x (20 out + 20 in) = 1600 bytes: 74 spans = 1480 bytes fill the
  // first datagram (a 75th would pass 1486); the rest goes in a second frame.
  const auto spans = layout(40, 20, 20);
  auto plan = plan_process_image(spans, 800, 1600, true);
  ASSERT_TRUE(plan.has_value());
  expect_plan(*plan, 2, {{Command::Lrw, 0, 1480, 2 * 40 + 34, 0}, {Command::Lrw, 1480, 120, 6, 1}});
  // With a DC slave the first frame keeps 20 bytes for the FRMW (SOEM EC_FIRSTDCDATAGRAM).
  PlanLimits dc;
  dc.first_frame_reserved = kDcDatagramBytes;
  auto with_dc = plan_process_image(spans, 800, 1600, true, dc);
  ASSERT_TRUE(with_dc.has_value());
  expect_plan(*with_dc, 2, {{Command::Lrw, 0, 1460, 2 * 40 + 33, 0}, {Command::Lrw, 1460, 140, 7, 1}});
}

TEST(ProcessImagePlan, SeveralFramesLogicalAddressesRunOn) {
  // 300 slaves x (8 out + 8 in) = 4800 bytes: 185 spans (1480 bytes) per datagram.
  const auto spans = layout(300, 8, 8);
  auto plan = plan_process_image(spans, 2400, 4800, true);
  ASSERT_TRUE(plan.has_value());
  expect_plan(*plan, 4,
              {{Command::Lrw, 0, 1480, 2 * 185, 0},
               {Command::Lrw, 1480, 1480, 2 * 115 + 70, 1},
               {Command::Lrw, 2960, 1480, 185, 2},
               {Command::Lrw, 4440, 360, 45, 3}});
}

TEST(ProcessImagePlan, SmallerDatagramsShareAFrame) {
  // At most 700 bytes per datagram: three datagrams fill frame 0 (708 + 708 +
  // 76 of its 1498 bytes), the last one opens frame 1.
  const auto spans = layout(100, 8, 8);
  PlanLimits limits;
  limits.max_datagram_data = 700;
  auto plan = plan_process_image(spans, 800, 1600, true, limits);
  ASSERT_TRUE(plan.has_value());
  expect_plan(*plan, 2,
              {{Command::Lrw, 0, 696, 2 * 87, 0},
               {Command::Lrw, 696, 696, 2 * 13 + 74, 0},
               {Command::Lrw, 1392, 64, 8, 0},
               {Command::Lrw, 1456, 144, 18, 1}});
}

TEST(ProcessImagePlan, ASpanLargerThanADatagramIsCutAndCountsInBoth) {
  const std::vector<FmmuSpan> spans{{0, 2000, 0, true}, {2000, 100, 0, false}};
  auto plan = plan_process_image(spans, 2000, 2100, true);
  ASSERT_TRUE(plan.has_value());
  // The slave's write FMMU overlaps both datagrams: +2 in each (ETG.1000.4 §5.4.3).
  expect_plan(*plan, 2, {{Command::Lrw, 0, 1486, 2, 0}, {Command::Lrw, 1486, 614, 3, 1}});
}

TEST(ProcessImagePlan, LwrThenLrdWithoutLrw) {
  const auto spans = layout(2, 4, 6);
  auto plan = plan_process_image(spans, 8, 20, false);
  ASSERT_TRUE(plan.has_value());
  expect_plan(*plan, 1, {{Command::Lwr, 0, 8, 2, 0}, {Command::Lrd, 8, 12, 2, 0}});
  // Large: the LWR and LRD regions each cut, sharing frames where they fit.
  const auto big = layout(100, 10, 10);
  auto split = plan_process_image(big, 1000, 2000, false);
  ASSERT_TRUE(split.has_value());
  expect_plan(*split, 2,
              {{Command::Lwr, 0, 1000, 100, 0}, {Command::Lrd, 1000, 470, 47, 0}, {Command::Lrd, 1470, 530, 53, 1}});
}

TEST(ProcessImagePlan, ReadFmmusOfOneSlaveCountOncePerDatagram) {
  // Slave 0: inputs and its SM1 status byte in the same datagram -> +1, not +2.
  const std::vector<FmmuSpan> spans{{0, 4, 0, true}, {4, 4, 0, false}, {8, 1, 0, false}};
  auto plan = plan_process_image(spans, 4, 9, true);
  ASSERT_TRUE(plan.has_value());
  expect_plan(*plan, 1, {{Command::Lrw, 0, 9, 3, 0}});
}

TEST(ProcessImagePlan, GapsOverlapsAndBadLimitsAreRefused) {
  const std::vector<FmmuSpan> gap{{0, 4, 0, true}, {6, 4, 0, false}};
  EXPECT_EQ(plan_process_image(gap, 4, 10, true).error(), MasterError::InvalidArgument);
  const std::vector<FmmuSpan> short_total{{0, 4, 0, true}};
  EXPECT_EQ(plan_process_image(short_total, 4, 10, true).error(), MasterError::InvalidArgument);
  PlanLimits too_big;
  too_big.max_datagram_data = kMaxDatagramData + 1;
  EXPECT_EQ(plan_process_image(short_total, 4, 4, true, too_big).error(), MasterError::InvalidArgument);
  auto empty = plan_process_image({}, 0, 0, true);
  ASSERT_TRUE(empty.has_value());
  EXPECT_EQ(empty->frames, 0u);
  EXPECT_TRUE(empty->datagrams.empty());
}

}  // namespace
}  // namespace ecat::master::test
