// Each CiA 402 / emergency conformance case against a generic servo whose
// firmware misbehaves in exactly the way the case checks for (issue 31 item
// 3: every case is proven to fail on a slave that breaks it). The drive
// application is wrapped in one that rewrites the controlword the drive sees
// or the values it publishes (statusword, 6061h, actuals, 603Fh, 1001h), or
// the drive's SDO hooks are removed; the case must then report Fail.
#include <gtest/gtest.h>

#include <algorithm>
#include <functional>
#include <utility>

#include "ds402/objects.hpp"
#include "conformance_proofs.hpp"
#include "in_process_bus.hpp"
#include "master/conformance/cia402_axis.hpp"
#include "master/conformance/suite.hpp"
#include "slave/application.hpp"
#include "slave/firmware.hpp"

namespace ecat::master::test {
namespace {

using conformance::Verdict;
using conformance::cia402::State;
namespace c402 = conformance::cia402;

// The drive's cycle between two rewrites of the dictionary: `before` sees
// the outputs the master sent (6040h, 6060h ...), `after` the values the
// drive published, before they go to SM3.
class Tampered final : public slave::Application {
 public:
  using Rewrite = std::function<void(ecat::coe::ObjectStore&)>;
  Tampered(std::unique_ptr<slave::Application> inner, ecat::coe::ObjectStore& store, Rewrite before, Rewrite after)
      : inner_(std::move(inner)), store_(store), before_(std::move(before)), after_(std::move(after)) {}
  void cycle(Nanoseconds dt, bool outputs_valid) noexcept override {
    if (before_) before_(store_);
    inner_->cycle(dt, outputs_valid);
    if (after_) after_(store_);
  }
  void on_state(esc::AlState state) noexcept override { inner_->on_state(state); }
  ds402::Drive* drive(std::size_t axis) noexcept override { return inner_->drive(axis); }

 private:
  std::unique_ptr<slave::Application> inner_;
  ecat::coe::ObjectStore& store_;
  Rewrite before_, after_;
};

State state_of(const ecat::coe::ObjectStore& s) { return c402::decode(s.get<std::uint16_t>(c402::kStatusword, 0)); }
std::uint16_t cw_of(const ecat::coe::ObjectStore& s) { return s.get<std::uint16_t>(c402::kControlword, 0); }

// Rewrites the controlword `from` to `to` while the drive is in `in`.
Tampered::Rewrite command_swap(State in, std::uint16_t from, std::uint16_t to) {
  return [=](ecat::coe::ObjectStore& s) {
    if (state_of(s) == in && cw_of(s) == from) (void)s.set<std::uint16_t>(c402::kControlword, 0, to);
  };
}

struct Breakage {
  const char* case_name;
  Tampered::Rewrite before;
  Tampered::Rewrite after;
  std::vector<std::uint16_t> unhook;  // SDO hooks removed (the drive's range checks)
};

std::vector<Breakage> breakages() {
  std::vector<Breakage> b;
  // Starts in Ready to switch on, with no shutdown command.
  b.push_back({"cia402.startup_switch_on_disabled", nullptr,
               [](ecat::coe::ObjectStore& s) {
                 if (state_of(s) == State::SwitchOnDisabled) (void)s.set<std::uint16_t>(c402::kStatusword, 0, 0x0221);
               },
               {}});
  b.push_back({"cia402.t2_shutdown", command_swap(State::SwitchOnDisabled, c402::kShutdown, c402::kDisableVoltage), nullptr, {}});
  b.push_back({"cia402.t3_switch_on", command_swap(State::ReadyToSwitchOn, c402::kSwitchOn, c402::kShutdown), nullptr, {}});
  b.push_back({"cia402.t4_enable_operation", command_swap(State::SwitchedOn, c402::kEnableOperation, c402::kSwitchOn), nullptr, {}});
  b.push_back({"cia402.t5_disable_operation", command_swap(State::OperationEnabled, c402::kSwitchOn, c402::kEnableOperation), nullptr, {}});
  b.push_back({"cia402.t6_shutdown_from_switched_on", command_swap(State::SwitchedOn, c402::kShutdown, c402::kSwitchOn), nullptr, {}});
  b.push_back({"cia402.t7_disable_voltage_from_ready", command_swap(State::ReadyToSwitchOn, c402::kDisableVoltage, c402::kShutdown), nullptr, {}});
  b.push_back({"cia402.t7_quick_stop_from_ready", command_swap(State::ReadyToSwitchOn, c402::kQuickStop, c402::kShutdown), nullptr, {}});
  b.push_back({"cia402.t8_shutdown_from_enabled", command_swap(State::OperationEnabled, c402::kShutdown, c402::kEnableOperation), nullptr, {}});
  b.push_back({"cia402.t9_disable_voltage_from_enabled", command_swap(State::OperationEnabled, c402::kDisableVoltage, c402::kEnableOperation), nullptr, {}});
  b.push_back({"cia402.t10_disable_voltage_from_switched_on", command_swap(State::SwitchedOn, c402::kDisableVoltage, c402::kSwitchOn), nullptr, {}});
  b.push_back({"cia402.t10_quick_stop_from_switched_on", command_swap(State::SwitchedOn, c402::kQuickStop, c402::kSwitchOn), nullptr, {}});
  b.push_back({"cia402.t11_quick_stop_per_605a", command_swap(State::OperationEnabled, c402::kQuickStop, c402::kEnableOperation), nullptr, {}});
  b.push_back({"cia402.t12_disable_voltage_from_quick_stop", command_swap(State::QuickStopActive, c402::kDisableVoltage, c402::kQuickStop), nullptr, {}});
  b.push_back({"cia402.t16_enable_from_quick_stop", command_swap(State::QuickStopActive, c402::kEnableOperation, c402::kQuickStop), nullptr, {}});
  b.push_back({"cia402.refused_switch_on_from_disabled", command_swap(State::SwitchOnDisabled, c402::kSwitchOn, c402::kShutdown), nullptr, {}});
  b.push_back({"cia402.refused_enable_from_disabled", command_swap(State::SwitchOnDisabled, c402::kEnableOperation, c402::kShutdown), nullptr, {}});
  b.push_back({"cia402.refused_fault_reset_without_fault",
               command_swap(State::ReadyToSwitchOn, c402::kFaultReset | c402::kShutdown, c402::kDisableVoltage), nullptr, {}});
  // The fault is there but 603Fh never says which.
  b.push_back({"cia402.t13_t14_fault_on_following_error", nullptr,
               [](ecat::coe::ObjectStore& s) { (void)s.set<std::uint16_t>(c402::kErrorCode, 0, 0); }, {}});
  // Enable operation in Fault shows Operation enabled.
  b.push_back({"cia402.fault_refuses_enable", nullptr,
               [](ecat::coe::ObjectStore& s) {
                 if (state_of(s) == State::Fault && cw_of(s) == c402::kEnableOperation) {
                   (void)s.set<std::uint16_t>(c402::kStatusword, 0, 0x0237);
                 }
               },
               {}});
  b.push_back({"cia402.t15_fault_reset", command_swap(State::Fault, c402::kFaultReset, c402::kDisableVoltage), nullptr, {}});
  // 1001h no longer what the emergency carried.
  b.push_back({"cia402.fault_emergency", nullptr,
               [](ecat::coe::ObjectStore& s) { (void)s.set<std::uint8_t>(c402::kErrorRegister, 0, 0); }, {}});
  // 1001h shows the class bit but not the generic error bit.
  b.push_back({"cia402.fault_error_register_generic_bit", nullptr,
               [](ecat::coe::ObjectStore& s) {
                 const auto reg = s.get<std::uint8_t>(c402::kErrorRegister, 0);
                 (void)s.set<std::uint8_t>(c402::kErrorRegister, 0, static_cast<std::uint8_t>(reg & ~0x01u));
               },
               {}});
  // 1001h keeps the generic error bit after the reset.
  b.push_back({"cia402.fault_reset_emergency", nullptr,
               [](ecat::coe::ObjectStore& s) {
                 if (state_of(s) == State::SwitchOnDisabled) (void)s.set<std::uint8_t>(c402::kErrorRegister, 0, 0x01);
               },
               {}});
  // 6061h never shows CSV.
  b.push_back({"cia402.modes_display_follows_6060", nullptr,
               [](ecat::coe::ObjectStore& s) {
                 if (s.get<std::int8_t>(c402::kModesDisplay, 0) == c402::kCsv) (void)s.set<std::int8_t>(c402::kModesDisplay, 0, c402::kCsp);
               },
               {}});
  // A mode 6502h does not list is taken and shown.
  b.push_back({"cia402.mode_not_in_6502_refused", nullptr,
               [](ecat::coe::ObjectStore& s) { (void)s.set<std::int8_t>(c402::kModesDisplay, 0, s.get<std::int8_t>(c402::kModes, 0)); },
               {c402::kModes}});
  // CSP: bit 12 ("follows the command value") never set.
  b.push_back({"cia402.csp_follows_set_point", nullptr,
               [](ecat::coe::ObjectStore& s) {
                 const auto sw = s.get<std::uint16_t>(c402::kStatusword, 0);
                 (void)s.set<std::uint16_t>(c402::kStatusword, 0, static_cast<std::uint16_t>(sw & ~c402::kBitFollowsCommand));
               },
               {}});
  // CSV: the actual velocity reads half of what it is.
  b.push_back({"cia402.csv_follows_set_point", nullptr,
               [](ecat::coe::ObjectStore& s) {
                 (void)s.set<std::int32_t>(c402::kVelocityActual, 0, s.get<std::int32_t>(c402::kVelocityActual, 0) / 2);
               },
               {}});
  // CST: the actual torque has the wrong sign.
  b.push_back({"cia402.cst_follows_set_point", nullptr,
               [](ecat::coe::ObjectStore& s) {
                 (void)s.set<std::int16_t>(c402::kTorqueActual, 0, static_cast<std::int16_t>(-s.get<std::int16_t>(c402::kTorqueActual, 0)));
               },
               {}});
  // Option codes taken whatever their value.
  b.push_back({"cia402.option_605a_reserved_refused", nullptr, nullptr, {c402::kQuickStopOption}});
  b.push_back({"cia402.option_605b_reserved_refused", nullptr, nullptr, {c402::kShutdownOption}});
  b.push_back({"cia402.option_605c_reserved_refused", nullptr, nullptr, {c402::kDisableOperationOption}});
  b.push_back({"cia402.option_605d_reserved_refused", nullptr, nullptr, {c402::kHaltOption}});
  b.push_back({"cia402.option_605e_reserved_refused", nullptr, nullptr, {c402::kFaultReactionOption}});
  return b;
}

class BrokenDrive : public testing::TestWithParam<std::size_t> {};

TEST_P(BrokenDrive, CaseFails) {
  const auto all = breakages();
  const Breakage& broken = all.at(GetParam());
  InProcessBus bus;
  ASSERT_TRUE(bus.add(device_path("generic-servo.xml")));
  slave::Firmware& fw = bus.chain()[0].firmware();
  ecat::coe::ObjectStore& store = fw.coe().objects();
  fw.set_application(std::make_unique<Tampered>(fw.take_application(), store, broken.before, broken.after));
  for (std::uint16_t index : broken.unhook) store.set_hooks(index, nullptr);
  Master master(bus.transport, bus.clock);
  conformance::SuiteOptions options;
  options.wait = [&bus](Nanoseconds d) { bus.wait(d); };
  options.filter = broken.case_name;
  const auto reports = conformance::run_suite(master, options);
  ASSERT_EQ(reports.size(), 1u) << broken.case_name;
  EXPECT_EQ(reports[0].name, broken.case_name);
  EXPECT_EQ(reports[0].result.verdict, Verdict::Fail)
      << broken.case_name << ": expected " << reports[0].result.expected << ", seen " << reports[0].result.seen;
}

INSTANTIATE_TEST_SUITE_P(Cases, BrokenDrive, testing::Range<std::size_t>(0, breakages().size()),
                         [](const testing::TestParamInfo<std::size_t>& p) {
                           std::string n = breakages().at(p.param).case_name;
                           for (char& c : n) {
                             if (c == '.') c = '_';
                           }
                           return n;
                         });

// Every CiA 402 case of the suite has a breakage above.
TEST(BrokenDrive, EveryCia402CaseIsCovered) {
  expect_every_case_broken(conformance::cia402_cases(), breakages());
}

}  // namespace

std::vector<std::string> proven_drive_cases() {
  return case_names(breakages());
}

}  // namespace ecat::master::test

namespace ecat::master::test {
namespace {

// 10F3h's hooks (coe::DiagnosisHistory) wrapped: every access goes to them,
// and a read is then rewritten the way a broken firmware would answer.
class RewrittenReads final : public ecat::coe::ObjectHooks {
 public:
  using Rewrite = std::function<void(ecat::coe::ObjectStore&, std::uint8_t subindex)>;
  RewrittenReads(ecat::coe::ObjectHooks* inner, Rewrite rewrite) : inner_(inner), rewrite_(std::move(rewrite)) {}
  void on_read(ecat::coe::ObjectStore& store, std::uint16_t index, std::uint8_t subindex) noexcept override {
    if (inner_) inner_->on_read(store, index, subindex);
    rewrite_(store, subindex);
  }
  Expected<void, ecat::coe::SdoAbort> on_write(ecat::coe::ObjectStore& store, const ecat::coe::WriteRequest& request) noexcept override {
    return inner_ ? inner_->on_write(store, request) : Expected<void, ecat::coe::SdoAbort>{};
  }
  void after_write(ecat::coe::ObjectStore& store, std::uint16_t index, std::uint8_t subindex) noexcept override {
    if (inner_) inner_->after_write(store, index, subindex);
  }

 private:
  ecat::coe::ObjectHooks* inner_;
  Rewrite rewrite_;
};

constexpr std::uint16_t kHistory = 0x10F3;

struct HistoryBreakage {
  const char* case_name;
  RewrittenReads::Rewrite rewrite;  // null: the hooks are removed (no checks at all)
};

std::vector<HistoryBreakage> history_breakages() {
  return {
      {"diag.10f3_layout", [](ecat::coe::ObjectStore& s, std::uint8_t sub) {
         if (sub == 1) (void)s.set<std::uint8_t>(kHistory, 1, 0);
       }},
      {"diag.10f3_newest_message", [](ecat::coe::ObjectStore& s, std::uint8_t sub) {
         if (sub == 2 && s.get<std::uint8_t>(kHistory, 2) != 0) (void)s.set<std::uint8_t>(kHistory, 2, 3);
       }},
      // Messages lose their time stamp and parameters (8 bytes).
      {"diag.10f3_message_format", [](ecat::coe::ObjectStore& s, std::uint8_t sub) {
         if (sub < 6) return;
         std::vector<std::uint8_t> head(8, 0);
         const auto* slot = std::as_const(s).slot(kHistory, sub);
         if (slot == nullptr) return;
         const auto v = s.value(*slot);
         std::copy_n(v.begin(), std::min<std::size_t>(v.size(), head.size()), head.begin());
         (void)s.assign(kHistory, sub, head);
       }},
      // 10F3h:04 stays 1.
      {"diag.10f3_new_messages_flag", [](ecat::coe::ObjectStore& s, std::uint8_t sub) {
         if (sub == 4) (void)s.set<std::uint8_t>(kHistory, 4, 1);
       }},
      // The acknowledge is taken but 10F3h:03 reads 0.
      {"diag.10f3_acknowledge", [](ecat::coe::ObjectStore& s, std::uint8_t sub) {
         if (sub == 3) (void)s.set<std::uint8_t>(kHistory, 3, 0);
       }},
      {"diag.10f3_refuses_acknowledge_of_non_message", nullptr},
  };
}

class BrokenHistory : public testing::TestWithParam<std::size_t> {};

TEST_P(BrokenHistory, CaseFails) {
  const auto all = history_breakages();
  const HistoryBreakage& broken = all.at(GetParam());
  InProcessBus bus;
  ASSERT_TRUE(bus.add(device_path("generic-servo.xml")));
  ecat::coe::ObjectStore& store = bus.chain()[0].firmware().coe().objects();
  RewrittenReads hooks(store.hooks(kHistory), broken.rewrite);
  store.set_hooks(kHistory, broken.rewrite ? &hooks : nullptr);
  Master master(bus.transport, bus.clock);
  conformance::SuiteOptions options;
  options.wait = [&bus](Nanoseconds d) { bus.wait(d); };
  options.filter = broken.case_name;
  const auto reports = conformance::run_suite(master, options);
  ASSERT_EQ(reports.size(), 1u) << broken.case_name;
  EXPECT_EQ(reports[0].result.verdict, Verdict::Fail)
      << broken.case_name << ": expected " << reports[0].result.expected << ", seen " << reports[0].result.seen;
}

INSTANTIATE_TEST_SUITE_P(Cases, BrokenHistory, testing::Range<std::size_t>(0, history_breakages().size()),
                         [](const testing::TestParamInfo<std::size_t>& p) {
                           std::string n = history_breakages().at(p.param).case_name;
                           for (char& c : n) {
                             if (c == '.') c = '_';
                           }
                           return n;
                         });

TEST(BrokenHistory, EveryCaseIsCovered) {
  expect_every_case_broken(conformance::emergency_cases(), history_breakages());
}

}  // namespace

std::vector<std::string> proven_history_cases() {
  return case_names(history_breakages());
}

}  // namespace ecat::master::test

#include <unistd.h>

#include <filesystem>
#include <fstream>

#include "esi/device_loader.hpp"
#include "esi/esi_writer_device_xml.hpp"

namespace ecat::master::test {
namespace {

// 1003h: the generic servo with a pre-defined error field of 4 entries
// (CiA 301 §7.5.2.3; coe::ErrorField gives it its behaviour). Each case
// passes on it, and fails when the field is broken on purpose.
constexpr std::uint16_t kErrorField = 0x1003;

class ServoWithErrorField : public testing::Test {
 protected:
  void SetUp() override {
    auto d = esi::load_device_file(device_path("generic-servo.xml"));
    ASSERT_TRUE(d);
    od::Object o;
    o.index = kErrorField;
    o.name = "Pre-defined error field";
    o.code = od::ObjectCode::Array;
    o.type = od::DataType::Unsigned32;
    auto entry = [](std::uint8_t sub, od::DataType type, std::uint16_t bits, std::uint16_t access) {
      od::Entry e;
      e.subindex = sub;
      e.name = sub == 0 ? "Number of errors" : "Standard error field";
      e.type = type;
      e.bit_length = bits;
      e.access.bits = access;
      e.default_value.assign(bits / 8, 0);
      return e;
    };
    o.entries.push_back(entry(0, od::DataType::Unsigned8, 8, od::Access::kRw));
    for (std::uint8_t k = 1; k <= 4; ++k) o.entries.push_back(entry(k, od::DataType::Unsigned32, 32, od::Access::kRo));
    ASSERT_TRUE(d->dictionary.put(o));
    dir_ = std::filesystem::path(::testing::TempDir()) / ("servo-1003-" + std::to_string(::getpid()));
    std::filesystem::create_directories(dir_);
    file_ = (dir_ / "servo.device.xml").string();
    std::ofstream(file_) << esi::write_device_xml(*d);
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

// Hooks that refuse a write of 1003h:00 as read-only (a field that cannot be cleared).
class RefuseWrites final : public ecat::coe::ObjectHooks {
 public:
  Expected<void, ecat::coe::SdoAbort> on_write(ecat::coe::ObjectStore&, const ecat::coe::WriteRequest&) noexcept override {
    return fail(ecat::coe::SdoAbort::ReadOnly);
  }
};

struct FieldBreakage {
  const char* case_name;
  Tampered::Rewrite after;  // on the drive's cycle
  bool unhook;              // 1003h without its hooks (any value taken)
  bool refuse_writes;
};

std::vector<FieldBreakage> field_breakages() {
  return {
      // 1003h:01 keeps a code that is not the fault's.
      {"emcy.1003h_records_error", [](ecat::coe::ObjectStore& s) {
         if (s.get<std::uint32_t>(kErrorField, 1) != 0) (void)s.set<std::uint32_t>(kErrorField, 1, 0x1000);
       }, false, false},
      {"emcy.1003h_write_zero_clears", nullptr, false, true},
      {"emcy.1003h_write_nonzero_refused", nullptr, true, false},
  };
}

TEST_F(ServoWithErrorField, EveryCasePasses) {
  InProcessBus bus;
  ASSERT_TRUE(bus.add(file_));
  const auto reports = run(bus, "emcy.1003h");
  ASSERT_EQ(reports.size(), conformance::error_field_cases().size());
  for (const auto& r : reports) {
    EXPECT_EQ(r.result.verdict, Verdict::Pass) << r.name << ": expected " << r.result.expected << ", seen " << r.result.seen;
  }
}

TEST_F(ServoWithErrorField, EachCaseFailsOnABrokenField) {
  for (const auto& broken : field_breakages()) {
    InProcessBus bus;
    ASSERT_TRUE(bus.add(file_));
    slave::Firmware& fw = bus.chain()[0].firmware();
    ecat::coe::ObjectStore& store = fw.coe().objects();
    if (broken.after) fw.set_application(std::make_unique<Tampered>(fw.take_application(), store, nullptr, broken.after));
    RefuseWrites refuse;
    if (broken.unhook) store.set_hooks(kErrorField, nullptr);
    if (broken.refuse_writes) store.set_hooks(kErrorField, &refuse);
    const auto reports = run(bus, broken.case_name);
    ASSERT_EQ(reports.size(), 1u) << broken.case_name;
    EXPECT_EQ(reports[0].result.verdict, Verdict::Fail)
        << broken.case_name << ": expected " << reports[0].result.expected << ", seen " << reports[0].result.seen;
  }
}

// Without 1003h (the shipped generic servo) the cases skip with the abort.
TEST(ErrorFieldCases, SkipWithout1003h) {
  InProcessBus bus;
  ASSERT_TRUE(bus.add(device_path("generic-servo.xml")));
  Master master(bus.transport, bus.clock);
  conformance::SuiteOptions options;
  options.filter = "emcy.1003h";
  for (const auto& r : conformance::run_suite(master, options)) {
    EXPECT_EQ(r.result.verdict, Verdict::Skip) << r.name;
    EXPECT_EQ(r.result.seen.rfind("no 1003h: ", 0), 0u) << r.result.seen;
  }
}

TEST(ErrorFieldCases, EveryCaseIsCovered) {
  expect_every_case_broken(conformance::error_field_cases(), field_breakages());
}

}  // namespace

std::vector<std::string> proven_error_field_cases() {
  return case_names(field_breakages());
}

}  // namespace ecat::master::test
