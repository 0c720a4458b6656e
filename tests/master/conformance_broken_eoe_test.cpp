// The EoE conformance cases against the Elmo Gold twin (tests/data/esi-vendor:
// its ESI lists EoE; the built-in responder answers ARP and ping): every case
// passes; and each case fails when the slave's EoE service is wrapped in one
// that breaks what the case checks (issue 31 item 3).
#include <gtest/gtest.h>

#include "conformance_proofs.hpp"

#include <unistd.h>

#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>

#include "coe/mailbox_service.hpp"
#include "esi/esi_writer_device_xml.hpp"
#include "esi/twin_import.hpp"
#include "in_process_bus.hpp"
#include "master/conformance/suite.hpp"
#include "slave/firmware.hpp"

namespace ecat::master::test {
namespace {

using conformance::Verdict;

constexpr std::uint16_t kLastFragment = 1u << 8;

// The real EoE service; each request, reply and unsolicited fragment can be
// rewritten (bytes from the EoE header on).
class RewrittenEoe final : public ecat::coe::MailboxService {
 public:
  using Rewrite = std::function<void(Bytes)>;
  struct Rewrites {
    Rewrite request, reply, output;
  };
  RewrittenEoe(ecat::coe::MailboxService& inner, Rewrites r) : inner_(inner), r_(std::move(r)) {}
  ecat::coe::MailboxType type() const noexcept override { return inner_.type(); }
  bool active_in(od::EsmState s) const noexcept override { return inner_.active_in(s); }
  Expected<std::size_t, ecat::coe::MailboxError> handle(ConstBytes request, Bytes reply, od::EsmState state) noexcept override {
    std::vector<std::uint8_t> copy(request.begin(), request.end());
    if (r_.request && copy.size() >= 4) r_.request(copy);
    auto n = inner_.handle(copy, reply, state);
    if (n && *n >= 4 && r_.reply) r_.reply(reply.first(*n));
    return n;
  }
  std::size_t next_reply(Bytes reply) noexcept override { return inner_.next_reply(reply); }
  bool has_output() const noexcept override { return inner_.has_output(); }
  bool starts_messages() const noexcept override { return inner_.starts_messages(); }
  std::size_t next_output(Bytes out) noexcept override {
    const std::size_t n = inner_.next_output(out);
    if (n >= 4 && r_.output) r_.output(out.first(n));
    return n;
  }
  void set_sizes(std::size_t rq, std::size_t rp) noexcept override { inner_.set_sizes(rq, rp); }
  bool busy() const noexcept override { return inner_.busy(); }
  void reset() noexcept override { inner_.reset(); }

 private:
  ecat::coe::MailboxService& inner_;
  Rewrites r_;
};

std::uint8_t type_of(Bytes m) { return static_cast<std::uint8_t>(m[0] & 0x0F); }
std::uint16_t word1(Bytes m) { return load_le<std::uint16_t>(m.data() + 2); }
void set_word1(Bytes m, std::uint16_t v) { store_le<std::uint16_t>(m.data() + 2, v); }

struct EoeBreakage {
  const char* case_name;
  RewrittenEoe::Rewrites rewrites;
};

std::vector<EoeBreakage> eoe_breakages() {
  return {
      // Set IP Parameter answered with "unspecified error".
      {"eoe.set_ip_parameter", {nullptr, [](Bytes r) {
                                  if (type_of(r) == 3) set_word1(r, 0x0001);
                                }, nullptr}},
      // Get IP Parameter reports another IP (last byte of the address changed).
      {"eoe.get_ip_parameter", {nullptr, [](Bytes r) {
                                  if (type_of(r) == 7 && r.size() >= 4 + 4 + 6 + 4) r[4 + 4 + 6] ^= 0x01;
                                }, nullptr}},
      {"eoe.set_address_filter", {nullptr, [](Bytes r) {
                                    if (type_of(r) == 5) set_word1(r, 0x0001);
                                  }, nullptr}},
      // An unknown frame type is answered "success".
      {"eoe.unknown_frame_type", {nullptr, [](Bytes r) {
                                    if (word1(r) == 0x0002) set_word1(r, 0x0000);
                                  }, nullptr}},
      // The reply's last fragment has its last data byte changed.
      {"eoe.fragment_reassembly", {nullptr, nullptr, [](Bytes m) {
                                     if (type_of(m) == 0 && (load_le<std::uint16_t>(m.data()) & kLastFragment) != 0 && m.size() > 4) {
                                       m[m.size() - 1] ^= 0x5A;
                                     }
                                   }}},
      // Fragment numbers counted from 1.
      {"eoe.reply_fragment_numbering", {nullptr, nullptr, [](Bytes m) {
                                          if (type_of(m) == 0) set_word1(m, static_cast<std::uint16_t>(word1(m) + 1));
                                        }}},
      // A slave that does not look at fragment numbers: each fragment is
      // renumbered as the next one expected.
      {"eoe.bad_fragment_number_dropped", {[next = std::make_shared<std::uint16_t>(0)](Bytes q) {
                                             if (type_of(q) != 0) return;
                                             if ((word1(q) & 0x3F) == 0) *next = 0;
                                             set_word1(q, static_cast<std::uint16_t>((word1(q) & ~0x3Fu) | (*next & 0x3Fu)));
                                             ++*next;
                                           }, nullptr, nullptr}},
  };
}

class ElmoEoe : public testing::Test {
 protected:
  void SetUp() override {
    auto twin = esi::import_twin(std::string(ECAT_SOURCE_DIR) + "/tests/data/esi-vendor/elmo-gold-ecat.xml", {});
    ASSERT_TRUE(twin) << twin.error().to_string();
    dir_ = std::filesystem::path(::testing::TempDir()) / ("elmo-eoe-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
    file_ = (dir_ / "elmo.device.xml").string();
    std::ofstream(file_) << esi::write_device_xml(*twin);
  }
  void TearDown() override { std::filesystem::remove_all(dir_); }

  std::vector<conformance::Report> run(InProcessBus& bus, const std::string& filter) {
    Master master(bus.transport, bus.clock);
    conformance::SuiteOptions options;
    options.wait = [&bus](Nanoseconds d) { bus.wait(d); };
    options.filter = filter;
    return conformance::run_suite(master, options);
  }

  std::filesystem::path dir_;
  std::string file_;
};

TEST_F(ElmoEoe, EveryEoeCasePasses) {
  InProcessBus bus;
  ASSERT_TRUE(bus.add(file_));
  const auto reports = run(bus, "eoe.");
  ASSERT_EQ(reports.size(), conformance::eoe_cases().size());
  for (const auto& r : reports) {
    EXPECT_EQ(r.result.verdict, Verdict::Pass) << r.name << ": expected " << r.result.expected << ", seen " << r.result.seen;
  }
}

// Without EoE (generic servo) each case skips with the SII's answer.
TEST(ConformanceEoe, SkipsWithoutEoe) {
  InProcessBus bus;
  ASSERT_TRUE(bus.add(device_path("generic-servo.xml")));
  Master master(bus.transport, bus.clock);
  conformance::SuiteOptions options;
  options.filter = "eoe.";
  const auto reports = conformance::run_suite(master, options);
  EXPECT_EQ(reports.size(), conformance::eoe_cases().size());
  for (const auto& r : reports) {
    EXPECT_EQ(r.result.verdict, Verdict::Skip) << r.name;
    EXPECT_EQ(r.result.seen, "no EoE in the SII mailbox protocols");
  }
}

TEST_F(ElmoEoe, EachCaseFailsOnABrokenEoe) {
  for (const auto& broken : eoe_breakages()) {
    InProcessBus bus;
    ASSERT_TRUE(bus.add(file_));
    auto& mailbox = bus.chain()[0].firmware().coe().mailbox();
    struct Probe final : ecat::coe::MailboxService {
      ecat::coe::MailboxType type() const noexcept override { return ecat::coe::MailboxType::EoE; }
      Expected<std::size_t, ecat::coe::MailboxError> handle(ConstBytes, Bytes, od::EsmState) noexcept override { return 0; }
    } probe;
    ecat::coe::MailboxService* real = mailbox.replace_service(probe);
    ASSERT_NE(real, nullptr);
    RewrittenEoe wrapped(*real, broken.rewrites);
    mailbox.replace_service(wrapped);
    const auto reports = run(bus, broken.case_name);
    ASSERT_EQ(reports.size(), 1u) << broken.case_name;
    EXPECT_EQ(reports[0].result.verdict, Verdict::Fail)
        << broken.case_name << ": expected " << reports[0].result.expected << ", seen " << reports[0].result.seen;
  }
}

TEST(ConformanceEoe, EveryCaseHasABreakage) {
  expect_every_case_broken(conformance::eoe_cases(), eoe_breakages());
}

}  // namespace

std::vector<std::string> proven_eoe_cases() {
  return case_names(eoe_breakages());
}

}  // namespace ecat::master::test
