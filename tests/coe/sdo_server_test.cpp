#include <gtest/gtest.h>

#include <thread>

#include "tests/coe/rig.hpp"

namespace ecat::coe {
namespace {

using test::Frame;
using test::sdo;
using test::segment;

std::uint32_t abort_code(const Frame& reply) {
  EXPECT_EQ(reply.size(), 10u);
  if (reply.size() < 10) return 0;
  EXPECT_EQ(reply[1], 0x20);  // CoE service 2 (SDO request) carries aborts
  EXPECT_EQ(reply[2], 0x80);
  return static_cast<std::uint32_t>(reply[6] | (reply[7] << 8) | (reply[8] << 16) | (reply[9] << 24));
}

class SdoServerTest : public ::testing::Test {
 protected:
  Frame request(const Frame& payload) { return rig.sdo_request(payload); }
  test::Rig rig;
};

TEST_F(SdoServerTest, ExpeditedDownloadAndUploadByteExact) {
  EXPECT_EQ(request(sdo(0x2B, 0x2000, 0, 0xFFC4)), (Frame{0x00, 0x30, 0x60, 0x00, 0x20, 0x00, 0, 0, 0, 0}));
  EXPECT_EQ(rig.store.get<std::int16_t>(0x2000, 0), -60);
  EXPECT_EQ(request(sdo(0x40, 0x2000, 0)), (Frame{0x00, 0x30, 0x4B, 0x00, 0x20, 0x00, 0xC4, 0xFF, 0, 0}));
  EXPECT_EQ(request(sdo(0x40, 0x1001, 0)), (Frame{0x00, 0x30, 0x4F, 0x01, 0x10, 0x00, 0, 0, 0, 0}));
  // Size not indicated (0x22): the entry's own size is taken.
  EXPECT_EQ(request(sdo(0x22, 0x2000, 0, 0x0011))[2], 0x60);
  EXPECT_EQ(rig.store.get<std::int16_t>(0x2000, 0), 17);
}

TEST_F(SdoServerTest, NormalUploadOfAString) {
  EXPECT_EQ(request(sdo(0x40, 0x1008, 0)),
            (Frame{0x00, 0x30, 0x41, 0x08, 0x10, 0x00, 9, 0, 0, 0, 'e', 'c', 'a', 't', ' ', 't', 'e', 's', 't'}));
}

TEST_F(SdoServerTest, NormalDownloadInOneFrame) {
  EXPECT_EQ(request(sdo(0x21, 0x2002, 0, 5, {1, 2, 3, 4, 5}))[2], 0x60);
  const auto v = rig.store.value(0x2002, 0);
  EXPECT_EQ(Frame(v.begin(), v.end()), (Frame{1, 2, 3, 4, 5}));
  // More data than the complete size announces.
  EXPECT_EQ(abort_code(request(sdo(0x21, 0x2002, 0, 2, {1, 2, 3}))), 0x06070010u);
}

Frame pattern(std::size_t n) {
  Frame f(n);
  for (std::size_t i = 0; i < n; ++i) f[i] = static_cast<std::uint8_t>(i * 7 + i / 256);
  return f;
}

// Downloads `data` to 0x2002 as SOEM does: a normal initiate with as much as
// fits, then segments of up to 128 - 6 - 3 bytes, toggling from 0.
Frame segmented_download(test::Rig& rig, const Frame& data, int break_toggle_at = -1, std::uint8_t initiate = 0x21) {
  const std::size_t first = std::min<std::size_t>(data.size(), test::kMbxLen - 6 - 10);
  Frame init = sdo(initiate, 0x2002, 0, static_cast<std::uint32_t>(data.size()), Frame(data.begin(), data.begin() + first));
  Frame reply = rig.sdo_request(init);
  if (reply.size() < 3 || reply[2] != 0x60) return reply;
  std::size_t offset = first;
  bool toggle = false;
  int n = 0;
  while (offset < data.size()) {
    const std::size_t chunk = std::min<std::size_t>(data.size() - offset, test::kMbxLen - 6 - 3);
    const bool last = offset + chunk == data.size();
    std::uint8_t cmd = static_cast<std::uint8_t>((toggle ? 0x10 : 0) | (last ? 1 : 0));
    if (n == break_toggle_at) cmd ^= 0x10;
    if (chunk < 7) cmd |= static_cast<std::uint8_t>((7 - chunk) << 1);
    reply = rig.sdo_request(segment(cmd, Frame(data.begin() + offset, data.begin() + offset + chunk)));
    if (reply[2] == 0x80) return reply;
    EXPECT_EQ(reply, (Frame{0x00, 0x30, static_cast<std::uint8_t>(0x20 | (toggle ? 0x10 : 0)), 0, 0, 0, 0, 0, 0, 0}));
    offset += chunk;
    toggle = !toggle;
    ++n;
  }
  return reply;
}

Frame segmented_upload(test::Rig& rig, std::uint16_t index, std::uint8_t sub, std::uint8_t ca = 0,
                       int break_toggle_at = -1) {
  Frame reply = rig.sdo_request(sdo(static_cast<std::uint8_t>(0x40 | ca), index, sub));
  if (reply[2] == 0x80) return reply;
  if ((reply[2] & 0x02) != 0) {  // expedited
    return Frame(reply.begin() + 6, reply.begin() + 6 + (4 - ((reply[2] >> 2) & 3)));
  }
  const std::size_t size = reply[6] | (reply[7] << 8) | (reply[8] << 16) | (static_cast<std::size_t>(reply[9]) << 24);
  Frame data(reply.begin() + 10, reply.end());
  bool toggle = false;
  int n = 0;
  while (data.size() < size) {
    std::uint8_t cmd = static_cast<std::uint8_t>(0x60 | (toggle ? 0x10 : 0));
    if (n == break_toggle_at) cmd ^= 0x10;
    reply = rig.sdo_request(sdo(cmd, 0, 0));
    if (reply[2] == 0x80) return reply;
    EXPECT_EQ(reply[2] & 0x10, toggle ? 0x10 : 0);
    const std::size_t carried = reply.size() - 3 - ((reply[2] >> 1) & 7);
    data.insert(data.end(), reply.begin() + 3, reply.begin() + 3 + static_cast<std::ptrdiff_t>(carried));
    if (reply[2] & 1) break;
    toggle = !toggle;
    ++n;
  }
  EXPECT_EQ(data.size(), size);
  return data;
}

TEST_F(SdoServerTest, SegmentedDownloadAndUploadOf64KiB) {
  const Frame data = pattern(65536);
  Frame last = segmented_download(rig, data);
  ASSERT_EQ(last.size(), 10u);
  const auto stored = rig.store.value(0x2002, 0);
  ASSERT_EQ(stored.size(), data.size());
  EXPECT_TRUE(std::equal(stored.begin(), stored.end(), data.begin()));
  EXPECT_EQ(segmented_upload(rig, 0x2002, 0), data);
}

TEST_F(SdoServerTest, ShortLastSegmentIsPaddedToSeven) {
  const Frame data = pattern(112 + 3);  // 112 in the first frame, 3 in the segment
  segmented_download(rig, data);
  EXPECT_EQ(rig.store.value(0x2002, 0).size(), data.size());
  // Upload: first frame 112, last segment 3 bytes padded: cmd 0x00|n=4<<1|c = 0x09.
  Frame first = request(sdo(0x40, 0x2002, 0));
  EXPECT_EQ(first.size(), 122u);
  EXPECT_EQ(request(sdo(0x60, 0, 0)), (Frame{0x00, 0x30, 0x09, data[112], data[113], data[114], 0, 0, 0, 0}));
}

// Issue 19: KickCAT sends normal downloads as 0x20 (0x30 with complete
// access), s = 0, the complete size in the size field. They were refused with
// 05040001h.
TEST_F(SdoServerTest, NormalDownloadWithoutSizeBitTakesTheSizeField) {
  const Frame ok{0x00, 0x30, 0x60, 0x02, 0x20, 0x00, 0, 0, 0, 0};
  EXPECT_EQ(request(sdo(0x20, 0x2002, 0, 5, {1, 2, 3, 4, 5})), ok);
  const auto v = rig.store.value(0x2002, 0);
  EXPECT_EQ(Frame(v.begin(), v.end()), (Frame{1, 2, 3, 4, 5}));
  // The field still bounds the data, as with s = 1.
  EXPECT_EQ(abort_code(request(sdo(0x20, 0x2002, 0, 2, {1, 2, 3}))), 0x06070010u);
  EXPECT_EQ(abort_code(request(sdo(0x20, 0x2000, 0, 6, {1, 2, 3, 4, 5, 6}))), 0x06070012u);
  // Longer than one frame: the first 112 bytes, then segments.
  const Frame data = pattern(300);
  EXPECT_EQ(segmented_download(rig, data, -1, 0x20).size(), 10u);
  const auto stored = rig.store.value(0x2002, 0);
  EXPECT_EQ(Frame(stored.begin(), stored.end()), data);
}

TEST_F(SdoServerTest, CompleteAccessDownloadWithoutSizeBit) {
  // PDO mapping by complete access as KickCAT writes it: 0x30, size 10.
  EXPECT_EQ(request(sdo(0x30, 0x1601, 0, 10, {2, 0, 0x20, 0x00, 0x02, 0x70, 0x08, 0x00, 0x01, 0x70})),
            (Frame{0x00, 0x30, 0x60, 0x01, 0x16, 0x00, 0, 0, 0, 0}));
  EXPECT_EQ(rig.store.get<std::uint8_t>(0x1601, 0), 2);
  EXPECT_EQ(rig.store.get<std::uint32_t>(0x1601, 1), 0x70020020u);
  EXPECT_EQ(rig.store.get<std::uint32_t>(0x1601, 2), 0x70010008u);
  // The size field against the object's complete size (sub 0 = 1: 6 bytes).
  EXPECT_EQ(abort_code(request(sdo(0x30, 0x1601, 0, 8, {1, 0, 0x20, 0x00, 0x02, 0x70, 0, 0}))), 0x06070012u);
  EXPECT_EQ(rig.store.get<std::uint8_t>(0x1601, 0), 2);
}

TEST_F(SdoServerTest, NormalDownloadOfUnindicatedSize) {
  const Frame ok{0x00, 0x30, 0x60, 0x02, 0x20, 0x00, 0, 0, 0, 0};
  // Size field 0 and data in the frame: the frame's data is the value.
  EXPECT_EQ(request(sdo(0x20, 0x2002, 0, 0, {7, 8, 9})), ok);
  auto v = rig.store.value(0x2002, 0);
  EXPECT_EQ(Frame(v.begin(), v.end()), (Frame{7, 8, 9}));
  // No data in the frame: segments up to the last one carry it (CiA 301).
  EXPECT_EQ(request(sdo(0x20, 0x2002, 0, 0)), ok);
  EXPECT_EQ(request(segment(0x00, {1, 2, 3, 4, 5, 6, 7})), (Frame{0x00, 0x30, 0x20, 0, 0, 0, 0, 0, 0, 0}));
  EXPECT_EQ(rig.store.value(0x2002, 0).size(), 3u);  // nothing written before the last segment
  EXPECT_EQ(request(segment(0x10 | (5 << 1) | 1, {8, 9})), (Frame{0x00, 0x30, 0x30, 0, 0, 0, 0, 0, 0, 0}));
  v = rig.store.value(0x2002, 0);
  EXPECT_EQ(Frame(v.begin(), v.end()), (Frame{1, 2, 3, 4, 5, 6, 7, 8, 9}));
  // A fixed-size entry learns the size at the last segment: 3 bytes into 16 bits.
  EXPECT_EQ(request(sdo(0x20, 0x2000, 0, 0))[2], 0x60);
  EXPECT_EQ(abort_code(request(segment(0x00 | (4 << 1) | 1, {1, 2, 3}))), 0x06070012u);
  EXPECT_EQ(request(sdo(0x20, 0x2000, 0, 0))[2], 0x60);
  EXPECT_EQ(request(segment(0x00 | (5 << 1) | 1, {0x42, 0x00}))[2], 0x20);
  EXPECT_EQ(rig.store.get<std::int16_t>(0x2000, 0), 0x42);
}

TEST_F(SdoServerTest, ToggleErrorsAbortAndLeaveTheValue) {
  ASSERT_TRUE(rig.store.assign(0x2002, 0, Frame{9, 9}));
  Frame reply = segmented_download(rig, pattern(500), 1);
  EXPECT_EQ(abort_code(reply), 0x05030000u);
  EXPECT_EQ(reply[3] | (reply[4] << 8), 0x2002);
  EXPECT_EQ(rig.store.value(0x2002, 0).size(), 2u);
  // Further segments after the abort are out of any transfer.
  EXPECT_EQ(abort_code(request(segment(0x00, {1}))), 0x05040001u);
  segmented_download(rig, pattern(500));
  EXPECT_EQ(abort_code(segmented_upload(rig, 0x2002, 0, 0, 2)), 0x05030000u);
  EXPECT_EQ(abort_code(request(sdo(0x60, 0, 0))), 0x05040001u);
}

TEST_F(SdoServerTest, MasterAbortEndsTheTransferWithoutReply) {
  segmented_download(rig, pattern(50));
  Frame init = sdo(0x21, 0x2002, 0, 300, pattern(112));
  EXPECT_EQ(request(init)[2], 0x60);
  EXPECT_TRUE(request(sdo(0x80, 0x2002, 0, 0x08000000)).empty());
  EXPECT_EQ(abort_code(request(segment(0x01, {1}))), 0x05040001u);
  EXPECT_EQ(rig.store.value(0x2002, 0).size(), 50u);
}

TEST_F(SdoServerTest, AbortCodes) {
  auto code = [&](const Frame& f) { return abort_code(request(f)); };
  EXPECT_EQ(code(sdo(0xE0, 0x1000, 0)), 0x05040001u);  // command specifier 7
  EXPECT_EQ(code(sdo(0x40, 0x1018, 0x09)), 0x06090011u);
  EXPECT_EQ(code(sdo(0x40, 0x5555, 0)), 0x06020000u);
  EXPECT_EQ(code(sdo(0x40, 0x2001, 0)), 0x06010001u);       // read of a write-only entry
  EXPECT_EQ(code(sdo(0x23, 0x1000, 0, 1)), 0x06010002u);    // write of a read-only entry
  EXPECT_EQ(code(sdo(0x27, 0x2000, 0, 1)), 0x06070012u);    // 3 bytes into 16 bits
  EXPECT_EQ(code(sdo(0x2F, 0x2000, 0, 1)), 0x06070013u);    // 1 byte into 16 bits
  EXPECT_EQ(code(sdo(0x21, 0x2000, 0, 3, {1, 2, 3})), 0x06070012u);
  EXPECT_EQ(code(sdo(0x2B, 0x2000, 0, 101)), 0x06090031u);
  EXPECT_EQ(code(sdo(0x2B, 0x2000, 0, 0xFF9B)), 0x06090032u);  // -101
  EXPECT_EQ(code(sdo(0x2F, 0x2005, 2, 9)), 0x06090030u);        // BIT3 = 9
  EXPECT_EQ(code(sdo(0x50, 0x1018, 2)), 0x06010000u);           // complete access from sub 2
  EXPECT_EQ(code(sdo(0x50, 0x1000, 0)), 0x06010000u);           // complete access of a VAR
  EXPECT_EQ(rig.store.get<std::int16_t>(0x2000, 0), 5);          // every refused write left it
  rig.esc.set_state(0x04);  // SafeOp
  EXPECT_EQ(code(sdo(0x2F, 0x2004, 0, 1)), 0x08000022u);  // writable in PreOp only
  EXPECT_EQ(code(sdo(0x2F, 0x1600, 0, 0)), 0x08000022u);  // PDO mapping outside PreOp
  EXPECT_EQ(rig.store.get<std::uint8_t>(0x2004, 0), 7);
}

TEST_F(SdoServerTest, CompleteAccessUploadFromSub0AndSub1) {
  // 1018h from sub 0: {4, pad, 4 x UDINT}, 18 bytes -> normal upload 0x51.
  EXPECT_EQ(request(sdo(0x50, 0x1018, 0)),
            (Frame{0x00, 0x30, 0x51, 0x18, 0x10, 0x00, 18, 0, 0, 0, 4, 0, 0xBC, 0x0A, 0, 0, 0x78, 0x56, 0x34, 0x12,
                   0x02, 0x00, 0x01, 0x00, 0xFE, 0xCA, 0xAD, 0x0B}));
  // 1C12h from sub 0 with one PDO: {1, pad, 0x1600} = 4 bytes -> expedited 0x53.
  EXPECT_EQ(request(sdo(0x50, 0x1C12, 0)), (Frame{0x00, 0x30, 0x53, 0x12, 0x1C, 0x00, 1, 0, 0x00, 0x16}));
  // From sub 1: the entries only -> 2 bytes, 0x5B.
  EXPECT_EQ(request(sdo(0x50, 0x1C12, 1)), (Frame{0x00, 0x30, 0x5B, 0x12, 0x1C, 0x01, 0x00, 0x16, 0, 0}));
  // Bit-packed record: BOOL(1) + BIT3(5) packed into one byte, then a byte-aligned UINT16.
  EXPECT_EQ(request(sdo(0x50, 0x2005, 0)),
            (Frame{0x00, 0x30, 0x51, 0x05, 0x20, 0x00, 5, 0, 0, 0, 3, 0, 0x0B, 0xEF, 0xBE}));
  EXPECT_EQ(request(sdo(0x50, 0x2005, 1)), (Frame{0x00, 0x30, 0x57, 0x05, 0x20, 0x01, 0x0B, 0xEF, 0xBE, 0x00}));
}

TEST_F(SdoServerTest, CompleteAccessDownload) {
  // 2003h: sub 0 read-only (3), subs 1, 2 rw, 3 ro (skipped).
  EXPECT_EQ(request(sdo(0x31, 0x2003, 0, 8, {3, 0, 0x01, 0xA0, 0x02, 0xA0, 0x03, 0xA0}))[2], 0x60);
  EXPECT_EQ(rig.store.get<std::uint16_t>(0x2003, 1), 0xA001);
  EXPECT_EQ(rig.store.get<std::uint16_t>(0x2003, 2), 0xA002);
  EXPECT_EQ(rig.store.get<std::uint16_t>(0x2003, 3), 0x3333);
  // Wrong length: too long / too short.
  EXPECT_EQ(abort_code(request(sdo(0x31, 0x2003, 0, 9, {3, 0, 1, 1, 2, 2, 3, 3, 4}))), 0x06070012u);
  EXPECT_EQ(abort_code(request(sdo(0x31, 0x2003, 0, 6, {3, 0, 1, 1, 2, 2}))), 0x06070013u);
  // Changing a read-only sub 0.
  EXPECT_EQ(abort_code(request(sdo(0x31, 0x2003, 0, 6, {2, 0, 1, 1, 2, 2}))), 0x06010002u);
  // From sub 1, expedited (4 bytes do not cover the 6 of subs 1..3).
  EXPECT_EQ(abort_code(request(sdo(0x33, 0x2003, 1, 0x12345678))), 0x06070013u);
  // PDO mapping in one go from sub 0: {1, pad, 0x70020020}.
  EXPECT_EQ(request(sdo(0x31, 0x1601, 0, 6, {1, 0, 0x20, 0x00, 0x02, 0x70}))[2], 0x60);
  EXPECT_EQ(rig.store.get<std::uint8_t>(0x1601, 0), 1);
  // A value refused half way leaves the whole record as it was.
  EXPECT_EQ(abort_code(request(sdo(0x31, 0x2005, 0, 5, {3, 0, 0x00, 0xFF, 0xFF}))), 0x06090031u);
  EXPECT_EQ(rig.store.get<std::uint8_t>(0x2005, 1), 1);
  EXPECT_EQ(rig.store.get<std::uint8_t>(0x2005, 2), 5);
}

// The rollback copy is one buffer per thread (SdoServer::rollback_buffer):
// a server built on this thread and asked on another (a firmware lane), where
// the buffer starts empty, still puts a record refused half way back - twice,
// the second time with the buffer the first one grew.
TEST_F(SdoServerTest, CompleteAccessRollbackOnAnotherThread) {
  std::uint32_t first = 0;
  std::uint32_t second = 0;
  std::thread lane([&] {
    first = abort_code(request(sdo(0x31, 0x2005, 0, 5, {3, 0, 0x00, 0xFF, 0xFF})));
    second = abort_code(request(sdo(0x31, 0x2005, 0, 5, {3, 0, 0x0E, 0xFF, 0xFF})));
  });
  lane.join();
  EXPECT_EQ(first, 0x06090031u);
  EXPECT_EQ(second, 0x06090031u);
  EXPECT_EQ(rig.store.get<std::uint8_t>(0x2005, 1), 1);
  EXPECT_EQ(rig.store.get<std::uint8_t>(0x2005, 2), 5);
}

}  // namespace
}  // namespace ecat::coe

namespace ecat::coe {
namespace {

TEST(SdoServerOptions, CompleteAccessRefusedWhenNotOffered) {
  od::DeviceDescription d = test::make_device();
  ObjectStore store(d.dictionary);
  SdoServer server(store, false);
  const std::uint8_t req[8] = {0x50, 0x18, 0x10, 0x00, 0, 0, 0, 0};
  std::uint8_t reply[64]{};
  auto n = server.handle(req, reply, od::EsmState::PreOp);
  ASSERT_TRUE(n);
  EXPECT_EQ(test::Frame(reply, reply + *n), (test::Frame{0x00, 0x20, 0x80, 0x18, 0x10, 0x00, 0x00, 0x00, 0x01, 0x06}));
}

}  // namespace
}  // namespace ecat::coe

namespace ecat::coe {
namespace {

TEST(SdoServerOptions, CompleteAccessOverAVariableLengthEntry) {
  od::DeviceDescription d = test::make_device();
  (void)d.dictionary.put(test::composite(0x2100, "With blob", od::ObjectCode::Record, od::DataType::Record, test::kRo,
                                         {test::entry(1, "Word", od::DataType::Unsigned16, 16, test::kRw),
                                          test::entry(2, "Blob", od::DataType::OctetString, 0, test::kRw)}));
  test::Rig rig(std::move(d));
  EXPECT_EQ(rig.sdo_request(test::sdo(0x50, 0x2100, 0)),
            (test::Frame{0x00, 0x20, 0x80, 0x00, 0x21, 0x00, 0x04, 0x00, 0x01, 0x06}));
  EXPECT_EQ(rig.sdo_request(test::sdo(0x31, 0x2100, 0, 4, {2, 0, 1, 2})),
            (test::Frame{0x00, 0x20, 0x80, 0x00, 0x21, 0x00, 0x04, 0x00, 0x01, 0x06}));
}

}  // namespace
}  // namespace ecat::coe
