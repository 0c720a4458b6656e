// Frames through a line of ESCs: malformed frames, source MAC, lost and
// circulating frames, VLAN tags, and no heap on the frame path.
#include <gtest/gtest.h>

#include <atomic>
#include <cstdlib>
#include <new>

#include "esc_fixture.hpp"
#include "tests/support/alloc_counter.hpp"

namespace ecat::esc::test {
namespace {

constexpr std::uint16_t kRam = 0x1000;

// A frame with one BWR of 4 bytes at 0x1000, as raw bytes.
Data bwr_frame() {
  Data buf(60);
  FrameBuilder b(buf);
  (void)b.append(Command::Bwr, 0, device_address(0, kRam), Data{1, 2, 3, 4});
  b.finish();
  return buf;
}

void expect_untouched(Line& line) {
  for (std::size_t i = 0; i < line.escs.size(); ++i) EXPECT_EQ(line[i].memory()[kRam], 0) << "slave " << i;
}

TEST(SegmentFrames, WellFormedFrameReachesAllAndMarksSourceMac) {
  Line line(3);
  Data f = bwr_frame();
  EXPECT_EQ(f[6], 0x00);
  ASSERT_TRUE(line.segment.process_frame(f, 0ns));
  EXPECT_EQ(f[6], 0x02);  // SOURCE_MAC[1]
  EXPECT_EQ(f[0], 0xFF);  // destination untouched
  EXPECT_EQ(f.size(), 60u);
  EXPECT_EQ(load_le<std::uint16_t>(f.data() + 14 + 2 + 10 + 4), 3);  // WKC
  for (std::size_t i = 0; i < 3; ++i) EXPECT_EQ(line[i].memory()[kRam], 1);
  EXPECT_EQ(line.segment.frames_processed(), 1u);
}

struct Malformed {
  const char* name;
  void (*mutate)(Data&);
  FrameError error;
};

class SegmentMalformed : public ::testing::TestWithParam<Malformed> {};

TEST_P(SegmentMalformed, LeavesEveryEscUnchangedAndCounts) {
  Line line(3);
  Data f = bwr_frame();
  GetParam().mutate(f);
  const Data before = f;
  EXPECT_FALSE(line.segment.process_frame(f, 0ns));
  EXPECT_EQ(line.segment.last_error(), GetParam().error);
  EXPECT_EQ(f, before);  // not a byte changed
  expect_untouched(line);
  // The first processing unit rejects the frame (0x030C) and marks it; the
  // others count it as forwarded where it enters (port 0 on the way out,
  // port 1 on the way back) and in their units (Section I §14.1 Table 51).
  const auto counters = [&](std::size_t i) {
    const std::uint8_t* m = line[i].memory();
    return Data(m + reg::kRxErrorCounter, m + reg::kProcessingUnitErrorCounter + 1);
  };
  //                    0x0300..0x0307 (invalid/RX per port)  0x0308..0x030B fwd  0x030C
  EXPECT_EQ(counters(0), (Data{0, 0, 0, 0, 0, 0, 0, 0, /**/ 0, 1, 0, 0, /**/ 1}));
  EXPECT_EQ(counters(1), (Data{0, 0, 0, 0, 0, 0, 0, 0, /**/ 1, 1, 0, 0, /**/ 1}));
  EXPECT_EQ(counters(2), (Data{0, 0, 0, 0, 0, 0, 0, 0, /**/ 1, 0, 0, 0, /**/ 1}));
  EXPECT_EQ(line.segment.frames_dropped(), 1u);
}

INSTANTIATE_TEST_SUITE_P(
    All, SegmentMalformed,
    ::testing::Values(
        Malformed{"Short", [](Data& f) { f.resize(20); }, FrameError::LengthBeyondFrame},
        Malformed{"EthernetOnly", [](Data& f) { f.resize(13); }, FrameError::TooShort},
        Malformed{"LengthBeyondFrame", [](Data& f) { f[14] = 0xFF; f[15] = 0x13; }, FrameError::LengthBeyondFrame},
        Malformed{"WrongType", [](Data& f) { f[15] = 0x40; }, FrameError::UnsupportedType},
        Malformed{"DatagramBeyondFrame", [](Data& f) { f[22] = 0x40; }, FrameError::DatagramBeyondFrame},
        Malformed{"MoreWithoutNext", [](Data& f) { f[23] = 0x80; }, FrameError::DatagramBeyondFrame},
        Malformed{"TrailingBytesInLength", [](Data& f) { f[14] = static_cast<std::uint8_t>(f[14] + 3); },
                  FrameError::LengthMismatch},
        Malformed{"UnknownCommand", [](Data& f) { f[16] = 0x20; }, FrameError::UnknownCommand}),
    [](const auto& p) { return std::string(p.param.name); });

TEST(SegmentFrames, NonEtherCatFrameIsNotCounted) {
  Line line(2);
  Data f = bwr_frame();
  f[12] = 0x08;
  f[13] = 0x00;  // IPv4
  EXPECT_FALSE(line.segment.process_frame(f, 0ns));
  EXPECT_EQ(line.segment.last_error(), FrameError::NotEtherCat);
  EXPECT_EQ(line[0].memory()[reg::kRxErrorCounter], 0);
  expect_untouched(line);
}

TEST(SegmentFrames, ShortUnpaddedFrameIsProcessed) {
  Line line(1);
  Data f = bwr_frame();
  f.resize(14 + 2 + 10 + 4 + 2);
  ASSERT_TRUE(line.segment.process_frame(f, 0ns));
  EXPECT_EQ(f.size(), 32u);
  EXPECT_EQ(line[0].memory()[kRam + 3], 4);
}

TEST(SegmentFrames, VlanTaggedFrame) {
  Line line(2);
  Data buf(64);
  EthernetHeader eth;
  eth.destination = kBroadcastMac;
  eth.vlan_tci = 0x0005;
  ASSERT_TRUE(eth.pack(buf));
  FrameHeader{12 + 1, kFrameTypeDlpdu}.pack(std::span(buf).subspan(18));
  DatagramHeader h;
  h.command = Command::Brd;
  h.address = device_address(0, reg::kType);
  h.length = 1;
  ASSERT_TRUE(h.pack(std::span(buf).subspan(20)));
  ASSERT_TRUE(line.segment.process_frame(buf, 0ns));
  EXPECT_EQ(buf[30], kEscTypeEt1100);
  EXPECT_EQ(buf[31], 2);  // WKC
}

TEST(SegmentFrames, FrameSentIntoAnOpenPortWithoutLinkIsLost) {
  Line line(2);
  // Force the last slave's port 1 open (0x0101 bits 11:10 = 10): nothing is connected.
  TestFrame open;
  open.add(Command::Apwr, ap(1, reg::kDlControl + 1), Data{0x08});
  EXPECT_FALSE(open.send(line.segment));  // this frame already leaves through the open port
  EXPECT_EQ(line[1].memory()[reg::kDlControl + 1], 0x08);
  Data f = bwr_frame();
  EXPECT_FALSE(line.segment.process_frame(f, 0ns));
  EXPECT_EQ(line.segment.frames_dropped(), 2u);
}

TEST(EscCirculating, SecondPassThroughClosedPort0DestroysTheFrame) {
  ManualClock clock;
  Esc esc(make_config(), clock);  // no link on port 0 -> closed
  Data buf = bwr_frame();
  auto view = parse_frame(buf);
  ASSERT_TRUE(view);
  EXPECT_TRUE(esc.process(*view, 0ns));
  EXPECT_TRUE((*view)[0].circulating());
  EXPECT_EQ((*view)[0].wkc(), 1);
  EXPECT_EQ(esc.memory()[reg::kProcessingUnitErrorCounter], 0);
  EXPECT_FALSE(esc.process(*view, 0ns));
  EXPECT_EQ((*view)[0].wkc(), 1);  // not processed again
  EXPECT_EQ(esc.memory()[reg::kProcessingUnitErrorCounter], 1);  // Section I §14.1 Table 51
}

TEST(SegmentFrames, NoHeapAllocationPerFrame) {
  Line line(3);
  assign_stations(line);
  for (std::uint16_t i = 0; i < 3; ++i) {
    const auto st = static_cast<std::uint16_t>(0x1001 + i);
    config_sm(line.segment, st, 2, 0x1100, 4, 0x64);
    config_sm(line.segment, st, 3, 0x1200, 4, 0x20);
    config_fmmu(line.segment, st, 0, 4u * i, 4, 0, 7, 0x1100, 0, 2);
    config_fmmu(line.segment, st, 1, 0x100 + 4u * i, 4, 0, 7, 0x1200, 0, 1);
  }
  std::array<std::uint8_t, 256> buf{};
  FrameBuilder b(buf);
  (void)b.append_zeros(Command::Lrw, 0, 0, 12);
  (void)b.append_zeros(Command::Lrd, 1, 0x100, 12);
  (void)b.append_zeros(Command::Brd, 2, device_address(0, reg::kAlStatus), 2);
  (void)b.append_zeros(Command::Frmw, 3, device_address(0x1001, 0x0910), 8);
  (void)b.append_zeros(Command::Fprd, 4, device_address(0x1002, reg::kEepromControlStatus), 10);
  Bytes frame = b.finish();
  ASSERT_TRUE(line.segment.process_frame(frame, 0ns));  // warm-up
  // The counter itself works...
  {
    const ecat::test::AllocCounter counter;
    auto probe = std::make_unique<int>(1);
    EXPECT_EQ(counter.count(), 1u);
  }
  // ...and the frame path does not allocate.
  {
    const ecat::test::AllocCounter counter;
    for (int i = 0; i < 100; ++i) {
      (void)line.segment.process_frame(frame, Nanoseconds{i * 1000});
      line[1].write(0x1200, std::span(buf).first(4));
      (void)line.segment.poll(Nanoseconds{i * 1000 + 500});
    }
    EXPECT_EQ(counter.count(), 0u);
  }
}

// The same for frames that pass ESCs by (issue 16 item 5): LRW, FPRD and
// APRD without a broadcast take the skipping path (plan, index, lazy times),
// with time going back once (every ESC takes in the previous frame).
TEST(SegmentFrames, NoHeapAllocationPerSkippingFrame) {
  Line line(70);
  assign_stations(line);
  for (std::uint16_t i = 0; i < 70; ++i) {
    const auto st = static_cast<std::uint16_t>(0x1001 + i);
    config_fmmu(line.segment, st, 0, 4u * i, 4, 0, 7, 0x1100, 0, 2);
  }
  std::array<std::uint8_t, 256> buf{};
  FrameBuilder b(buf);
  (void)b.append_zeros(Command::Lrw, 0, 4 * 30, 8);
  (void)b.append_zeros(Command::Fprd, 1, device_address(0x1002, reg::kAlStatus), 2);
  (void)b.append_zeros(Command::Aprd, 2, device_address(auto_increment_adp(65), reg::kAlStatus), 2);
  Bytes frame = b.finish();
  ASSERT_TRUE(line.segment.process_frame(frame, 0ns));  // warm-up
  {
    const ecat::test::AllocCounter counter;
    for (int i = 0; i < 100; ++i) {
      const Nanoseconds t{i == 50 ? 10 : i * 100'000};
      (void)line.segment.process_frame(frame, t);
      line[5].write(0x1100, std::span(buf).first(4));
    }
    EXPECT_EQ(counter.count(), 0u);
  }
  EXPECT_EQ(line[30].last_time(), Nanoseconds{99 * 100'000} + Segment::kDefaultHopDelay * 30);
}

}  // namespace
}  // namespace ecat::esc::test
