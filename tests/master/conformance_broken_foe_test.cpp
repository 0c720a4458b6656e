// The FoE conformance cases against the Elmo Gold twin (tests/data/esi-vendor:
// its ESI lists FoE) with a state directory for its files: every case
// passes; and each case fails when the slave's FoE service is wrapped in one
// that breaks what the case checks (issue 31 item 3).
#include <gtest/gtest.h>

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>

#include "coe/mailbox_service.hpp"
#include "coe/storage_quota.hpp"
#include "esi/esi_writer_device_xml.hpp"
#include "esi/twin_import.hpp"
#include "conformance_proofs.hpp"
#include "in_process_bus.hpp"
#include "master/conformance/suite.hpp"
#include "slave/firmware.hpp"

namespace ecat::master::test {
namespace {

using conformance::Verdict;

constexpr std::uint8_t kData = 3, kAck = 4, kErr = 5, kBusy = 6;

// The real FoE service, each reply rewritten by `rewrite` (its bytes from the
// FoE header on).
class RewrittenFoe final : public ecat::coe::MailboxService {
 public:
  using Rewrite = std::function<void(Bytes reply)>;
  RewrittenFoe(ecat::coe::MailboxService& inner, Rewrite rewrite) : inner_(inner), rewrite_(std::move(rewrite)) {}
  ecat::coe::MailboxType type() const noexcept override { return inner_.type(); }
  bool active_in(od::EsmState s) const noexcept override { return inner_.active_in(s); }
  Expected<std::size_t, ecat::coe::MailboxError> handle(ConstBytes request, Bytes reply, od::EsmState state) noexcept override {
    auto n = inner_.handle(request, reply, state);
    if (n && *n >= 6) rewrite_(reply.first(*n));
    return n;
  }
  std::size_t next_reply(Bytes reply) noexcept override { return inner_.next_reply(reply); }
  void set_sizes(std::size_t rq, std::size_t rp) noexcept override { inner_.set_sizes(rq, rp); }
  bool busy() const noexcept override { return inner_.busy(); }
  void reset() noexcept override { inner_.reset(); }

 private:
  ecat::coe::MailboxService& inner_;
  Rewrite rewrite_;
};

std::uint32_t value_of(Bytes r) { return load_le<std::uint32_t>(r.data() + 2); }
void set_value(Bytes r, std::uint32_t v) { store_le<std::uint32_t>(r.data() + 2, v); }

struct FoeBreakage {
  const char* case_name;
  RewrittenFoe::Rewrite rewrite;
};

std::vector<FoeBreakage> foe_breakages() {
  return {
      {"foe.write_ack_numbers", [](Bytes r) {
         if (r[0] == kAck && value_of(r) > 0) set_value(r, value_of(r) + 1);
       }},
      {"foe.read_back", [](Bytes r) {
         if (r[0] == kData && r.size() > 6) r[6] ^= 0xFF;
       }},
      {"foe.read_packet_numbers", [](Bytes r) {
         if (r[0] == kData) set_value(r, value_of(r) + 1);
       }},
      {"foe.read_not_found", [](Bytes r) {
         if (r[0] == kErr && value_of(r) == 0x8001) set_value(r, 0x8000);
       }},
      {"foe.write_wrong_packet_number", [](Bytes r) {
         if (r[0] == kErr && value_of(r) == 0x8005) {
           r[0] = kAck;
           set_value(r, 2);
         }
       }},
      // The denied file is reported missing instead.
      {"foe.access_denied", [](Bytes r) {
         if (r[0] == kErr && value_of(r) == 0x8002) set_value(r, 0x8001);
       }},
      // A wrong password is taken.
      {"foe.wrong_password", [](Bytes r) {
         if (r[0] == kErr && value_of(r) == 0x800A) {
           r[0] = kAck;
           set_value(r, 0);
         }
       }},
      // A full store answers "not defined".
      {"foe.write_disk_full", [](Bytes r) {
         if (r[0] == kErr && value_of(r) == 0x8003) set_value(r, 0x8000);
       }},
      // Done beyond Entire (3 of 2).
      {"foe.busy_then_complete", [](Bytes r) {
         if (r[0] == kBusy) store_le<std::uint16_t>(r.data() + 2, 3);
       }},
  };
}

class ElmoFoe : public testing::Test {
 protected:
  void SetUp() override {
    auto twin = esi::import_twin(std::string(ECAT_SOURCE_DIR) + "/tests/data/esi-vendor/elmo-gold-ecat.xml", {});
    ASSERT_TRUE(twin) << twin.error().to_string();
    dir_ = std::filesystem::path(::testing::TempDir()) / ("elmo-foe-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
    file_ = (dir_ / "elmo.device.xml").string();
    std::ofstream(file_) << esi::write_device_xml(*twin);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::vector<conformance::Report> run(InProcessBus& bus, const std::string& filter, bool busy = true) {
    Master master(bus.transport, bus.clock);
    conformance::SuiteOptions options;
    options.wait = [&bus](Nanoseconds d) { bus.wait(d); };
    options.filter = filter;
    options.foe_password = kPassword;
    options.foe_denied_file = ".denied";  // coe::FoeServer denies names starting with '.'
    options.foe_capacity = kCapacity;
    options.foe_busy = busy;
    return conformance::run_suite(master, options);
  }
  // The twin's files need kPassword; its state directory holds kCapacity
  // bytes; each read/write request is answered BUSY twice (every case copes).
  slave::SlaveOptions options(std::uint16_t busy = kBusyReplies) const {
    slave::SlaveOptions o;
    o.state_dir = dir_ / "state";
    std::filesystem::create_directories(o.state_dir);
    o.foe_password = kPassword;
    o.foe_busy = busy;
    o.state_quota = std::make_shared<ecat::coe::StorageQuota>(ecat::coe::StorageQuota::Limits{kCapacity, 64});
    return o;
  }
  static constexpr std::uint32_t kPassword = 0x00C0FFEE;
  static constexpr std::size_t kCapacity = 4096;
  static constexpr std::uint16_t kBusyReplies = 2;

  std::filesystem::path dir_;
  std::string file_;
};

TEST_F(ElmoFoe, EveryFoeCasePasses) {
  InProcessBus bus;
  ASSERT_TRUE(bus.add(file_, 1, slave::PdiKind::Direct, options()));
  const auto reports = run(bus, "foe.");
  ASSERT_EQ(reports.size(), conformance::foe_cases().size());
  for (const auto& r : reports) {
    EXPECT_EQ(r.result.verdict, Verdict::Pass) << r.name << ": expected " << r.result.expected << ", seen " << r.result.seen;
  }
}

// A slave that never answers BUSY fails the case when the suite is told it does.
TEST_F(ElmoFoe, BusyCaseFailsWithoutBusy) {
  InProcessBus bus;
  ASSERT_TRUE(bus.add(file_, 1, slave::PdiKind::Direct, options(0)));
  const auto reports = run(bus, "foe.busy_then_complete");
  ASSERT_EQ(reports.size(), 1u);
  EXPECT_EQ(reports[0].result.verdict, Verdict::Fail);
  EXPECT_EQ(reports[0].result.seen.rfind("no BUSY, then ", 0), 0u) << reports[0].result.seen;
  // And it skips when the suite is not told, whatever the slave does.
  const auto skipped = run(bus, "foe.busy_then_complete", false);
  ASSERT_EQ(skipped.size(), 1u);
  EXPECT_EQ(skipped[0].result.verdict, Verdict::Skip);
}

// Without FoE (generic servo: foe="false") each case skips with the SII's answer.
TEST(ConformanceFoe, SkipsWithoutFoe) {
  InProcessBus bus;
  ASSERT_TRUE(bus.add(device_path("generic-servo.xml")));
  Master master(bus.transport, bus.clock);
  conformance::SuiteOptions options;
  options.filter = "foe.";
  for (const auto& r : conformance::run_suite(master, options)) {
    EXPECT_EQ(r.result.verdict, Verdict::Skip) << r.name;
    EXPECT_EQ(r.result.seen, "no FoE in the SII mailbox protocols");
  }
}

TEST_F(ElmoFoe, EachCaseFailsOnABrokenFoe) {
  for (const auto& broken : foe_breakages()) {
    InProcessBus bus;
    ASSERT_TRUE(bus.add(file_, 1, slave::PdiKind::Direct, options()));
    auto& mailbox = bus.chain()[0].firmware().coe().mailbox();
    // Swap in a wrapper around the real service (it stays owned by the CoE server).
    struct Probe final : ecat::coe::MailboxService {
      ecat::coe::MailboxType type() const noexcept override { return ecat::coe::MailboxType::FoE; }
      Expected<std::size_t, ecat::coe::MailboxError> handle(ConstBytes, Bytes, od::EsmState) noexcept override { return 0; }
    } probe;
    ecat::coe::MailboxService* real = mailbox.replace_service(probe);
    ASSERT_NE(real, nullptr);
    RewrittenFoe wrapped(*real, broken.rewrite);
    mailbox.replace_service(wrapped);
    const auto reports = run(bus, broken.case_name);
    ASSERT_EQ(reports.size(), 1u) << broken.case_name;
    EXPECT_EQ(reports[0].result.verdict, Verdict::Fail)
        << broken.case_name << ": expected " << reports[0].result.expected << ", seen " << reports[0].result.seen;
  }
}

TEST(ConformanceFoe, EveryCaseHasABreakage) {
  expect_every_case_broken(conformance::foe_cases(), foe_breakages());
}

}  // namespace

std::vector<std::string> proven_foe_cases() {
  return case_names(foe_breakages());
}

}  // namespace ecat::master::test
