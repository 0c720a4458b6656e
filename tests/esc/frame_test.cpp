// Wire format: value types round-trip, parser bounds checks, builder.
#include <gtest/gtest.h>

#include <array>
#include <vector>

#include "common/frame.hpp"
#include "common/frame_builder.hpp"
#include "common/frame_parser.hpp"

namespace ecat {
namespace {

TEST(FrameHeader, EncodesLengthAndType) {
  FrameHeader h{0x01A, kFrameTypeDlpdu};
  std::array<std::uint8_t, 2> b{};
  ASSERT_TRUE(h.pack(b));
  EXPECT_EQ(b[0], 0x1A);
  EXPECT_EQ(b[1], 0x10);
  EXPECT_EQ(FrameHeader::unpack(b).value(), h);
}

TEST(DatagramHeader, RoundTripsSpecLayout) {
  // FPRD idx 0x42, ADP 0x1001, ADO 0x0130, len 2, more, circulating, IRQ 0x0008.
  std::array<std::uint8_t, 10> wire{0x04, 0x42, 0x01, 0x10, 0x30, 0x01, 0x02, 0xC0, 0x08, 0x00};
  auto h = DatagramHeader::unpack(wire);
  ASSERT_TRUE(h);
  EXPECT_EQ(h->command, Command::Fprd);
  EXPECT_EQ(h->index, 0x42);
  EXPECT_EQ(h->adp(), 0x1001);
  EXPECT_EQ(h->ado(), 0x0130);
  EXPECT_EQ(h->length, 2);
  EXPECT_TRUE(h->more);
  EXPECT_TRUE(h->circulating);
  EXPECT_EQ(h->irq, 0x0008);
  std::array<std::uint8_t, 10> out{};
  ASSERT_TRUE(h->pack(out));
  EXPECT_EQ(out, wire);
}

TEST(DatagramHeader, RejectsUnknownCommand) {
  std::array<std::uint8_t, 10> wire{0x0F, 0, 0, 0, 0, 0, 0, 0, 0, 0};
  EXPECT_EQ(DatagramHeader::unpack(wire).error(), FrameError::UnknownCommand);
}

TEST(EthernetHeader, ParsesVlanTag) {
  std::array<std::uint8_t, 18> wire{0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 1, 2, 3, 4, 5, 6,
                                    0x81, 0x00, 0x20, 0x05, 0x88, 0xA4};
  auto h = EthernetHeader::unpack(wire);
  ASSERT_TRUE(h);
  EXPECT_EQ(h->vlan_tci, 0x2005);
  EXPECT_EQ(h->ether_type, kEtherTypeEtherCat);
  EXPECT_EQ(h->size(), 18u);
  std::array<std::uint8_t, 18> out{};
  ASSERT_TRUE(h->pack(out));
  EXPECT_EQ(out, wire);
}

TEST(FrameBuilder, BuildsTwoDatagramsPaddedTo60) {
  std::array<std::uint8_t, 128> buf{};
  FrameBuilder b(buf, kBroadcastMac, MacAddress{0x02, 0, 0, 0, 0, 1});
  std::array<std::uint8_t, 2> data{0x02, 0x00};
  ASSERT_EQ(b.append(Command::Bwr, 1, device_address(0, 0x0120), data).value(), 16u);
  ASSERT_EQ(b.append_zeros(Command::Aprd, 2, device_address(auto_increment_adp(1), 0x0130), 2).value(), 30u);
  Bytes f = b.finish();
  ASSERT_EQ(f.size(), 60u);
  const std::vector<std::uint8_t> expect{
      0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x02, 0, 0, 0, 0, 1, 0x88, 0xA4,  // Ethernet
      0x1C, 0x10,                                                        // len 28, type 1
      0x08, 0x01, 0x00, 0x00, 0x20, 0x01, 0x02, 0x80, 0x00, 0x00, 0x02, 0x00, 0x00, 0x00,
      0x01, 0x02, 0xFF, 0xFF, 0x30, 0x01, 0x02, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0x00};
  EXPECT_EQ(std::vector<std::uint8_t>(f.begin(), f.begin() + 44), expect);
  auto v = parse_frame(f);
  ASSERT_TRUE(v);
  ASSERT_EQ(v->size(), 2u);
  EXPECT_EQ((*v)[0].command(), Command::Bwr);
  EXPECT_TRUE((*v)[0].more());
  EXPECT_EQ((*v)[1].adp(), 0xFFFF);
  EXPECT_FALSE((*v)[1].more());
  (*v)[1].add_wkc(3);
  EXPECT_EQ(f[42], 3);
}

TEST(FrameBuilder, RefusesWhatDoesNotFit) {
  std::array<std::uint8_t, 40> buf{};
  FrameBuilder b(buf);
  EXPECT_EQ(b.remaining_data_capacity(), 40u - 16u - 12u);
  EXPECT_EQ(b.append_zeros(Command::Brd, 0, 0, 13).error(), FrameError::BufferFull);
  EXPECT_TRUE(b.append_zeros(Command::Brd, 0, 0, 12));
  EXPECT_EQ(b.append_zeros(Command::Brd, 0, 0, 0).error(), FrameError::BufferFull);
}

std::vector<std::uint8_t> one_datagram_frame() {
  std::vector<std::uint8_t> buf(60);
  FrameBuilder b(buf);
  (void)b.append_zeros(Command::Brd, 0, 0, 4);
  auto f = b.finish();
  return {f.begin(), f.end()};
}

TEST(FrameParser, Rejects) {
  auto good = one_datagram_frame();
  ASSERT_TRUE(parse_frame(good));
  {
    auto f = good;
    f.resize(15);
    EXPECT_EQ(parse_frame(f).error(), FrameError::TooShort);
  }
  {
    auto f = good;
    f[13] = 0x00;  // EtherType 0x8800
    EXPECT_EQ(parse_frame(f).error(), FrameError::NotEtherCat);
  }
  {
    auto f = good;
    f[15] = 0x50;  // type 5
    EXPECT_EQ(parse_frame(f).error(), FrameError::UnsupportedType);
  }
  {
    auto f = good;
    f[14] = 0xFF;
    f[15] = 0x17;  // length 0x7FF
    EXPECT_EQ(parse_frame(f).error(), FrameError::LengthBeyondFrame);
  }
  {
    auto f = good;
    f[22] = 30;  // datagram length 30 > frame length
    EXPECT_EQ(parse_frame(f).error(), FrameError::DatagramBeyondFrame);
  }
  {
    auto f = good;
    f[23] = 0x80;  // "more" but nothing follows
    EXPECT_EQ(parse_frame(f).error(), FrameError::DatagramBeyondFrame);
  }
  {
    auto f = good;
    f[14] = static_cast<std::uint8_t>(f[14] + 2);  // 2 extra bytes inside the length
    EXPECT_EQ(parse_frame(f).error(), FrameError::LengthMismatch);
  }
  {
    auto f = good;
    f[16] = 15;
    EXPECT_EQ(parse_frame(f).error(), FrameError::UnknownCommand);
  }
}

// The single-datagram case of validate_ethercat is the general loop unrolled
// once: the same checks in the same order, also when several fail at once,
// and the loop itself for a second datagram.
TEST(FrameParser, ErrorPrecedenceOneAndTwoDatagrams) {
  auto good = one_datagram_frame();
  {
    auto f = good;
    f[16] = 15;  // unknown command and a length beyond the frame: the command is checked first
    f[22] = 30;
    EXPECT_EQ(parse_frame(f).error(), FrameError::UnknownCommand);
  }
  {
    auto f = good;
    f[22] = 30;  // beyond the frame and inside the frame length by 2: beyond first
    f[14] = static_cast<std::uint8_t>(f[14] + 2);
    EXPECT_EQ(parse_frame(f).error(), FrameError::DatagramBeyondFrame);
  }
  std::array<std::uint8_t, 128> buf{};
  FrameBuilder b(buf);
  ASSERT_TRUE(b.append_zeros(Command::Aprd, 0, 0, 3));
  ASSERT_TRUE(b.append_zeros(Command::Brd, 1, 0, 2));
  const auto two = b.finish();
  const std::vector<std::uint8_t> good2(two.begin(), two.end());
  {
    auto f = good2;
    ASSERT_TRUE(parse_frame(f));
    ASSERT_EQ(parse_frame(f)->size(), 2u);
  }
  constexpr std::size_t kSecond = 16 + 12 + 3;  // header of the second datagram
  {
    auto f = good2;
    f[kSecond] = 15;
    EXPECT_EQ(parse_frame(f).error(), FrameError::UnknownCommand);
  }
  {
    auto f = good2;
    f[kSecond + 6] = 9;  // second datagram 9 bytes long: beyond the frame
    EXPECT_EQ(parse_frame(f).error(), FrameError::DatagramBeyondFrame);
  }
  {
    auto f = good2;
    f[kSecond + 6] = 1;  // one byte shorter: the frame length has one byte left over
    EXPECT_EQ(parse_frame(f).error(), FrameError::LengthMismatch);
  }
  {
    auto f = good2;
    f[kSecond + 7] = 0x80;  // "more" on the last one
    EXPECT_EQ(parse_frame(f).error(), FrameError::DatagramBeyondFrame);
  }
}

TEST(FrameParser, WalksDatagramsInPlace) {
  std::array<std::uint8_t, 128> buf{};
  FrameBuilder b(buf);
  ASSERT_TRUE(b.append_zeros(Command::Aprd, 7, 0, 3));
  ASSERT_TRUE(b.append_zeros(Command::Lrw, 8, 0x10000, 5));
  ASSERT_TRUE(b.append_zeros(Command::Nop, 9, 0, 0));
  Bytes f = b.finish();
  auto v = parse_frame(f);
  ASSERT_TRUE(v);
  ASSERT_EQ(v->size(), 3u);
  // Ethernet 14 + frame header 2, then 12 + length per datagram.
  EXPECT_EQ(v->offset(0), 16u);
  EXPECT_EQ(v->offset(1), 16u + 12 + 3);
  EXPECT_EQ(v->offset(2), 16u + 12 + 3 + 12 + 5);
  std::vector<std::uint8_t> indices;
  std::size_t i = 0;
  for (DatagramView d : *v) {
    EXPECT_EQ(d, (*v)[i]);
    EXPECT_EQ(d.header_pointer(), f.data() + v->offset(i));
    indices.push_back(d.index());
    ++i;
  }
  EXPECT_EQ(indices, (std::vector<std::uint8_t>{7, 8, 9}));
  EXPECT_EQ((*v)[1].logical_address(), 0x10000u);
  EXPECT_EQ((*v)[2].length(), 0);
  // A view of nothing walks nothing.
  FrameView none;
  EXPECT_TRUE(none.begin() == none.end());
}

TEST(FrameParser, LocatesTheEtherCatHeader) {
  auto plain = one_datagram_frame();
  EXPECT_EQ(locate_ethercat(plain).value(), 14u);
  std::vector<std::uint8_t> tagged(plain.begin(), plain.begin() + 12);
  for (const int b : {0x81, 0x00, 0x20, 0x05}) tagged.push_back(static_cast<std::uint8_t>(b));  // 802.1Q, TCI 0x2005
  tagged.insert(tagged.end(), plain.begin() + 12, plain.end());
  EXPECT_EQ(locate_ethercat(tagged).value(), 18u);
  ASSERT_TRUE(parse_frame(tagged));
  EXPECT_EQ(parse_frame(tagged)->ethercat_offset(), 18u);
  tagged.resize(17);
  EXPECT_EQ(locate_ethercat(tagged).error(), FrameError::TooShort);
  plain[12] = 0x08;  // EtherType 0x08A4
  EXPECT_EQ(locate_ethercat(plain).error(), FrameError::NotEtherCat);
  plain.resize(13);
  EXPECT_EQ(locate_ethercat(plain).error(), FrameError::TooShort);
}

TEST(FrameParser, AcceptsShortUnpaddedFrame) {
  auto f = one_datagram_frame();
  f.resize(14 + 2 + 16);
  auto v = parse_frame(f);
  ASSERT_TRUE(v);
  EXPECT_EQ((*v)[0].length(), 4);
}

}  // namespace
}  // namespace ecat
