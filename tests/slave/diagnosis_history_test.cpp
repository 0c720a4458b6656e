// The diagnosis history 10F3h of the default device (ETG.1020 §13,
// coe::DiagnosisHistory, docs/coe.md "Diagnosis history"), read and written
// by the project's master over SDO as TwinCAT's diagnosis tab does: the
// messages the stack raises (an AL error, a drive fault's emergency) with
// their exact bytes, "new messages available", acknowledging, clearing, the
// flags and both overflow modes, complete access.
#include <gtest/gtest.h>

#include <vector>

#include "common/le.hpp"
#include "master/coe_client.hpp"
#include "tests/slave/fault_rig.hpp"

namespace ecat::test {
namespace {

using coe::DiagnosisHistory;
using Bytes8 = std::vector<std::uint8_t>;

constexpr std::uint16_t kHistory = 0x10F3;
constexpr std::uint8_t kMax = 1, kNewest = 2, kAcked = 3, kNew = 4, kFlags = 5, kFirst = 6;
constexpr std::size_t kRing = 16;
constexpr std::size_t kTimeStampAt = 8;  // Diag Code 4, Flags 2, Text ID 2

struct DiagRig : FaultRig {
  master::CoeClient coe{master, 0};
  DiagRig() : FaultRig(1) {
    EXPECT_EQ(bring_up(), "");
  }
  std::uint32_t u(std::uint8_t sub) {
    auto v = coe.upload_value(kHistory, sub);
    EXPECT_TRUE(v) << int(sub);
    return v.value_or(0xDEAD);
  }
  Bytes8 message(std::uint8_t sub) {
    auto v = coe.upload(kHistory, sub);
    EXPECT_TRUE(v) << int(sub);
    return v.value_or(Bytes8{});
  }
  master::SdoAbortCode refused(std::uint8_t sub, std::uint32_t value, std::size_t size) {
    auto r = coe.download_value(kHistory, sub, value, size);
    return r ? master::SdoAbortCode::GeneralError : r.error().code;
  }
  coe::DiagnosisHistory& history() { return chain[0].firmware().coe().diagnosis(); }
};

// The message bytes without the time stamp (which must lie in the run).
Bytes8 without_time(Bytes8 m, Nanoseconds latest) {
  EXPECT_GE(m.size(), DiagnosisHistory::kHeaderBytes);
  if (m.size() < DiagnosisHistory::kHeaderBytes) return m;
  const auto ts = load_le<std::uint64_t>(m.data() + kTimeStampAt);
  EXPECT_GT(ts, 0u);
  EXPECT_LE(ts, static_cast<std::uint64_t>(latest.count()));
  m.erase(m.begin() + kTimeStampAt, m.begin() + kTimeStampAt + 8);
  return m;
}

TEST(DiagnosisHistory, EmptyAtStart) {
  DiagRig r;
  EXPECT_EQ(r.u(kMax), kRing);
  EXPECT_EQ(r.u(kNewest), 0u);
  EXPECT_EQ(r.u(kAcked), 0u);
  EXPECT_EQ(r.u(kNew), 0u);
  EXPECT_EQ(r.u(kFlags), 0u);
  EXPECT_TRUE(r.message(kFirst).empty());
}

TEST(DiagnosisHistory, AlErrorAndDriveFaultBecomeMessages) {
  DiagRig r;
  r.engage("al_error", 0, {{"code", 0x001A}});
  r.advance(std::chrono::milliseconds(1));
  EXPECT_EQ(r.u(kNewest), kFirst);
  EXPECT_EQ(r.u(kNew), 1u);
  // Diag Code E001h | 001Ah << 16, flags: error, local time stamp (bit 4),
  // 1 parameter; text ID 0; the parameter: UINT16 (type 0006h) 001Ah.
  EXPECT_EQ(without_time(r.message(kFirst), r.clock.now()),
            (Bytes8{0x01, 0xE0, 0x1A, 0x00, 0x12, 0x01, 0x00, 0x00, 0x06, 0x00, 0x1A, 0x00}));
  EXPECT_EQ(r.u(kNew), 0u);  // overwrite mode: the newest message was read
  r.faults.clear_all();
  ASSERT_TRUE(r.master.request_state(0, master::AlState::PreOp, true));
  ASSERT_TRUE(r.master.request_state(0, master::AlState::SafeOp));
  for (int c = 0; c < 5; ++c) (void)r.cycle_once(std::chrono::milliseconds(1));
  ASSERT_TRUE(r.master.request_state(0, master::AlState::Op));
  r.engage("drive_fault", 0, {{"code", 0x2310}});
  for (int c = 0; c < 3; ++c) (void)r.cycle_once(std::chrono::milliseconds(1));
  EXPECT_EQ(r.u(kNewest), kFirst + 1u);
  EXPECT_EQ(r.u(kNew), 1u);
  // Diag Code E800h with the emergency's error code 2310h above it; error,
  // local time stamp, no parameters.
  EXPECT_EQ(without_time(r.message(kFirst + 1), r.clock.now()),
            (Bytes8{0x00, 0xE8, 0x10, 0x23, 0x12, 0x00, 0x00, 0x00}));
}

// 10F8h Actual Time Stamp: the slave's local time now, in the ns the
// messages' (local, flags bit 4) time stamps count in - never before a
// message's stamp, and it advances with the slave's time.
TEST(DiagnosisHistory, ActualTimeStampIsTheMessagesTimeBase) {
  DiagRig r;
  r.engage("al_error", 0, {{"code", 0x001A}});
  r.advance(std::chrono::milliseconds(1));
  const Bytes8 m = r.message(kFirst);
  ASSERT_GE(m.size(), DiagnosisHistory::kHeaderBytes);
  const auto stamp = load_le<std::uint64_t>(m.data() + kTimeStampAt);
  auto now_at = [&r]() -> std::uint64_t {
    auto v = r.coe.upload(0x10F8, 0);
    EXPECT_TRUE(v);
    EXPECT_EQ(v ? v->size() : 0u, 8u);
    return v && v->size() == 8 ? load_le<std::uint64_t>(v->data()) : 0;
  };
  const std::uint64_t first = now_at();
  EXPECT_GE(first, stamp);
  EXPECT_LE(first, static_cast<std::uint64_t>(r.clock.now().count()));
  r.advance(std::chrono::milliseconds(20));
  const std::uint64_t later = now_at();
  EXPECT_GE(later - first, 20'000'000u);
  EXPECT_LE(later, static_cast<std::uint64_t>(r.clock.now().count()));
  const std::uint8_t zero[8]{};
  auto w = r.coe.download(0x10F8, 0, zero);
  ASSERT_FALSE(w);
  EXPECT_EQ(w.error().code, master::SdoAbortCode::ReadOnly);
}

TEST(DiagnosisHistory, AcknowledgeAndClear) {
  DiagRig r;
  for (int code : {0x1000, 0x2000, 0x3000}) {
    ASSERT_TRUE(r.history().add(DiagnosisHistory::from_emergency(static_cast<std::uint16_t>(code)), r.clock.now()));
  }
  EXPECT_EQ(r.u(kNewest), kFirst + 2u);
  EXPECT_EQ(r.refused(kAcked, 5, 1), master::SdoAbortCode::ValueTooLow);            // 06090032
  EXPECT_EQ(r.refused(kAcked, kFirst + kRing, 1), master::SdoAbortCode::ValueTooHigh);  // 06090031
  EXPECT_EQ(r.refused(kAcked, kFirst + 3, 1), master::SdoAbortCode::ValueRange);        // no message there
  EXPECT_EQ(r.u(kAcked), 0u);  // refused writes changed nothing
  ASSERT_TRUE(r.coe.download_value(kHistory, kAcked, kFirst + 1, 1));
  EXPECT_EQ(r.u(kAcked), kFirst + 1u);
  // Acknowledge mode: "new" means unacknowledged ones exist (the third).
  ASSERT_TRUE(r.coe.download_value(kHistory, kFlags, DiagnosisHistory::kFlagAcknowledgeMode, 2));
  EXPECT_EQ(r.u(kNew), 1u);
  ASSERT_TRUE(r.coe.download_value(kHistory, kAcked, kFirst + 2, 1));
  EXPECT_EQ(r.u(kNew), 0u);
  EXPECT_EQ(r.refused(kFlags, 0x0100, 2), master::SdoAbortCode::ValueRange);  // a reserved bit
  // 0 clears every message.
  ASSERT_TRUE(r.coe.download_value(kHistory, kAcked, 0, 1));
  EXPECT_EQ(r.u(kNewest), 0u);
  EXPECT_EQ(r.u(kAcked), 0u);
  EXPECT_EQ(r.u(kNew), 0u);
  EXPECT_TRUE(r.message(kFirst).empty());
  EXPECT_EQ(r.u(kFlags), DiagnosisHistory::kFlagAcknowledgeMode);
}

TEST(DiagnosisHistory, OverwriteModeWrapsAndFlagsTheOverflow) {
  DiagRig r;
  for (std::size_t i = 0; i < kRing + 1; ++i) {
    ASSERT_TRUE(r.history().add(DiagnosisHistory::from_emergency(static_cast<std::uint16_t>(0x1000 + i)), r.clock.now()));
  }
  EXPECT_EQ(r.u(kNewest), kFirst);  // the 17th went into the first slot
  EXPECT_EQ(r.u(kFlags), DiagnosisHistory::kFlagOverflow);
  EXPECT_EQ(load_le<std::uint16_t>(r.message(kFirst).data() + 2), 0x1000 + kRing);
  // Bit 5 is the slave's: writing the flags keeps it.
  ASSERT_TRUE(r.coe.download_value(kHistory, kFlags, 0, 2));
  EXPECT_EQ(r.u(kFlags), DiagnosisHistory::kFlagOverflow);
}

TEST(DiagnosisHistory, AcknowledgeModeDropsWhenFullAndDisabledTypesAreNotKept) {
  DiagRig r;
  ASSERT_TRUE(r.coe.download_value(kHistory, kFlags, DiagnosisHistory::kFlagAcknowledgeMode, 2));
  for (std::size_t i = 0; i < kRing; ++i) {
    ASSERT_TRUE(r.history().add(DiagnosisHistory::from_emergency(static_cast<std::uint16_t>(0x1000 + i)), r.clock.now()));
  }
  EXPECT_FALSE(r.history().add(DiagnosisHistory::from_emergency(0x9999), r.clock.now()));
  EXPECT_EQ(r.u(kNewest), kFirst + kRing - 1);
  EXPECT_EQ(r.u(kFlags), DiagnosisHistory::kFlagAcknowledgeMode | DiagnosisHistory::kFlagOverflow);
  ASSERT_TRUE(r.coe.download_value(kHistory, kAcked, kFirst, 1));  // the oldest acknowledged
  EXPECT_TRUE(r.history().add(DiagnosisHistory::from_emergency(0x9999), r.clock.now()));
  EXPECT_EQ(r.u(kNewest), kFirst);
  ASSERT_TRUE(r.coe.download_value(kHistory, kFlags, DiagnosisHistory::kFlagDisableError, 2));
  EXPECT_FALSE(r.history().add(DiagnosisHistory::from_emergency(0x1234), r.clock.now()));
  bool emcy = true;
  ASSERT_TRUE(r.coe.download_value(kHistory, kFlags, DiagnosisHistory::kFlagEmergency, 2));
  ASSERT_TRUE(r.coe.download_value(kHistory, kAcked, 0, 1));
  EXPECT_TRUE(r.history().add(DiagnosisHistory::from_emergency(0x1234), r.clock.now(), &emcy));
  EXPECT_TRUE(emcy);  // bit 0 asks for an emergency as well
}

TEST(DiagnosisHistory, ReadableByCompleteAccess) {
  DiagRig r;
  ASSERT_TRUE(r.history().add(DiagnosisHistory::from_emergency(0x4310), r.clock.now()));
  auto all = r.coe.upload(kHistory, 0, true);
  ASSERT_TRUE(all);
  // Subindex 0 as 16 bits (complete access from subindex 0: the count and a
  // padding byte, docs/coe.md), then 1 and 2.
  ASSERT_GE(all->size(), 4u);
  EXPECT_EQ((*all)[0], kFirst + kRing - 1);  // highest subindex
  EXPECT_EQ((*all)[1], 0);
  EXPECT_EQ((*all)[2], kRing);
  EXPECT_EQ((*all)[3], kFirst);
}

}  // namespace
}  // namespace ecat::test
