// Interpolation data buffer 60C4h (CiA 402-2 interpolated position mode):
// FIFO and ring organisation, size, clearing and access, the drive taking one
// record per interpolation period, records by SDO and by RxPDO through the
// binding.
#include "ds402/ip_buffer.hpp"

#include <gtest/gtest.h>

#include <vector>

#include "ds402/controlword.hpp"
#include "ds402/od_binding.hpp"
#include "ds402/statusword.hpp"
#include "harness.hpp"
#include "tests/coe/rig.hpp"

namespace ecat::ds402::test {
namespace {

IpBuffer::Config fifo(std::uint32_t size, std::uint8_t access = IpBuffer::kEnableAccess) {
  return IpBuffer::Config{size, IpBuffer::kFifo, 0, access};
}

TEST(IpBuffer, FifoKeepsOrderAndDropsWhenFull) {
  IpBuffer b;
  b.configure(fifo(3));
  EXPECT_TRUE(b.push(10));
  EXPECT_TRUE(b.push(20));
  EXPECT_TRUE(b.push(30));
  EXPECT_FALSE(b.push(40));  // full
  EXPECT_EQ(b.lost(), 1u);
  EXPECT_EQ(b.count(), 3u);
  EXPECT_EQ(b.pop(), 10);
  EXPECT_TRUE(b.push(50));
  EXPECT_EQ(b.pop(), 20);
  EXPECT_EQ(b.pop(), 30);
  EXPECT_EQ(b.pop(), 50);
  EXPECT_EQ(b.pop(), std::nullopt);
}

TEST(IpBuffer, AccessClearAndSize) {
  IpBuffer b;
  b.configure(fifo(4, IpBuffer::kClear));
  EXPECT_FALSE(b.enabled());
  EXPECT_FALSE(b.push(1));  // access disabled: not taken, not counted as lost
  EXPECT_EQ(b.lost(), 0u);
  b.configure(fifo(4));
  EXPECT_TRUE(b.push(1));
  EXPECT_TRUE(b.push(2));
  b.configure(fifo(4, IpBuffer::kClear));  // 60C4h:06 = 0 clears and disables
  EXPECT_EQ(b.count(), 0u);
  b.configure(fifo(4));
  EXPECT_EQ(b.pop(), std::nullopt);
  EXPECT_TRUE(b.push(3));
  b.configure(fifo(2));  // a new size clears
  EXPECT_EQ(b.count(), 0u);
  EXPECT_EQ(b.size(), 2u);
  b.configure(fifo(0));  // sizes clamp to 1..16
  EXPECT_EQ(b.size(), 1u);
  b.configure(fifo(1000));
  EXPECT_EQ(b.size(), IpBuffer::kMaxSize);
}

TEST(IpBuffer, RingWritesAtThePositionAndAdvancesIt) {
  IpBuffer b;
  b.configure(IpBuffer::Config{4, IpBuffer::kRing, 2, IpBuffer::kEnableAccess});
  EXPECT_EQ(b.position(), 2u);
  b.push(100);
  b.push(200);
  EXPECT_EQ(b.position(), 0u);  // wrapped after position 3
  b.push(300);
  EXPECT_EQ(b.position(), 1u);
  EXPECT_EQ(b.pop(), 100);  // the drive reads the ring from where it was written
  EXPECT_EQ(b.pop(), 200);
  // The drive's own advance, written back to 60C4h:04, is no reconfiguration.
  b.configure(IpBuffer::Config{4, IpBuffer::kRing, 1, IpBuffer::kEnableAccess});
  EXPECT_EQ(b.count(), 1u);
  b.push(400);
  b.push(500);
  b.push(600);
  EXPECT_EQ(b.lost(), 0u);
  b.push(700);  // the ring is full: the oldest record not yet taken (300) is overwritten
  EXPECT_EQ(b.lost(), 1u);
  EXPECT_EQ(b.count(), 4u);
  EXPECT_EQ(b.pop(), 400);
}

constexpr std::uint16_t kEnableOp = 0x000F;

// The drive takes one buffered record per interpolation period (1 ms here)
// and moves the demand there in a straight line; an empty buffer holds.
TEST(IpBufferDrive, OneRecordPerPeriodThenHold) {
  Harness h(*drive_personality("yaskawa-sigma5-sd"));
  h.in.ip_period_value = 2;  // 2 ms
  h.in.ip_period_index = -3;
  h.in.ip_buffer_actual_size = 8;
  h.in.ip_buffer_access = IpBuffer::kEnableAccess;
  h.enable(OperationMode::InterpolatedPosition);
  // Fill before interpolation starts: 4 records, one per cycle.
  const std::vector<std::int32_t> points{1000, 3000, 6000, 10000};
  h.in.ip_record_new = true;
  for (std::int32_t p : points) {
    h.in.ip_position = p;
    h.step();
  }
  h.in.ip_record_new = false;
  EXPECT_EQ(h.drive.ip_buffer().count(), 4u);
  EXPECT_EQ(h.out.position_demand, 0);
  h.command(kEnableOp | cw::kEnableIpMode);  // takes 1000, half way after 1 ms
  EXPECT_TRUE(h.bit(sw::kIpModeActive));
  EXPECT_EQ(h.out.position_demand, 500);
  h.step();
  EXPECT_EQ(h.out.position_demand, 1000);
  h.step();
  EXPECT_EQ(h.out.position_demand, 2000);  // toward 3000
  h.step();
  EXPECT_EQ(h.out.position_demand, 3000);
  h.run(2);
  EXPECT_EQ(h.out.position_demand, 6000);
  h.run(2);
  EXPECT_EQ(h.out.position_demand, 10000);
  EXPECT_EQ(h.drive.ip_buffer().count(), 0u);
  h.run(10);  // empty: holds the last point
  EXPECT_EQ(h.out.position_demand, 10000);
  // A record arriving now is taken at the next period boundary.
  h.in.ip_position = 12000;
  h.in.ip_record_new = true;
  h.step();
  h.in.ip_record_new = false;
  h.run(2);
  EXPECT_EQ(h.out.position_demand, 12000);
}

TEST(IpBufferDrive, OverflowSetsTheWarningBitInThatCycle) {
  Harness h(*drive_personality("yaskawa-sigma5-sd"));
  h.in.ip_buffer_actual_size = 2;
  h.in.ip_buffer_access = IpBuffer::kEnableAccess;
  h.enable(OperationMode::InterpolatedPosition);
  h.in.ip_record_new = true;
  h.step();
  h.step();
  EXPECT_FALSE(h.bit(sw::kWarning));
  h.step();  // the third record does not fit
  EXPECT_TRUE(h.bit(sw::kWarning));
  EXPECT_EQ(h.drive.ip_buffer().lost(), 1u);
  h.in.ip_record_new = false;
  h.step();
  EXPECT_FALSE(h.bit(sw::kWarning));
}

TEST(IpBufferDrive, WithoutAccessTheRecordIsTakenDirectly) {
  Harness h(*drive_personality("yaskawa-sigma5-sd"));
  h.in.ip_buffer_access = IpBuffer::kClear;
  h.enable(OperationMode::InterpolatedPosition);
  h.in.ip_position = 4000;
  h.in.ip_record_new = true;
  h.command(kEnableOp | cw::kEnableIpMode);
  h.step();
  EXPECT_EQ(h.out.position_demand, 4000);  // 60C2h default here: one cycle
  EXPECT_EQ(h.drive.ip_buffer().count(), 0u);
}

// Through the binding: an SDO write of 60C1h:01 is one record; an RxPDO that
// maps 60C1h:01 brings one every cycle; 60C4h's entries reach the drive.
od::Entry entry(std::uint8_t sub, od::DataType type, std::uint16_t bits) {
  od::Entry e;
  e.subindex = sub;
  e.type = type;
  e.bit_length = bits;
  e.access.bits = od::Access::kRw;
  return e;
}

od::DeviceDescription ip_servo() {
  using T = od::DataType;
  od::DeviceDescription dev;
  od::Object rec;
  rec.index = 0x60C1;
  rec.code = od::ObjectCode::Array;
  rec.type = T::Integer32;
  rec.entries.push_back(entry(0, T::Unsigned8, 8));
  rec.entries.back().default_value = {1};
  rec.entries.push_back(entry(1, T::Integer32, 32));
  EXPECT_TRUE(dev.dictionary.put(rec));
  od::Object cfg;
  cfg.index = 0x60C4;
  cfg.code = od::ObjectCode::Record;
  cfg.type = T::Record;
  cfg.entries.push_back(entry(0, T::Unsigned8, 8));
  cfg.entries.back().default_value = {6};
  cfg.entries.push_back(entry(1, T::Unsigned32, 32));
  cfg.entries.push_back(entry(2, T::Unsigned32, 32));
  cfg.entries.push_back(entry(3, T::Unsigned8, 8));
  cfg.entries.push_back(entry(4, T::Unsigned16, 16));
  cfg.entries.push_back(entry(5, T::Unsigned8, 8));
  cfg.entries.push_back(entry(6, T::Unsigned8, 8));
  EXPECT_TRUE(dev.dictionary.put(cfg));
  return dev;
}

TEST(IpBufferBinding, SdoWritesAndRxPdoBringRecords) {
  coe::test::Rig rig(ip_servo());
  DriveBinding b(rig.store);
  b.publish(*drive_personality("yaskawa-sigma5-sd"));
  ASSERT_TRUE(rig.store.set<std::uint32_t>(0x60C4, 2, 5));
  ASSERT_TRUE(rig.store.set<std::uint8_t>(0x60C4, 3, 1));
  ASSERT_TRUE(rig.store.set<std::uint16_t>(0x60C4, 4, 3));
  ASSERT_TRUE(rig.store.set<std::uint8_t>(0x60C4, 6, 1));
  DriveInputs in;
  b.read_cycle(in, {});
  EXPECT_FALSE(in.ip_record_new);
  EXPECT_EQ(in.ip_buffer_actual_size, 5u);
  EXPECT_EQ(in.ip_buffer_organisation, 1);
  EXPECT_EQ(in.ip_buffer_position, 3);
  EXPECT_EQ(in.ip_buffer_access, 1);
  const std::vector<std::uint8_t> bytes{0x10, 0x27, 0, 0};  // 10000
  ASSERT_TRUE(rig.store.write(coe::WriteRequest{0x60C1, 1, bytes, od::EsmState::Op}));
  b.read_cycle(in, {});
  EXPECT_TRUE(in.ip_record_new);
  EXPECT_EQ(in.ip_position, 10000);
  b.read_cycle(in, {});
  EXPECT_FALSE(in.ip_record_new);  // one write, one record
  // An RxPDO mapping 60C1h:01: a record every cycle.
  std::vector<coe::PdoItem> rx{coe::PdoItem{}};
  rx[0].entry = rig.store.slot(0x60C1, 1);
  b.read_cycle(in, rx);
  EXPECT_TRUE(in.ip_record_new);
  b.read_cycle(in, rx);
  EXPECT_TRUE(in.ip_record_new);
  // The drive's ring position goes back to 60C4h:04.
  DriveOutputs out;
  out.ip_buffer_position = 4;
  EmcyQueue q;
  b.write(out, q);
  EXPECT_EQ(rig.store.get<std::uint16_t>(0x60C4, 4), 4);
}

}  // namespace
}  // namespace ecat::ds402::test
