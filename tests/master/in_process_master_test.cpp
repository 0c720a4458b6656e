// The master against the real in-process stack (esc::Esc + ESM + CoE behind
// slave::Chain): scan, SII, station addresses, Init -> PreOp with mailbox SMs,
// SDO traffic, process data up to Op.
#include <gtest/gtest.h>

#include <fstream>

#include "esi/esi_writer_device_xml.hpp"
#include "esi/twin_import.hpp"
#include "in_process_bus.hpp"
#include "master/coe_client.hpp"

namespace ecat::master::test {
namespace {

class InProcessMaster : public ::testing::Test {
 protected:
  InProcessBus bus;
  Master master{bus.transport, bus.clock};
};

TEST_F(InProcessMaster, ScanThreeSlavesAssignsAddressesAndReadsSii) {
  ASSERT_TRUE(bus.add(device_path("generic-servo.xml"), 3));
  auto n = master.scan();
  ASSERT_TRUE(n.has_value()) << describe(n.error());
  ASSERT_EQ(*n, 3u);
  for (std::size_t i = 0; i < 3; ++i) {
    const SlaveInfo& s = master.slave(i);
    EXPECT_EQ(s.position, i);
    EXPECT_EQ(s.station_address, 0x1001 + i);
    EXPECT_TRUE(s.sii.checksum_ok);
    EXPECT_EQ(s.sii.product_code, bus.chain()[i].device().identity.product_code);
    EXPECT_EQ(s.sii.vendor_id, bus.chain()[i].device().identity.vendor_id);
    EXPECT_TRUE(s.sii.has_coe());
    EXPECT_TRUE(s.al.is(AlState::Init));
    EXPECT_FALSE(s.al.error());
    // The ESC register file holds the address the master wrote.
    EXPECT_EQ(bus.chain()[i].esc().register_u16(0x0010), 0x1001 + i);
  }
}

// A slave left with register (0x0021) or ESC (0x0031) write protection on (a
// stray frame, the 10^6-frame fuzz) drops every write; the scan releases it
// first (ESC datasheet Section I "Write protection", Section II 0x0020-0x0031).
TEST(InProcessWriteProtection, ScanReleasesProtectionLeftOnByAStrayFrame) {
  for (const std::uint16_t protection : {std::uint16_t{0x0021}, std::uint16_t{0x0031}}) {
    SCOPED_TRACE(protection);
    InProcessBus bus;
    ASSERT_TRUE(bus.add(device_path("generic-servo.xml"), 2));
    Master master(bus.transport, bus.clock);
    const std::uint8_t on[1]{0x01};
    ASSERT_EQ(master.bwr(protection, on).value_or(0), 2u);
    // Protected now: a plain station-address write is discarded (no WKC, no change).
    const std::uint8_t address[2]{0x34, 0x12};
    EXPECT_EQ(master.bwr(0x0010, address).value_or(99), 0u);
    EXPECT_EQ(bus.chain()[0].esc().register_u16(0x0010), 0x0000);
    auto n = master.scan();
    ASSERT_TRUE(n.has_value()) << describe(n.error());
    ASSERT_EQ(*n, 2u);
    for (std::size_t i = 0; i < 2; ++i) {
      EXPECT_EQ(bus.chain()[i].esc().register_u16(0x0010), 0x1001 + i);
      EXPECT_EQ(bus.chain()[i].esc().register_u16(0x0020) & 0xFF00, 0x0000);  // 0x0021 = 0
      EXPECT_EQ(bus.chain()[i].esc().register_u16(0x0030) & 0xFF00, 0x0000);  // 0x0031 = 0
    }
  }
}

TEST_F(InProcessMaster, InitToPreOpNeedsTheMailboxSms) {
  ASSERT_TRUE(bus.add(device_path("generic-servo.xml")));
  ASSERT_EQ(master.scan().value_or(0), 1u);
  // Without SM0/SM1 the slave refuses with 0x0016 (ETG.1000.6 Table 11).
  auto refused = master.request_state(0, AlState::PreOp);
  ASSERT_TRUE(refused.has_value());
  EXPECT_TRUE(refused->error());
  EXPECT_TRUE(refused->is(AlState::Init));
  EXPECT_EQ(refused->code, 0x0016);
  ASSERT_TRUE(master.acknowledge_error(0).has_value());
  ASSERT_TRUE(master.configure_mailbox(0).has_value());
  auto st = master.request_state(0, AlState::PreOp);
  ASSERT_TRUE(st.has_value());
  EXPECT_TRUE(st->is(AlState::PreOp));
  EXPECT_FALSE(st->error());
  EXPECT_EQ(st->code, 0);
  // The SM registers the ESC holds are the SII's.
  const auto& sii = master.slave(0).sii;
  EXPECT_EQ(bus.chain()[0].esc().register_u16(0x0800), sii.rx_mailbox_offset);
  EXPECT_EQ(bus.chain()[0].esc().register_u16(0x0802), sii.rx_mailbox_size);
  EXPECT_EQ(bus.chain()[0].esc().register_u16(0x0808), sii.tx_mailbox_offset);
}

TEST_F(InProcessMaster, SdoTrafficAndProcessDataToOp) {
  ASSERT_TRUE(bus.add(device_path("generic-servo.xml")));
  ASSERT_EQ(master.scan().value_or(0), 1u);
  ASSERT_TRUE(master.configure_mailbox(0).has_value());
  ASSERT_TRUE(master.request_state(0, AlState::PreOp).has_value());
  CoeClient coe(master, 0);
  auto vendor = coe.upload_value(0x1018, 1);
  ASSERT_TRUE(vendor.has_value());
  EXPECT_EQ(*vendor, master.slave(0).sii.vendor_id);
  auto product = coe.upload_value(0x1018, 2);
  ASSERT_TRUE(product.has_value());
  EXPECT_EQ(*product, master.slave(0).sii.product_code);
  auto missing = coe.upload(0x5FFF, 0);
  ASSERT_FALSE(missing.has_value());
  EXPECT_EQ(missing.error().code, SdoAbortCode::ObjectNotFound);
  auto list = coe.od_list();
  ASSERT_TRUE(list.has_value());
  EXPECT_GT(list->size(), 10u);
  auto od = coe.object_description(0x1018);
  ASSERT_TRUE(od.has_value());
  EXPECT_EQ(od->max_subindex, 4);

  ASSERT_TRUE(coe.read_pdo_sizes().has_value());
  const auto& pd = master.slave(0).pd;
  EXPECT_EQ(pd.output_bytes * 8u, master.slave(0).sii.default_pdo_bits(false, 2));
  EXPECT_EQ(pd.input_bytes * 8u, master.slave(0).sii.default_pdo_bits(true, 3));
  ASSERT_TRUE(master.configure_process_data().has_value());
  EXPECT_EQ(master.expected_wkc(), 3);
  auto safe = master.request_state(0, AlState::SafeOp);
  ASSERT_TRUE(safe.has_value());
  EXPECT_TRUE(safe->is(AlState::SafeOp)) << safe->raw << " code " << safe->code;
  for (int i = 0; i < 5; ++i) ASSERT_TRUE(master.exchange_process_data().has_value());
  auto op = master.request_state(0, AlState::Op);
  ASSERT_TRUE(op.has_value());
  EXPECT_TRUE(op->is(AlState::Op)) << op->raw << " code " << op->code;
  auto r = master.exchange_process_data();
  ASSERT_TRUE(r.has_value());
  EXPECT_EQ(r->wkc, 3);
  EXPECT_EQ(r->round_trip, InProcessBus::kFrameTime);
}

}  // namespace
}  // namespace ecat::master::test

namespace ecat::master::test {
namespace {

// SM1 status mapped by an FMMU onto register 0x080D (SOEM, TwinCAT): the
// emulated ESC answers the mailbox poll inside the cyclic frame.
TEST(InProcessMailboxStatus, ReplySeenInTheCyclicImage) {
  InProcessBus bus;
  ASSERT_TRUE(bus.add(device_path("generic-servo.xml")));
  MasterConfig cfg;
  cfg.map_mailbox_status = true;
  Master master(bus.transport, bus.clock, cfg);
  ASSERT_EQ(master.scan().value_or(0), 1u);
  ASSERT_TRUE(master.configure_mailbox(0).has_value());
  ASSERT_TRUE(master.request_state(0, AlState::PreOp).has_value());
  CoeClient coe(master, 0);
  ASSERT_TRUE(coe.read_pdo_sizes().has_value());
  ASSERT_TRUE(master.configure_process_data().has_value());
  auto safe = master.request_state(0, AlState::SafeOp);
  ASSERT_TRUE(safe.has_value() && safe->is(AlState::SafeOp));
  auto r = master.exchange_process_data();
  ASSERT_TRUE(r.has_value());
  EXPECT_TRUE(r->ok()) << r->wkc << " vs " << r->expected_wkc;
  EXPECT_FALSE(master.mailbox_reply_flagged(0));
  const auto req = CoeClient::upload_request(0x1018, 1, false);
  ASSERT_TRUE(master.mailbox_send(0, mbx::kTypeCoe, req).has_value());
  ASSERT_TRUE(master.exchange_process_data().has_value());
  EXPECT_TRUE(master.mailbox_reply_flagged(0));
  auto m = master.mailbox_receive(0, std::chrono::milliseconds(100));
  ASSERT_TRUE(m.has_value());
  ASSERT_TRUE(master.exchange_process_data().has_value());
  EXPECT_FALSE(master.mailbox_reply_flagged(0));
}

// Propagation delays on a line of 3 emulated ESCs (esc::Segment hop delay):
// the reference has delay 0 and each later slave a larger one.
TEST(InProcessDc, DelaysGrowAlongTheLine) {
  InProcessBus bus;
  ASSERT_TRUE(bus.add(device_path("generic-servo.xml"), 3));
  Master master(bus.transport, bus.clock);
  ASSERT_EQ(master.scan().value_or(0), 3u);
  if (!master.slave(0).esc.has_dc()) GTEST_SKIP() << "device without DC";
  auto n = master.configure_dc(Nanoseconds{1'000'000'000});
  ASSERT_TRUE(n.has_value()) << describe(n.error());
  ASSERT_EQ(*n, 3u);
  EXPECT_EQ(master.reference_clock(), std::optional<std::size_t>(0));
  EXPECT_EQ(master.slave(0).dc.delay_ns, 0u);
  EXPECT_GT(master.slave(1).dc.delay_ns, 0u);
  EXPECT_GT(master.slave(2).dc.delay_ns, master.slave(1).dc.delay_ns);
  for (std::size_t i = 0; i < 3; ++i) {
    // 0x0928 holds what the master computed (hop delay 1 µs per slave).
    auto delay = master.fprd_u32(master.slave(i).station_address, 0x0928);
    ASSERT_TRUE(delay.has_value());
    EXPECT_EQ(*delay, master.slave(i).dc.delay_ns) << i;
    EXPECT_EQ(master.slave(i).dc.delay_ns, i * 1000u);
  }
  ASSERT_TRUE(master.dc_static_drift_compensation(100).has_value());
  ASSERT_TRUE(master.dc_static_drift_compensation(100, Command::Armw).has_value());
  EXPECT_EQ(master.dc_static_drift_compensation(1, Command::Lrw).error(), MasterError::InvalidArgument);
}

}  // namespace
}  // namespace ecat::master::test


namespace ecat::master::test {
namespace {

// A segment without process data (the rt-labs ATO sample device of the vendor
// corpus: mailbox only, no PDOs) still cycles: one BRD of the AL status per
// cycle, every slave answers it, expected WKC = slave count (issue 14).
TEST(InProcessNoProcessData, CyclesOnTheAlStatusWithWkcSlaveCount) {
  std::vector<esi::EsiWarning> warnings;
  auto twin = esi::import_twin(std::string(ECAT_SOURCE_DIR) + "/tests/data/esi-vendor/rtlabs-ato.xml", {}, &warnings);
  ASSERT_TRUE(twin) << twin.error().to_string();
  ASSERT_TRUE(twin->rx_pdos.empty() && twin->tx_pdos.empty());
  const std::string file = ::testing::TempDir() + "rtlabs-ato.device.xml";
  std::ofstream(file) << esi::write_device_xml(*twin);
  InProcessBus bus;
  ASSERT_TRUE(bus.add(file, 2));
  Master master(bus.transport, bus.clock);
  ASSERT_EQ(master.scan().value_or(0), 2u);
  EXPECT_EQ(master.exchange_process_data().error(), MasterError::NotConfigured);
  for (std::size_t i = 0; i < 2; ++i) {
    ASSERT_TRUE(master.configure_mailbox(i));
    ASSERT_TRUE(master.request_state(i, AlState::PreOp).value().is(AlState::PreOp));
  }
  ASSERT_TRUE(master.configure_process_data());
  EXPECT_TRUE(master.process_image().empty());
  for (AlState s : {AlState::SafeOp, AlState::Op}) {
    for (std::size_t i = 0; i < 2; ++i) {
      auto st = master.request_state(i, s);
      ASSERT_TRUE(st && st->is(s) && !st->error());
    }
  }
  for (int c = 0; c < 10; ++c) {
    auto r = master.exchange_process_data();
    ASSERT_TRUE(r) << describe(r.error());
    EXPECT_EQ(r->expected_wkc, 2);
    EXPECT_EQ(r->wkc, 2);
    EXPECT_TRUE(r->ok());
  }
  EXPECT_EQ(master.cyclic_stats().wkc_errors, 0u);
}

}  // namespace
}  // namespace ecat::master::test

// request_state_all broadcasts AL control and polls AL status by BRD (SOEM
// ecx_writestate(0)): the whole chain changes state in a few frames, not 4
// per slave; a refusal falls back to slave by slave, which records the code.
namespace ecat::master::test {
namespace {

TEST(InProcessStateAll, BroadcastTakesTheChainToPreOpInAFewFrames) {
  InProcessBus bus;
  ASSERT_TRUE(bus.add(device_path("generic-servo.xml"), 8));
  Master master(bus.transport, bus.clock);
  ASSERT_EQ(master.scan().value_or(0), 8u);
  for (std::size_t i = 0; i < 8; ++i) ASSERT_TRUE(master.configure_mailbox(i).has_value());
  const auto before = bus.chain().stats().frames_received;
  ASSERT_TRUE(master.request_state_all(AlState::PreOp).has_value());
  const auto frames = bus.chain().stats().frames_received - before;
  EXPECT_GE(frames, 2u);  // BWR 0x0120, then at least one BRD 0x0130
  EXPECT_LT(frames, 8u);  // slave by slave it was 2 per slave at least
  for (std::size_t i = 0; i < 8; ++i) {
    EXPECT_EQ(bus.chain()[i].esc().register_u16(0x0130) & 0x1F, 0x02) << i;
    EXPECT_TRUE(master.slave(i).al.is(AlState::PreOp));
  }
}

TEST(InProcessStateAll, ARefusalFallsBackToSlaveBySlaveWithItsCode) {
  InProcessBus bus;
  ASSERT_TRUE(bus.add(device_path("generic-servo.xml"), 3));
  Master master(bus.transport, bus.clock);
  ASSERT_EQ(master.scan().value_or(0), 3u);
  // No mailbox SMs: every slave refuses PreOp with 0x0016 (ETG.1000.6 Table 11).
  auto r = master.request_state_all(AlState::PreOp);
  ASSERT_FALSE(r.has_value());
  EXPECT_EQ(r.error(), MasterError::StateTimeout);
  EXPECT_TRUE(master.slave(0).al.error());
  EXPECT_EQ(master.slave(0).al.code, 0x0016);
}

}  // namespace
}  // namespace ecat::master::test
