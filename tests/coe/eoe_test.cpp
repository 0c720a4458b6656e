// EoE (ETG.1000.6 §5.7): fragment reassembly and fragmentation with exact
// header bytes, IP parameters, the built-in ARP/ICMP responder, fair turns
// with CoE replies, and mailbox error 2 on a device without EoE.
#include "coe/eoe_server.hpp"

#include <gtest/gtest.h>

#include "coe/coe_server.hpp"
#include "coe/eoe_responder.hpp"
#include "tests/coe/rig.hpp"
#include "tests/support/alloc_counter.hpp"

namespace ecat::coe {
namespace {

using test::Frame;
using test::mbx;

constexpr std::uint8_t kEoe = 2;

struct CapturePort final : EthernetPort {
  void receive(ConstBytes frame) noexcept override { frames.emplace_back(frame.begin(), frame.end()); }
  std::vector<Frame> frames;
};

Frame eoe_header(std::uint16_t w0, std::uint16_t w1, const Frame& data = {}) {
  return test::concat({static_cast<std::uint8_t>(w0), static_cast<std::uint8_t>(w0 >> 8),
                       static_cast<std::uint8_t>(w1), static_cast<std::uint8_t>(w1 >> 8)},
                      data);
}

Frame pattern(std::size_t n) {
  Frame f(n);
  for (std::size_t i = 0; i < n; ++i) f[i] = static_cast<std::uint8_t>(i * 7 + 3);
  return f;
}

Frame slice(const Frame& f, std::size_t from, std::size_t n) {
  return Frame(f.begin() + static_cast<std::ptrdiff_t>(from), f.begin() + static_cast<std::ptrdiff_t>(from + n));
}

class EoeTest : public ::testing::Test {
 protected:
  void SetUp() override {
    eoe.set_port(&capture);
    rig.mailbox.add_service(eoe);
  }
  // Sends one EoE payload; returns the reply frame if SM1 got one.
  std::optional<Frame> send(const Frame& payload) {
    counter = MailboxHeader::next_counter(counter);
    return rig.request(mbx(kEoe, counter, payload));
  }
  Frame payload_of(const Frame& reply) { return Frame(reply.begin() + 6, reply.end()); }

  test::Rig rig;
  EoeServer eoe;
  CapturePort capture;
  std::uint8_t counter = 0;
};

// 1500 bytes over a 128-byte mailbox: 118 bytes of room after the mailbox
// and EoE headers, so 96 per fragment (3 blocks of 32): 15 x 96 + 60.
TEST_F(EoeTest, FrameFromTheMasterIn128ByteMailboxFragments) {
  const Frame frame = pattern(1500);
  constexpr std::size_t kChunk = 96;
  for (std::size_t k = 0; k < 16; ++k) {
    const bool last = k == 15;
    const std::size_t n = last ? 60 : kChunk;
    // Fragment 0 carries the complete size: ceil(1500 / 32) = 47 blocks.
    const std::uint16_t offset = k == 0 ? 47 : static_cast<std::uint16_t>(k * 3);
    const std::uint16_t w0 = last ? 0x0100 : 0x0000;
    const std::uint16_t w1 = static_cast<std::uint16_t>(k | offset << 6 | 5u << 12);  // frame number 5
    const Frame payload = eoe_header(w0, w1, slice(frame, k * kChunk, n));
    if (k == 0) {
      EXPECT_EQ(slice(payload, 0, 4), (Frame{0x00, 0x00, 0xC0, 0x5B}));
    }
    if (k == 1) {
      EXPECT_EQ(slice(payload, 0, 4), (Frame{0x00, 0x00, 0xC1, 0x50}));
    }
    if (last) {
      EXPECT_EQ(slice(payload, 0, 4), (Frame{0x00, 0x01, 0x4F, 0x5B}));
    }
    EXPECT_FALSE(send(payload)) << "fragment " << k << " got a reply";
    EXPECT_EQ(capture.frames.size(), last ? 1u : 0u);
  }
  ASSERT_EQ(capture.frames.size(), 1u);
  EXPECT_EQ(capture.frames[0], frame);
  EXPECT_EQ(eoe.stats().frames_received, 1u);
  EXPECT_EQ(eoe.stats().fragments_received, 16u);
  EXPECT_EQ(eoe.stats().dropped_sequence + eoe.stats().dropped_oversize, 0u);
}

TEST_F(EoeTest, FrameToTheMasterIn128ByteMailboxFragments) {
  const Frame frame = pattern(1500);
  ASSERT_TRUE(eoe.transmit(frame));
  rig.mailbox.poll(Nanoseconds{0});
  Frame back;
  std::uint8_t expect_counter = 0;
  for (std::size_t k = 0; k < 16; ++k) {
    auto got = rig.fetch();
    ASSERT_TRUE(got) << "fragment " << k;
    const bool last = k == 15;
    const std::size_t n = last ? 60 : 96;
    expect_counter = MailboxHeader::next_counter(expect_counter);
    // Mailbox header: length 4 + n, address 0, channel 0 priority 0, type 2 + counter.
    EXPECT_EQ(slice(*got, 0, 6), (Frame{static_cast<std::uint8_t>(4 + n), 0, 0, 0, 0,
                                        static_cast<std::uint8_t>(kEoe | expect_counter << 4)}));
    const std::uint16_t offset = k == 0 ? 47 : static_cast<std::uint16_t>(k * 3);
    const std::uint16_t w1 = static_cast<std::uint16_t>(k | offset << 6 | 1u << 12);  // first frame: number 1
    EXPECT_EQ(slice(*got, 6, 4), eoe_header(last ? 0x0100 : 0x0000, w1)) << "fragment " << k;
    const Frame data = slice(*got, 10, got->size() - 10);
    back.insert(back.end(), data.begin(), data.end());
  }
  EXPECT_FALSE(rig.fetch());
  EXPECT_EQ(back, frame);
  EXPECT_EQ(eoe.stats().frames_sent, 1u);
  EXPECT_EQ(eoe.stats().fragments_sent, 16u);
  // The next frame gets frame number 2; a small one is one last fragment of
  // ceil(60/32) = 2 blocks: 00 01 80 20.
  ASSERT_TRUE(eoe.transmit(pattern(60)));
  rig.mailbox.poll(Nanoseconds{0});
  auto one = rig.fetch();
  ASSERT_TRUE(one);
  EXPECT_EQ(slice(*one, 6, 4), (Frame{0x00, 0x01, 0x80, 0x20}));
}

TEST_F(EoeTest, OutOfOrderAndLostFragmentsAreCountedDropsAndCoeGoesOn) {
  const Frame frame = pattern(200);  // 96 + 96 + 8
  auto frag = [&](std::uint8_t k, std::uint8_t frame_no, bool last, std::size_t from, std::size_t n,
                  std::uint16_t offset) {
    return eoe_header(last ? 0x0100 : 0, static_cast<std::uint16_t>(k | offset << 6 | frame_no << 12),
                      slice(frame, from, n));
  };
  // Fragment 1 lost: fragment 2 arrives out of sequence.
  EXPECT_FALSE(send(frag(0, 1, false, 0, 96, 7)));
  EXPECT_FALSE(send(frag(2, 1, true, 192, 8, 6)));
  EXPECT_EQ(eoe.stats().dropped_sequence, 1u);
  // The late fragment 1 belongs to the dropped frame: dropped too.
  EXPECT_FALSE(send(frag(1, 1, false, 96, 96, 3)));
  EXPECT_EQ(eoe.stats().dropped_sequence, 2u);
  // Wrong frame number in the middle of a frame.
  EXPECT_FALSE(send(frag(0, 2, false, 0, 96, 7)));
  EXPECT_FALSE(send(frag(1, 3, false, 96, 96, 3)));
  EXPECT_EQ(eoe.stats().dropped_sequence, 3u);
  // Wrong offset.
  EXPECT_FALSE(send(frag(0, 4, false, 0, 96, 7)));
  EXPECT_FALSE(send(frag(1, 4, false, 96, 96, 4)));
  EXPECT_EQ(eoe.stats().dropped_sequence, 4u);
  // Last fragment lost: the next frame's fragment 0 drops the old one.
  EXPECT_FALSE(send(frag(0, 5, false, 0, 96, 7)));
  EXPECT_FALSE(send(frag(1, 5, false, 96, 96, 3)));
  EXPECT_FALSE(send(frag(0, 6, false, 0, 96, 7)));
  EXPECT_EQ(eoe.stats().dropped_sequence, 5u);
  EXPECT_FALSE(send(frag(1, 6, false, 96, 96, 3)));
  EXPECT_FALSE(send(frag(2, 6, true, 192, 8, 6)));
  ASSERT_EQ(capture.frames.size(), 1u);
  EXPECT_EQ(capture.frames[0], frame);
  // Oversize: an announced 63 blocks (2016 bytes) exceed the 1536-byte
  // buffer; data past the announced size (1 block) is dropped.
  EXPECT_FALSE(send(eoe_header(0x0100, 63u << 6 | 7u << 12, pattern(40))));
  EXPECT_FALSE(send(eoe_header(0x0100, 1u << 6 | 8u << 12, pattern(40))));
  EXPECT_EQ(eoe.stats().dropped_oversize, 2u);
  EXPECT_EQ(capture.frames.size(), 1u);
  // Too short for a mailbox EoE header: mailbox error 6 (size too short).
  counter = MailboxHeader::next_counter(counter);
  auto err = rig.request(mbx(kEoe, counter, Frame{0x00, 0x00}));
  ASSERT_TRUE(err);
  EXPECT_EQ(payload_of(*err), (Frame{0x01, 0x00, 0x06, 0x00}));
  // CoE traffic is unaffected: 1018h:01 vendor ID still uploads.
  rig.counter = counter;  // one counter sequence for both protocols
  const Frame sdo = rig.sdo_request(test::sdo(0x40, 0x1018, 1));
  ASSERT_GE(sdo.size(), 3u);
  EXPECT_EQ(sdo[2], 0x43);
}

TEST_F(EoeTest, TimestampAppendedToTheLastFragmentIsNotPartOfTheFrame) {
  Frame data = pattern(60);
  const Frame stamp{0x11, 0x22, 0x33, 0x44};
  data.insert(data.end(), stamp.begin(), stamp.end());
  EXPECT_FALSE(send(eoe_header(0x0300, 2u << 6 | 1u << 12, data)));  // last + time appended
  ASSERT_EQ(capture.frames.size(), 1u);
  EXPECT_EQ(capture.frames[0], pattern(60));
}

TEST_F(EoeTest, SetIpParameterEveryFieldThenGetIpParameter) {
  Frame req = eoe_header(0x0002, 0x0000,
                         {0x3F, 0x00, 0x00, 0x00,                // flags: all six
                          0x02, 0x11, 0x22, 0x33, 0x44, 0x55,    // MAC
                          0x02, 0x0A, 0xA8, 0xC0,                // 192.168.10.2, UINT32 LE
                          0x00, 0xFF, 0xFF, 0xFF,                // 255.255.255.0
                          0x01, 0x0A, 0xA8, 0xC0,                // gateway 192.168.10.1
                          0x08, 0x08, 0x08, 0x08});              // DNS 8.8.8.8
  Frame name(32, 0);
  const std::string n = "drive-7";
  std::copy(n.begin(), n.end(), name.begin());
  req.insert(req.end(), name.begin(), name.end());
  ASSERT_EQ(req.size(), 62u);  // as SOEM and TwinCAT send it
  auto reply = send(req);
  ASSERT_TRUE(reply);
  EXPECT_EQ(slice(*reply, 0, 6), (Frame{0x04, 0x00, 0x00, 0x00, 0x00, static_cast<std::uint8_t>(kEoe | counter << 4)}));
  EXPECT_EQ(payload_of(*reply), (Frame{0x03, 0x00, 0x00, 0x00}));  // Set IP response, success
  const auto& p = eoe.ip_parameters();
  EXPECT_EQ(p.flags, 0x3Fu);
  EXPECT_EQ(p.mac, (eoe::Mac{0x02, 0x11, 0x22, 0x33, 0x44, 0x55}));
  EXPECT_EQ(p.ip, 0xC0A80A02u);
  EXPECT_EQ(p.subnet, 0xFFFFFF00u);
  EXPECT_EQ(p.gateway, 0xC0A80A01u);
  EXPECT_EQ(p.dns_server, 0x08080808u);
  EXPECT_STREQ(p.dns_name.data(), "drive-7");

  auto got = send(eoe_header(0x0006, 0x0000));
  ASSERT_TRUE(got);
  Frame expect = eoe_header(0x0007, 0x0000, slice(req, 4, 58));
  EXPECT_EQ(payload_of(*got), expect);

  // Only the IP: the other fields stay.
  auto only_ip = send(eoe_header(0x0002, 0, {0x02, 0, 0, 0, 0x09, 0x0A, 0xA8, 0xC0}));
  ASSERT_TRUE(only_ip);
  EXPECT_EQ(payload_of(*only_ip), (Frame{0x03, 0x00, 0x00, 0x00}));
  EXPECT_EQ(eoe.ip_parameters().ip, 0xC0A80A09u);
  EXPECT_EQ(eoe.ip_parameters().subnet, 0xFFFFFF00u);
}

// SOEM 2.x writes every field at its fixed place and flags only the valid
// ones ("TwinCAT include empty entries"); SOES and older SOEM pack the
// flagged ones. A request as long as every field together (58 bytes after
// the EoE header) is read at the fixed places.
TEST_F(EoeTest, SetIpParameterWithEveryFieldAtItsFixedPlace) {
  Frame body = {0x06, 0x00, 0x00, 0x00,                // flags: IP and subnet only
                0x00, 0x00, 0x00, 0x00, 0x00, 0x00,    // MAC (empty, not flagged)
                0x07, 0x0A, 0xA8, 0xC0,                // 192.168.10.7
                0x00, 0xFF, 0xFF, 0xFF,                // 255.255.255.0
                0x00, 0x00, 0x00, 0x00,                // gateway (empty)
                0x00, 0x00, 0x00, 0x00};               // DNS server (empty)
  body.resize(58, 0);                                   // DNS name (empty)
  auto reply = send(eoe_header(0x0002, 0x0000, body));
  ASSERT_TRUE(reply);
  EXPECT_EQ(payload_of(*reply), (Frame{0x03, 0x00, 0x00, 0x00}));
  const auto& p = eoe.ip_parameters();
  EXPECT_EQ(p.flags, 0x06u);
  EXPECT_EQ(p.ip, 0xC0A80A07u);  // packed, the IP would have been read from the MAC's bytes
  EXPECT_EQ(p.subnet, 0xFFFFFF00u);
  EXPECT_EQ(p.mac, eoe::Mac{});
  EXPECT_EQ(p.gateway, 0u);
  // The same two fields packed (12 bytes): the same result.
  auto packed = send(eoe_header(0x0002, 0, {0x06, 0, 0, 0, 0x08, 0x0A, 0xA8, 0xC0, 0x00, 0x00, 0xFF, 0xFF}));
  ASSERT_TRUE(packed);
  EXPECT_EQ(payload_of(*packed), (Frame{0x03, 0x00, 0x00, 0x00}));
  EXPECT_EQ(eoe.ip_parameters().ip, 0xC0A80A08u);
  EXPECT_EQ(eoe.ip_parameters().subnet, 0xFFFF0000u);
}

TEST_F(EoeTest, BadAndUnsupportedRequestsGetTheirResultCodes) {
  // IP flag but no address: unspecified error 0x0001, nothing changed.
  auto r = send(eoe_header(0x0002, 0, {0x02, 0, 0, 0, 0x01}));
  ASSERT_TRUE(r);
  EXPECT_EQ(payload_of(*r), (Frame{0x03, 0x00, 0x01, 0x00}));
  EXPECT_EQ(eoe.ip_parameters().flags, 0u);
  // A response type from the master: unsupported frame type 0x0002.
  r = send(eoe_header(0x0001, 0));
  ASSERT_TRUE(r);
  EXPECT_EQ(payload_of(*r), (Frame{0x03, 0x00, 0x02, 0x00}));
  EXPECT_EQ(eoe.stats().bad_requests, 2u);
}

TEST_F(EoeTest, SetAddressFilterThenGetItAndItFiltersFramesToTheMaster) {
  // One filter, no masks, no broadcasts (options 0x0081).
  const Frame filter{0x02, 0xAA, 0xBB, 0xCC, 0xDD, 0xEE};
  auto r = send(eoe_header(0x0004, 0, test::concat({0x81, 0x00}, filter)));
  ASSERT_TRUE(r);
  EXPECT_EQ(payload_of(*r), (Frame{0x05, 0x00, 0x00, 0x00}));
  r = send(eoe_header(0x0008, 0));
  ASSERT_TRUE(r);
  EXPECT_EQ(payload_of(*r), eoe_header(0x0009, 0, test::concat({0x81, 0x00}, filter)));
  Frame to_filter = pattern(60);
  std::copy(filter.begin(), filter.end(), to_filter.begin());
  Frame broadcast = pattern(60);
  std::fill(broadcast.begin(), broadcast.begin() + 6, 0xFF);
  Frame other = pattern(60);
  EXPECT_TRUE(eoe.transmit(to_filter));
  EXPECT_FALSE(eoe.transmit(broadcast));
  EXPECT_FALSE(eoe.transmit(other));
  EXPECT_EQ(eoe.stats().dropped_filtered, 2u);
}

// The frame buffers come with the first frame, once: a slave whose master
// never uses EoE does not carry them (docs/performance-log.md, "Session 14").
TEST_F(EoeTest, FrameBuffersAreAllocatedOnceOnTheFirstFrame) {
  const Frame f = pattern(60);
  std::size_t first = 0;
  std::size_t later = 0;
  {
    ecat::test::AllocCounter allocs;
    EXPECT_TRUE(eoe.transmit(f));
    first = allocs.count();
  }
  {
    ecat::test::AllocCounter allocs;
    EXPECT_TRUE(eoe.transmit(f));
    EXPECT_TRUE(eoe.transmit(f));
    later = allocs.count();
  }
  EXPECT_EQ(first, 1u);
  EXPECT_EQ(later, 0u);
  EXPECT_EQ(eoe.tx_waiting(), 3u);
  EXPECT_EQ(eoe.stats().dropped_no_memory, 0u);
}

// Responder: 192.168.10.2 at 02:00:00:00:00:01; the master 192.168.10.1 at 02:AA:BB:CC:DD:EE.
class ResponderTest : public EoeTest {
 protected:
  void SetUp() override {
    eoe.set_port(&responder);
    rig.mailbox.add_service(eoe);
    eoe::IpParameters p;
    p.flags = eoe::kHasMac | eoe::kHasIp;
    p.mac = {0x02, 0x00, 0x00, 0x00, 0x00, 0x01};
    p.ip = 0xC0A80A02;
    eoe.set_ip_parameters(p);
  }
  // A frame of <= 118 bytes in one fragment; returns the reply frame's EoE payload.
  std::optional<Frame> exchange(const Frame& frame) {
    const std::uint16_t blocks = static_cast<std::uint16_t>((frame.size() + 31) / 32);
    auto reply = send(eoe_header(0x0100, static_cast<std::uint16_t>(blocks << 6 | 1u << 12), frame));
    if (!reply) return std::nullopt;
    return payload_of(*reply);
  }
  EoeResponder responder{eoe};
};

TEST_F(ResponderTest, AnswersArpForItsAddress) {
  Frame arp{0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x02, 0xAA, 0xBB, 0xCC, 0xDD, 0xEE, 0x08, 0x06,
            0x00, 0x01, 0x08, 0x00, 0x06, 0x04, 0x00, 0x01,
            0x02, 0xAA, 0xBB, 0xCC, 0xDD, 0xEE, 0xC0, 0xA8, 0x0A, 0x01,
            0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xC0, 0xA8, 0x0A, 0x02};
  arp.resize(60, 0);  // minimum Ethernet frame
  auto got = exchange(arp);
  ASSERT_TRUE(got);
  Frame expect{0x02, 0xAA, 0xBB, 0xCC, 0xDD, 0xEE, 0x02, 0x00, 0x00, 0x00, 0x00, 0x01, 0x08, 0x06,
               0x00, 0x01, 0x08, 0x00, 0x06, 0x04, 0x00, 0x02,
               0x02, 0x00, 0x00, 0x00, 0x00, 0x01, 0xC0, 0xA8, 0x0A, 0x02,
               0x02, 0xAA, 0xBB, 0xCC, 0xDD, 0xEE, 0xC0, 0xA8, 0x0A, 0x01};
  expect.resize(60, 0);
  // One last fragment of 2 blocks, frame number 1: 00 01 80 10.
  EXPECT_EQ(*got, eoe_header(0x0100, 0x1080, expect));
  EXPECT_EQ(responder.stats().arp_replies, 1u);
  // For another address: no answer.
  arp[41] = 0x03;
  EXPECT_FALSE(exchange(arp));
  EXPECT_EQ(responder.stats().ignored, 1u);
}

// The reply buffer comes with the first reply, once; the frame from the
// master is already in the server's buffers (given directly here).
TEST_F(ResponderTest, ReplyBufferIsAllocatedOnceOnTheFirstReply) {
  Frame arp{0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0xFF, 0x02, 0xAA, 0xBB, 0xCC, 0xDD, 0xEE, 0x08, 0x06,
            0x00, 0x01, 0x08, 0x00, 0x06, 0x04, 0x00, 0x01,
            0x02, 0xAA, 0xBB, 0xCC, 0xDD, 0xEE, 0xC0, 0xA8, 0x0A, 0x01,
            0x00, 0x00, 0x00, 0x00, 0x00, 0x00, 0xC0, 0xA8, 0x0A, 0x02};
  arp.resize(60, 0);
  std::size_t first = 0;
  std::size_t later = 0;
  {
    ecat::test::AllocCounter allocs;
    responder.receive(arp);
    first = allocs.count();
  }
  {
    ecat::test::AllocCounter allocs;
    responder.receive(arp);
    later = allocs.count();
  }
  EXPECT_EQ(first, 2u);  // the responder's reply buffer and the server's frame buffers
  EXPECT_EQ(later, 0u);
  EXPECT_EQ(responder.stats().arp_replies, 2u);
  EXPECT_EQ(responder.stats().no_memory, 0u);
  EXPECT_EQ(eoe.tx_waiting(), 2u);
}

TEST_F(ResponderTest, AnswersPingWithCorrectChecksums) {
  // Echo request id 0x1234 seq 1, 16 data bytes, TTL 128; checksums by RFC 1071.
  const Frame ping{0x02, 0x00, 0x00, 0x00, 0x00, 0x01, 0x02, 0xAA, 0xBB, 0xCC, 0xDD, 0xEE, 0x08, 0x00, 0x45,
                   0x00, 0x00, 0x2C, 0xAB, 0xCD, 0x40, 0x00, 0x80, 0x01, 0xB9, 0xAF, 0xC0, 0xA8, 0x0A, 0x01,
                   0xC0, 0xA8, 0x0A, 0x02, 0x08, 0x00, 0x2D, 0x0A, 0x12, 0x34, 0x00, 0x01, 0x10, 0x11, 0x12,
                   0x13, 0x14, 0x15, 0x16, 0x17, 0x18, 0x19, 0x1A, 0x1B, 0x1C, 0x1D, 0x1E, 0x1F};
  const Frame pong{0x02, 0xAA, 0xBB, 0xCC, 0xDD, 0xEE, 0x02, 0x00, 0x00, 0x00, 0x00, 0x01, 0x08, 0x00, 0x45,
                   0x00, 0x00, 0x2C, 0xAB, 0xCD, 0x40, 0x00, 0x40, 0x01, 0xF9, 0xAF, 0xC0, 0xA8, 0x0A, 0x02,
                   0xC0, 0xA8, 0x0A, 0x01, 0x00, 0x00, 0x35, 0x0A, 0x12, 0x34, 0x00, 0x01, 0x10, 0x11, 0x12,
                   0x13, 0x14, 0x15, 0x16, 0x17, 0x18, 0x19, 0x1A, 0x1B, 0x1C, 0x1D, 0x1E, 0x1F};
  auto got = exchange(ping);
  ASSERT_TRUE(got);
  EXPECT_EQ(*got, eoe_header(0x0100, 0x1080, pong));
  EXPECT_EQ(responder.stats().echo_replies, 1u);
  // A broken IP header checksum: counted, not answered.
  Frame bad = ping;
  bad[25] ^= 0x01;
  EXPECT_FALSE(exchange(bad));
  EXPECT_EQ(responder.stats().bad_checksum, 1u);
}

// EoE fragments and CoE replies take turns: a CoE reply waits behind at most
// one fragment of a long frame.
TEST_F(EoeTest, FragmentsToTheMasterTakeTurnsWithCoeReplies) {
  ASSERT_TRUE(eoe.transmit(pattern(1500)));
  ASSERT_TRUE(eoe.transmit(pattern(1500)));
  rig.mailbox.poll(Nanoseconds{0});
  auto first = rig.fetch();  // fragment 0 of frame 1
  ASSERT_TRUE(first);
  EXPECT_EQ((*first)[5] & 0x0F, kEoe);
  // SM1 now holds fragment 1; the SDO request arrives.
  rig.counter = MailboxHeader::next_counter(rig.counter);
  EXPECT_TRUE(rig.esc.master_write(mbx(3, rig.counter, test::sdo(0x40, 0x1018, 1))));
  rig.mailbox.poll(Nanoseconds{0});
  auto second = rig.fetch();
  ASSERT_TRUE(second);
  EXPECT_EQ((*second)[5] & 0x0F, kEoe);  // fragment 1, written before the request came
  auto third = rig.fetch();
  ASSERT_TRUE(third);
  EXPECT_EQ((*third)[5] & 0x0F, 3) << "the SDO reply waited behind more than one fragment";
  EXPECT_EQ((*third)[8], 0x43);
  std::size_t fragments = 2;
  while (auto f = rig.fetch()) {
    EXPECT_EQ((*f)[5] & 0x0F, kEoe);
    ++fragments;
  }
  EXPECT_EQ(fragments, 32u);
  EXPECT_EQ(eoe.stats().frames_sent, 2u);
}

// Four frames wait at most; the fifth is a counted drop, nothing blocks.
TEST_F(EoeTest, FullTransmitRingIsACountedDrop) {
  for (int i = 0; i < 4; ++i) EXPECT_TRUE(eoe.transmit(pattern(100)));
  EXPECT_FALSE(eoe.transmit(pattern(100)));
  EXPECT_EQ(eoe.stats().dropped_tx_full, 1u);
  EXPECT_FALSE(eoe.transmit(pattern(10)));  // shorter than an Ethernet header
  EXPECT_EQ(eoe.stats().dropped_short, 1u);
}

TEST(EoeAnnouncement, DeviceWithoutEoeAnswersMailboxErrorUnsupportedProtocol) {
  test::Rig rig;  // CoE only
  auto reply = rig.request(mbx(kEoe, 1, eoe_header(0x0006, 0)));
  ASSERT_TRUE(reply);
  EXPECT_EQ(*reply, (Frame{0x04, 0x00, 0x00, 0x00, 0x00, 0x10, 0x01, 0x00, 0x02, 0x00}));
}

TEST(EoeAnnouncement, CoeServerServesEoeOnlyWhenTheDeviceListsIt) {
  for (const bool listed : {false, true}) {
    test::FakeEsc esc;
    esc.configure_mailboxes(test::kSm0, test::kMbxLen, test::kSm1, test::kMbxLen);
    od::DeviceDescription device = test::make_device();
    device.mailbox.eoe = listed;
    CoeServer coe(esc, device);
    EXPECT_TRUE(esc.master_write(mbx(kEoe, 1, eoe_header(0x0006, 0))));
    coe.poll(Nanoseconds{0});
    auto raw = esc.master_read();
    ASSERT_TRUE(raw);
    if (!listed) {
      EXPECT_EQ(Frame(raw->begin() + 5, raw->begin() + 10), (Frame{0x10, 0x01, 0x00, 0x02, 0x00}));
    } else {
      // Get IP response, success, only the default MAC: flags 01, 02 00 00 00 00 01.
      EXPECT_EQ(Frame(raw->begin(), raw->begin() + 20),
                (Frame{0x0E, 0x00, 0x00, 0x00, 0x00, 0x12, 0x07, 0x00, 0x00, 0x00, 0x01, 0x00, 0x00, 0x00, 0x02,
                       0x00, 0x00, 0x00, 0x00, 0x01}));
    }
  }
}

}  // namespace
}  // namespace ecat::coe
