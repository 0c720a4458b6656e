// Many slaves through the master against the real in-process stack (issue 16
// item 5): a process image of several LRW datagrams and frames taken to Op
// with the right WKC in every datagram of every cycle, and the batched set-up
// (scan, SII, mailbox SMs, PDO sizes: many slaves' datagrams per frame)
// learning exactly what the slave-by-slave reads learn, for every device file.
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "in_process_bus.hpp"
#include "master/coe_client.hpp"
#include "master/registers.hpp"

namespace ecat::master::test {
namespace {

std::vector<std::size_t> all_slaves(const Master& m) {
  std::vector<std::size_t> v(m.slave_count());
  for (std::size_t i = 0; i < v.size(); ++i) v[i] = i;
  return v;
}

TEST(InProcessScale, EightyServosReachOpOverSeveralFramesWithTheRightWkcPerDatagram) {
  constexpr std::size_t kServos = 80;
  InProcessBus bus;
  ASSERT_TRUE(bus.add(device_path("generic-servo.xml"), kServos));
  MasterConfig cfg;
  cfg.max_slaves = kServos;
  Master master(bus.transport, bus.clock, cfg);
  ASSERT_EQ(master.scan().value_or(0), kServos);
  ASSERT_EQ(master.configure_mailboxes().value_or(0), kServos);
  ASSERT_TRUE(master.request_state_all(AlState::PreOp).has_value());
  ASSERT_TRUE(read_pdo_sizes_all(master, all_slaves(master)).has_value());
  const std::uint32_t out = master.slave(0).pd.output_bytes;
  const std::uint32_t in = master.slave(0).pd.input_bytes;
  ASSERT_GT(out, 0u);
  ASSERT_GT(in, 0u);
  ASSERT_TRUE(master.configure_process_data().has_value());
  ASSERT_EQ(master.process_image().size(), kServos * (out + in));
  ASSERT_GT(master.process_image().size(), kMaxDatagramData);  // one datagram would not do

  // The plan: logical addresses run on, every datagram within the limit, the
  // expected WKCs add up to 3 per servo plus 3 more for every servo whose
  // outputs or inputs are cut over two datagrams.
  const auto plan = master.process_data_plan();
  ASSERT_GE(plan.size(), 2u);
  EXPECT_GE(master.process_data_frames(), 2u);
  std::uint32_t at = 0;
  unsigned wkc = 0;
  for (const PdDatagram& d : plan) {
    EXPECT_EQ(d.command, Command::Lrw);
    EXPECT_EQ(d.logical, at);
    EXPECT_LE(d.length, kMaxDatagramData);
    at += d.length;
    wkc += d.expected_wkc;
  }
  EXPECT_EQ(at, master.process_image().size());
  EXPECT_EQ(wkc, master.expected_wkc());
  EXPECT_EQ(master.expected_wkc(), 3 * kServos);  // spans of a few bytes: SOEM's rule never cuts one
  // Each servo's FMMUs point at its bytes of the image (esc-registers.md §6).
  for (std::size_t i : {std::size_t{0}, kServos / 2, kServos - 1}) {
    const auto& esc = bus.chain()[i].esc();
    EXPECT_EQ(load_le<std::uint32_t>(esc.memory() + reg::fmmu(0)), master.slave(i).pd.output_offset) << i;
    EXPECT_EQ(load_le<std::uint32_t>(esc.memory() + reg::fmmu(1)), master.slave(i).pd.input_offset) << i;
  }

  ASSERT_TRUE(master.request_state_all(AlState::SafeOp).has_value());
  for (int c = 0; c < 5; ++c) {
    auto r = master.exchange_process_data();
    ASSERT_TRUE(r.has_value());
    EXPECT_TRUE(r->ok()) << "cycle " << c << " wkc " << r->wkc << " of " << r->expected_wkc;
    EXPECT_EQ(r->frames, master.process_data_frames());
  }
  ASSERT_TRUE(master.request_state_all(AlState::Op).has_value());
  const auto frames_before = bus.chain().stats().frames_received;
  for (int c = 0; c < 10; ++c) {
    auto r = master.exchange_process_data();
    ASSERT_TRUE(r.has_value());
    EXPECT_EQ(r->wkc, 3 * kServos);
    EXPECT_EQ(r->datagrams_wrong, 0u);
    EXPECT_TRUE(r->ok());
    for (std::size_t k = 0; k < plan.size(); ++k) EXPECT_EQ(master.last_datagram_wkc(k), plan[k].expected_wkc) << k;
  }
  EXPECT_EQ(bus.chain().stats().frames_received - frames_before, 10 * master.process_data_frames());
  for (std::size_t i = 0; i < kServos; ++i) {
    EXPECT_EQ(bus.chain()[i].esc().register_u16(0x0130) & 0x1F, 0x08) << i;
  }
  EXPECT_EQ(master.cyclic_stats().wkc_errors, 0u);

  // Outputs of the last servo (in the first frame) reach its SM2 buffer, and
  // its inputs (in the last frame) come back: the servo's statusword (6041h,
  // first input entry) is not zero in Op.
  const std::size_t last = kServos - 1;
  EXPECT_NE(master.inputs(last)[0] | master.inputs(last)[1], 0);

  // A servo that stops answering its inputs spoils exactly the datagram that
  // holds them.
  std::uint8_t off[1]{0};
  ASSERT_TRUE(master.fpwr(master.slave(last).station_address, static_cast<std::uint16_t>(reg::fmmu(1) + 12), off));
  auto bad = master.exchange_process_data();
  ASSERT_TRUE(bad.has_value());
  EXPECT_FALSE(bad->ok());
  EXPECT_EQ(bad->datagrams_wrong, 1u);
  EXPECT_EQ(bad->wkc, 3 * kServos - 1);
  EXPECT_EQ(master.last_datagram_wkc(plan.size() - 1), plan.back().expected_wkc - 1);
}

// The batched scan reads, per slave, exactly what the slave-by-slave reads
// return: ESC information, DL and AL status, the whole SII image; the batched
// mailbox set-up programs the same SMs; the batched PDO sizes equal
// CoeClient::read_pdo_sizes. One slave of every device in xml/devices.
TEST(InProcessScale, BatchedSetUpLearnsWhatSlaveBySlaveReadsLearnForEveryDevice) {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(std::string(ECAT_SOURCE_DIR) + "/xml/devices")) {
    if (e.path().extension() == ".xml") files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());
  ASSERT_GE(files.size(), 5u);
  InProcessBus bus;
  for (const auto& f : files) ASSERT_TRUE(bus.add(f)) << f;
  Master master(bus.transport, bus.clock);
  ASSERT_EQ(master.scan().value_or(0), files.size());
  for (std::size_t i = 0; i < files.size(); ++i) {
    SCOPED_TRACE(files[i]);
    const SlaveInfo& s = master.slave(i);
    auto alone = master.read_sii_image(s.station_address);
    ASSERT_TRUE(alone.has_value());
    EXPECT_EQ(s.sii_image, *alone);
    std::uint8_t info[reg::kEscInfoLength]{};
    ASSERT_TRUE(master.fprd(s.station_address, reg::kType, info));
    EXPECT_EQ(s.esc.type, info[0]);
    EXPECT_EQ(s.esc.fmmus, info[4]);
    EXPECT_EQ(s.esc.sync_managers, info[5]);
    EXPECT_EQ(s.esc.port_descriptor, info[7]);
    EXPECT_EQ(s.esc.features, load_le<std::uint16_t>(info + 8));
    EXPECT_EQ(s.dl_status, master.fprd_u16(s.station_address, reg::kDlStatus).value_or(0));
    EXPECT_EQ(s.sii.vendor_id, bus.chain()[i].device().identity.vendor_id);
  }
  // Mailbox SMs: the batch against configure_mailbox, slave by slave.
  std::vector<MailboxLayout> batched;
  ASSERT_TRUE(master.configure_mailboxes().has_value());
  for (std::size_t i = 0; i < files.size(); ++i) batched.push_back(master.slave(i).mailbox);
  std::vector<std::size_t> coe;
  for (std::size_t i = 0; i < files.size(); ++i) {
    SCOPED_TRACE(files[i]);
    if (!master.slave(i).sii.has_mailbox()) {
      EXPECT_FALSE(batched[i].configured);
      continue;
    }
    ASSERT_TRUE(master.configure_mailbox(i).has_value());
    const MailboxLayout& one = master.slave(i).mailbox;
    EXPECT_TRUE(batched[i].configured);
    EXPECT_EQ(batched[i].rx_start, one.rx_start);
    EXPECT_EQ(batched[i].rx_size, one.rx_size);
    EXPECT_EQ(batched[i].tx_start, one.tx_start);
    EXPECT_EQ(batched[i].tx_size, one.tx_size);
    EXPECT_EQ(batched[i].rx_control, one.rx_control);
    EXPECT_EQ(batched[i].tx_control, one.tx_control);
    if (master.slave(i).sii.has_coe()) coe.push_back(i);
  }
  ASSERT_GE(coe.size(), 4u);
  ASSERT_TRUE(master.request_state_all(AlState::PreOp).has_value());
  // PDO sizes: all CoE slaves side by side, then each alone the old way.
  ASSERT_TRUE(read_pdo_sizes_all(master, coe).has_value());
  std::vector<std::pair<std::uint16_t, std::uint16_t>> sizes;
  for (std::size_t i : coe) sizes.emplace_back(master.slave(i).pd.output_bytes, master.slave(i).pd.input_bytes);
  for (std::size_t k = 0; k < coe.size(); ++k) {
    SCOPED_TRACE(files[coe[k]]);
    auto& pd = master.slave(coe[k]).pd;
    pd.output_bytes = 0xFFFF;
    pd.input_bytes = 0xFFFF;
    CoeClient client(master, coe[k]);
    ASSERT_TRUE(client.read_pdo_sizes().has_value());
    EXPECT_EQ(pd.output_bytes, sizes[k].first);
    EXPECT_EQ(pd.input_bytes, sizes[k].second);
    EXPECT_GT(pd.output_bytes + pd.input_bytes, 0);
  }
}

// A slave that cannot take the batched path (here: no mailbox set up) is read
// alone by CoeClient, and the error is the one CoeClient reports; the others
// still get their sizes.
TEST(InProcessScale, BatchedPdoSizesReportTheSlaveBySlaveError) {
  InProcessBus bus;
  ASSERT_TRUE(bus.add(device_path("generic-servo.xml"), 3));
  Master master(bus.transport, bus.clock);
  ASSERT_EQ(master.scan().value_or(0), 3u);
  ASSERT_TRUE(master.configure_mailbox(0).has_value());
  ASSERT_TRUE(master.configure_mailbox(2).has_value());
  ASSERT_TRUE(master.request_state(0, AlState::PreOp).has_value());
  ASSERT_TRUE(master.request_state(2, AlState::PreOp).has_value());
  CoeClient alone(master, 1);
  auto want = alone.read_pdo_sizes();
  ASSERT_FALSE(want.has_value());
  const std::vector<std::size_t> only_good{0, 2};
  ASSERT_TRUE(read_pdo_sizes_all(master, only_good).has_value());
  EXPECT_GT(master.slave(2).pd.output_bytes, 0);
  const std::vector<std::size_t> all{0, 1, 2};
  auto got = read_pdo_sizes_all(master, all);
  ASSERT_FALSE(got.has_value());
  EXPECT_EQ(got.error(), want.error());
}

// MasterConfig::read_sii_strings = false: everything the configuration uses
// from the SII is the same, the strings are not read, the scan takes fewer frames.
TEST(InProcessScale, ScanWithoutStringsLearnsTheSameConfigurationInFewerFrames) {
  std::vector<std::string> files;
  for (const auto& e : std::filesystem::directory_iterator(std::string(ECAT_SOURCE_DIR) + "/xml/devices")) {
    if (e.path().extension() == ".xml") files.push_back(e.path().string());
  }
  std::sort(files.begin(), files.end());
  InProcessBus full_bus, lean_bus;
  for (const auto& f : files) {
    ASSERT_TRUE(full_bus.add(f)) << f;
    ASSERT_TRUE(lean_bus.add(f)) << f;
  }
  Master full(full_bus.transport, full_bus.clock);
  MasterConfig cfg;
  cfg.read_sii_strings = false;
  Master lean(lean_bus.transport, lean_bus.clock, cfg);
  ASSERT_EQ(full.scan().value_or(0), files.size());
  ASSERT_EQ(lean.scan().value_or(0), files.size());
  EXPECT_LT(lean_bus.chain().stats().frames_received, full_bus.chain().stats().frames_received);
  for (std::size_t i = 0; i < files.size(); ++i) {
    SCOPED_TRACE(files[i]);
    const SiiInfo& a = full.slave(i).sii;
    const SiiInfo& b = lean.slave(i).sii;
    EXPECT_EQ(full.slave(i).sii_image.size(), lean.slave(i).sii_image.size());
    EXPECT_FALSE(a.strings.empty());
    EXPECT_TRUE(b.strings.empty());
    EXPECT_EQ(a.checksum_ok, b.checksum_ok);
    EXPECT_EQ(a.vendor_id, b.vendor_id);
    EXPECT_EQ(a.product_code, b.product_code);
    EXPECT_EQ(a.revision, b.revision);
    EXPECT_EQ(a.serial, b.serial);
    EXPECT_EQ(a.rx_mailbox_offset, b.rx_mailbox_offset);
    EXPECT_EQ(a.rx_mailbox_size, b.rx_mailbox_size);
    EXPECT_EQ(a.tx_mailbox_offset, b.tx_mailbox_offset);
    EXPECT_EQ(a.tx_mailbox_size, b.tx_mailbox_size);
    EXPECT_EQ(a.mailbox_protocols, b.mailbox_protocols);
    EXPECT_EQ(a.category_order, b.category_order);
    ASSERT_EQ(a.general.has_value(), b.general.has_value());
    if (a.general) {
      EXPECT_EQ(a.general->coe_details, b.general->coe_details);
      EXPECT_EQ(a.general->flags, b.general->flags);
      EXPECT_EQ(a.general->physical_ports, b.general->physical_ports);
    }
    EXPECT_EQ(a.fmmu_usage, b.fmmu_usage);
    ASSERT_EQ(a.sync_managers.size(), b.sync_managers.size());
    for (std::size_t k = 0; k < a.sync_managers.size(); ++k) {
      EXPECT_EQ(a.sync_managers[k].start, b.sync_managers[k].start);
      EXPECT_EQ(a.sync_managers[k].length, b.sync_managers[k].length);
      EXPECT_EQ(a.sync_managers[k].control, b.sync_managers[k].control);
      EXPECT_EQ(a.sync_managers[k].type, b.sync_managers[k].type);
    }
    for (std::uint8_t sm = 0; sm < 8; ++sm) {
      EXPECT_EQ(a.default_pdo_bits(true, sm), b.default_pdo_bits(true, sm));
      EXPECT_EQ(a.default_pdo_bits(false, sm), b.default_pdo_bits(false, sm));
    }
    EXPECT_EQ(a.tx_pdos.size(), b.tx_pdos.size());
    EXPECT_EQ(a.rx_pdos.size(), b.rx_pdos.size());
    EXPECT_EQ(a.dc_modes.size(), b.dc_modes.size());
  }
}

// The batch packs: 60 servos' station addresses, ESC/DL/AL reads and SII
// rounds take far fewer frames than one per slave and step.
TEST(InProcessScale, ScanOfSixtySlavesPacksManyDatagramsPerFrame) {
  constexpr std::size_t kSlaves = 60;
  InProcessBus bus;
  ASSERT_TRUE(bus.add(device_path("generic-servo.xml"), kSlaves));
  MasterConfig cfg;
  cfg.max_slaves = kSlaves;
  Master master(bus.transport, bus.clock, cfg);
  ASSERT_EQ(master.scan().value_or(0), kSlaves);
  const std::size_t sii_reads = (master.slave(0).sii_image.size() + 7) / 8;
  // Alone: 2 frames per 8-byte read per slave (command, poll). Side by side:
  // per read one command round (60 x 18 B, 1 frame) and one poll round
  // (60 x 26 B, 2 frames), plus the idle check and the other scan steps.
  const auto frames = bus.chain().stats().frames_received;
  EXPECT_LT(frames, 3 * sii_reads + 40);
  EXPECT_GT(frames, 2 * sii_reads);
}

}  // namespace
}  // namespace ecat::master::test
