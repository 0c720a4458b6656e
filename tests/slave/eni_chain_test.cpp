// Networks from an ENI (issue 14 item 4): the chain an ETG.2100 ENI describes
// runs in one process with the project's master, which sends the ENI's
// register and CoE InitCmds as a master would and checks every answer (the
// working counter of each register command, no SDO abort, upload data equal
// to the ENI's), then brings the chain to Op with the ENI's expected WKC.
#include <fmt/format.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "common/clock.hpp"
#include "esi/device_loader.hpp"
#include "esi/eni_devices.hpp"
#include "esi/eni_reader.hpp"
#include "esi/esi_writer.hpp"
#include "master/coe_client.hpp"
#include "master/master.hpp"
#include "slave/chain.hpp"
#include "transport/in_memory_transport.hpp"

namespace ecat::test {
namespace {

namespace fs = std::filesystem;

constexpr Nanoseconds kWire = std::chrono::microseconds(5);
constexpr std::uint16_t kSmAssignOutputs = 0x1C12;
constexpr std::uint16_t kSmAssignInputs = 0x1C13;

std::string eni_path(const char* name) { return std::string(ECAT_SOURCE_DIR) + "/tests/data/eni/" + name; }

bool in_transition(const std::vector<std::string>& ts, const char* t) {
  return std::find(ts.begin(), ts.end(), t) != ts.end();
}

// The chain of an ENI behind the in-memory wire, with a master whose station
// addresses start at the ENI's first PhysAddr (so the ENI's Adp values hold).
// ESC registers (ESC datasheet Section II, 0x0120 AL control, 0x0130 AL status).
constexpr std::uint16_t kAlControl = 0x0120;
constexpr std::uint16_t kAlStatus = 0x0130;
// 0x0980 cyclic unit control/activation .. 0x09AF latch 1 (Section II §4.9 DC).
constexpr std::uint16_t kDcFirstSyncRegister = 0x0980;
constexpr std::uint16_t kDcLastSyncRegister = 0x09AF;
// SYNC0 starts this long after the master's set-up (as ecat-master does).
constexpr Nanoseconds kSync0StartDelay = std::chrono::milliseconds(20);
// 1 ms cycles run in SafeOp before Op is asked: past the SYNC0 start and
// several 10 ms SYNC0 cycles of the Elmo network.
constexpr int kSafeOpCycles = 60;

struct EniBus {
  const esi::EniNetwork& net_;

  explicit EniBus(const esi::EniNetwork& net, const fs::path& esi_dir = {})
      : net_(net), master(wire, clock, config_for(net)) {
    std::vector<esi::EsiWarning> warnings;
    auto devs = esi::eni_devices(net, esi_dir, &warnings);
    if (!devs) throw std::runtime_error(devs.error().to_string());
    for (auto& d : *devs) {
      sources.push_back(d.esi_file);
      auto ok = chain.add(std::move(d.device), {});
      if (!ok) throw std::runtime_error(ok.error());
    }
  }

  static master::MasterConfig config_for(const esi::EniNetwork& net) {
    master::MasterConfig c;
    if (net.slaves.front().phys_addr) c.first_station_address = *net.slaves.front().phys_addr;
    return c;
  }

  // Scan, mailboxes, PreOp; then every PS InitCmd of every slave, register
  // commands first (ETG.2100: they set up the ESC before the mailbox ones).
  // Returns "" or what went wrong, naming the ENI line.
  std::string run_init_cmds(const esi::EniNetwork& net, int& sent) {
    auto n = master.scan();
    if (!n || *n != net.slaves.size()) return "scan";
    for (std::size_t i = 0; i < *n; ++i) {
      if (net.slaves[i].mailbox && !master.configure_mailbox(i)) return "mailbox";
      auto st = master.request_state(i, master::AlState::PreOp);
      if (!st || st->error()) return "preop";
    }
    for (std::size_t i = 0; i < *n; ++i) {
      for (const auto& c : net.slaves[i].init_cmds) {
        if (!in_transition(c.transitions, "PS")) continue;
        // The state request and its checks (AL control/status) are the
        // harness's own: it asks for SafeOp in to_op(), after the mailbox
        // InitCmds, as a configurator's master does.
        if (c.ado == kAlControl || c.ado == kAlStatus) continue;
        // The DC start time is the master's to compute from the system time
        // when it starts SYNC0 (the ENI holds a placeholder): to_op() sets
        // up DC as the ENI's Slave/DC says.
        if (c.ado >= kDcFirstSyncRegister && c.ado <= kDcLastSyncRegister) continue;
        std::vector<std::uint8_t> data = c.data;
        auto wkc = master.transact(static_cast<Command>(c.cmd),
                                   static_cast<std::uint32_t>(c.ado) << 16 | c.adp, data);
        if (!wkc) return "register InitCmd line " + std::to_string(c.line) + ": no reply";
        if (c.cnt && *wkc != *c.cnt) {
          return "register InitCmd line " + std::to_string(c.line) + ": WKC " + std::to_string(*wkc);
        }
        ++sent;
      }
      master::CoeClient coe(master, i);
      for (const auto& c : net.slaves[i].coe_init_cmds) {
        if (!in_transition(c.transitions, "PS")) continue;
        const std::string where = "slave " + std::to_string(i + 1) + " CoE InitCmd line " + std::to_string(c.line);
        if (c.download) {
          auto ok = coe.download(c.index, c.subindex, c.data, c.complete_access);
          if (!ok) return where + ": abort " + std::to_string(static_cast<std::uint32_t>(ok.error().code));
        } else {
          auto got = coe.upload(c.index, c.subindex, c.complete_access);
          if (!got) return where + ": abort " + std::to_string(static_cast<std::uint32_t>(got.error().code));
          if (*got != c.data) return where + ": upload differs from the ENI's data";
        }
        ++sent;
      }
    }
    return "";
  }

  std::string to_op() {
    for (std::size_t i = 0; i < master.slave_count(); ++i) {
      master::CoeClient coe(master, i);
      if (!coe.read_pdo_sizes()) return "pdo sizes";
    }
    if (!master.configure_process_data()) return "process data";
    if (std::any_of(net_.slaves.begin(), net_.slaves.end(), [](const auto& s) { return s.dc.has_value(); })) {
      if (!master.configure_dc(clock.now())) return "dc";
      for (std::size_t i = 0; i < net_.slaves.size(); ++i) {
        const auto& dc = net_.slaves[i].dc;
        if (!dc || dc->cycle_time0 == 0) continue;
        if (!master.configure_sync0(i, dc->cycle_time0, static_cast<std::uint32_t>(dc->shift_time), kSync0StartDelay)) {
          return "sync0 slave " + std::to_string(i + 1);
        }
      }
    }
    for (std::size_t i = 0; i < master.slave_count(); ++i) {
      auto st = master.request_state(i, master::AlState::SafeOp);
      if (!st) return "safeop slave " + std::to_string(i + 1) + ": no answer";
      if (st->error()) return fmt::format("safeop slave {}: AL status code {:#06x}", i + 1, st->code);
    }
    // SafeOp cycles until SYNC0 has run a few of its cycles.
    for (int c = 0; c < kSafeOpCycles; ++c) cycle();
    for (std::size_t i = 0; i < master.slave_count(); ++i) {
      auto st = master.request_state(i, master::AlState::Op);
      if (!st) return "op slave " + std::to_string(i + 1) + ": no answer";
      if (st->error()) return fmt::format("op slave {}: AL status code {:#06x}", i + 1, st->code);
    }
    return "";
  }

  Expected<master::CyclicResult, master::MasterError> cycle() {
    clock.advance(std::chrono::milliseconds(1));
    (void)chain.poll(clock.now());
    return master.exchange_process_data();
  }

  std::vector<std::uint8_t> upload(std::size_t slave, std::uint16_t index, std::uint8_t sub) {
    master::CoeClient coe(master, slave);
    auto v = coe.upload(index, sub);
    return v ? *v : std::vector<std::uint8_t>{};
  }

  ManualClock clock;
  slave::Chain chain{clock};
  transport::InMemoryTransport wire{[this](Bytes frame) {
    clock.advance(kWire);
    (void)chain.process_frame(frame, clock.now());
  }};
  master::Master master;
  std::vector<std::string> sources;
};

// A directory holding the ESI of the built-in generic servo, the ESI the
// first slave of servo-and-io.xml matches.
struct EsiDir {
  EsiDir() {
    dir = fs::temp_directory_path() / ("ecat-eni-esi-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()) +
                                       "-" + std::to_string(reinterpret_cast<std::uintptr_t>(this)));
    fs::create_directories(dir);
    auto d = esi::load_default_device();
    if (!d) throw std::runtime_error(d.error().to_string());
    std::ofstream(dir / "generic-servo.esi.xml") << esi::write_esi(*d);
    std::ofstream(dir / "notes.xml") << "<NotAnEsi/>";
  }
  ~EsiDir() {
    std::error_code ec;
    fs::remove_all(dir, ec);
  }
  fs::path dir;
};

TEST(EniChain, SoemSampleInitCmdsAreAcceptedAndTheChainReachesOp) {
  auto net = esi::read_eni(eni_path("soem-sample-eni.xml"));
  ASSERT_TRUE(net) << net.error().to_string();
  EniBus bus(*net);
  int sent = 0;
  ASSERT_EQ(bus.run_init_cmds(*net, sent), "");
  EXPECT_EQ(sent, 5);
  // What the InitCmds wrote is what the slaves now hold.
  EXPECT_EQ(bus.upload(0, kSmAssignInputs, 0), (std::vector<std::uint8_t>{0x02}));
  EXPECT_EQ(bus.upload(0, kSmAssignInputs, 1), (std::vector<std::uint8_t>{0x02, 0x1A}));
  EXPECT_EQ(bus.upload(0, kSmAssignInputs, 2), (std::vector<std::uint8_t>{0x05, 0x1A}));
  EXPECT_EQ(bus.upload(1, kSmAssignOutputs, 0), (std::vector<std::uint8_t>{0x03}));
  EXPECT_EQ(bus.upload(1, kSmAssignOutputs, 1), (std::vector<std::uint8_t>{0x01, 0x16}));
  EXPECT_EQ(bus.upload(1, kSmAssignOutputs, 2), (std::vector<std::uint8_t>{0x07, 0x16}));
  EXPECT_EQ(bus.upload(1, kSmAssignOutputs, 3), (std::vector<std::uint8_t>{0x1C, 0x16}));
  // Identity as the ENI gives it, in the SII and in 1018h.
  EXPECT_EQ(bus.master.slave(0).sii.product_code, 0x1234u);
  EXPECT_EQ(bus.master.slave(1).sii.product_code, 0x010055AAu);
  EXPECT_EQ(bus.upload(1, 0x1018, 2), (std::vector<std::uint8_t>{0xAA, 0x55, 0x00, 0x01}));
  // The ENI does not describe the PDOs' entries: they are empty, the slaves
  // exchange no process data and still reach Op.
  ASSERT_EQ(bus.to_op(), "");
  for (std::size_t i = 0; i < 2; ++i) {
    auto st = bus.master.read_al_status(i);
    ASSERT_TRUE(st);
    EXPECT_EQ(st->raw, 0x0008) << "slave " << i;
  }
}

TEST(EniChain, ServoAndIoRunTheirInitCmdsAndReachOpWithTheEnisWkc) {
  auto net = esi::read_eni(eni_path("servo-and-io.xml"));
  ASSERT_TRUE(net) << net.error().to_string();
  EsiDir esis;
  EniBus bus(*net, esis.dir);
  ASSERT_EQ(bus.sources.size(), 2u);
  EXPECT_EQ(bus.sources[0], (esis.dir / "generic-servo.esi.xml").string());  // dictionary from the ESI
  EXPECT_EQ(bus.sources[1], "");                                             // synthesised
  EXPECT_EQ(bus.chain[0].device().identity.serial, 17u);
  int sent = 0;
  ASSERT_EQ(bus.run_init_cmds(*net, sent), "");
  EXPECT_EQ(sent, 6 + 2 + 9);  // servo: 6 CoE; IO: 2 register + 9 CoE (one disabled)
  EXPECT_EQ(bus.upload(0, 0x6060, 0), (std::vector<std::uint8_t>{0x08}));
  EXPECT_EQ(bus.upload(1, 0x8000, 1), (std::vector<std::uint8_t>{0x0A, 0x00}));
  EXPECT_EQ(bus.upload(1, 0x1A00, 2), (std::vector<std::uint8_t>{0x20, 0x02, 0x00, 0x60}));
  ASSERT_EQ(bus.to_op(), "");
  std::uint16_t want = 0;
  for (const auto& c : net->cyclic) want = static_cast<std::uint16_t>(want + c.cnt);
  EXPECT_EQ(want, 6);
  EXPECT_EQ(bus.master.expected_wkc(), want);
  for (int c = 0; c < 100; ++c) {
    auto r = bus.cycle();
    ASSERT_TRUE(r);
    ASSERT_EQ(r->wkc, want) << "cycle " << c;
  }
  // The process image has the ENI's sizes (ProcessData Send/Recv BitLength):
  // outputs 112 + 8 bits, inputs 128 + 48.
  for (std::size_t i = 0; i < 2; ++i) {
    const auto& s = net->slaves[i];
    ASSERT_TRUE(s.send_bit_length && s.recv_bit_length);
    EXPECT_EQ(bus.master.slave(i).pd.output_bytes * 8u, *s.send_bit_length) << "slave " << i;
    EXPECT_EQ(bus.master.slave(i).pd.input_bytes * 8u, *s.recv_bit_length) << "slave " << i;
  }
  EXPECT_EQ(*net->slaves[0].send_bit_length + *net->slaves[1].send_bit_length, 120u);
  EXPECT_EQ(*net->slaves[0].recv_bit_length + *net->slaves[1].recv_bit_length, 176u);
}


// A configurator-exported ENI (kpierczy/ethercat-lib, tests/data/eni/SOURCE.md):
// an IMU synthesised from the ENI and four Elmo Gold drives whose dictionary
// comes from the Elmo ESI of the twin corpus. Its CoE InitCmds are not sent here: all 48 are writes ("clear
// sm pdos (0x1C12)", "download pdo 0x1C12:01 index") with Ccs 1, the SDO
// download specifier (coe-mailbox.md §5), while SOEM's sample ENI and SOEM's
// ec_main write with Ccs 2, the convention this project's reader follows
// (docs/twins.md, open).
TEST(EniChain, ConfiguratorExportedElmoNetworkBuildsFromTheElmoEsi) {
  auto net = esi::read_eni(eni_path("kpierczy-elmo-wheels.xml"));
  ASSERT_TRUE(net) << net.error().to_string();
  ASSERT_EQ(net->slaves.size(), 5u);
  const fs::path dir = fs::temp_directory_path() / ("ecat-eni-elmo-" + std::to_string(::testing::UnitTest::GetInstance()->random_seed()));
  fs::create_directories(dir);
  fs::copy_file(fs::path(ECAT_SOURCE_DIR) / "tests/data/esi-vendor/elmo-gold-ecat.xml", dir / "elmo-gold-ecat.xml",
                fs::copy_options::overwrite_existing);
  {
    EniBus bus(*net, dir);
    ASSERT_EQ(bus.sources.size(), 5u);
    EXPECT_EQ(bus.sources[0], "");  // the IMU: synthesised
    for (std::size_t i = 1; i < 5; ++i) EXPECT_EQ(bus.sources[i], (dir / "elmo-gold-ecat.xml").string()) << i;
    std::size_t ccs1 = 0;
    for (const auto& sl : net->slaves) {
      for (const auto& c : sl.coe_init_cmds) ccs1 += c.ccs == 1 ? 1 : 0;
    }
    EXPECT_EQ(ccs1, 48u);
    // Every twin answers its identity as the ENI has it (SII read by the scan).
    auto n = bus.master.scan();
    ASSERT_TRUE(n);
    ASSERT_EQ(*n, 5u);
    for (std::size_t i = 0; i < 5; ++i) {
      EXPECT_EQ(bus.master.slave(i).sii.vendor_id, net->slaves[i].vendor_id) << i;
      EXPECT_EQ(bus.master.slave(i).sii.product_code, net->slaves[i].product_code) << i;
      EXPECT_EQ(bus.master.slave(i).sii.revision, net->slaves[i].revision) << i;
    }
    // The export writes its downloads with Ccs 1 (EniCoeInitCmd::download):
    // every PS InitCmd is answered, then the network reaches Op with the
    // expected WKC.
    int sent = 0;
    ASSERT_EQ(bus.run_init_cmds(*net, sent), "");
    EXPECT_EQ(sent, 48 + 20);  // 48 CoE (4 drives x 12), 20 register (state and DC commands are the harness's)
    ASSERT_EQ(bus.to_op(), "");
    EXPECT_GT(bus.master.expected_wkc(), 0);
    for (int c = 0; c < 20; ++c) {
      auto r = bus.cycle();
      ASSERT_TRUE(r);
      EXPECT_EQ(r->wkc, bus.master.expected_wkc()) << c;
    }
  }
  std::error_code ec;
  fs::remove_all(dir, ec);
}

}  // namespace
}  // namespace ecat::test
