// A conformance suite for one EtherCAT slave, run through the master library
// over any transport (apps/ecat-conform is the command-line front end; tests
// run it in-process). Each case names the ETG/CiA clause it checks and
// reports expected vs seen. Cases discover what they need from the slave
// itself (SII, SDO information), so the suite works for any device.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <vector>

#include "common/clock.hpp"
#include "common/expected.hpp"
#include "master/coe_client.hpp"
#include "master/master.hpp"

namespace ecat::master::conformance {

enum class Verdict : std::uint8_t { Pass, Fail, Skip };

struct CaseResult {
  Verdict verdict = Verdict::Pass;
  std::string expected;
  std::string seen;
  Nanoseconds duration{0};
  static CaseResult pass(std::string expected, std::string seen);
  static CaseResult failed(std::string expected, std::string seen);
  static CaseResult skip(std::string why);
  // Pass if expected == seen.
  static CaseResult compare(std::string expected, std::string seen);
};

// Identity the slave should report, when the caller knows it (device file / ESI).
struct ExpectedIdentity {
  std::uint32_t vendor_id = 0;
  std::uint32_t product_code = 0;
  std::uint32_t revision = 0;
};

// DC Sync0 mode for a device whose ESI offers no OpMode without DC (Dc/OpMode
// all with an AssignActivate that starts the SYNC unit, Inovance IS620N): a
// configurator can only run it in DC, so the suite programs the DC clocks
// once and SYNC0 before every PreOp->SafeOp (ETG.1020 §22.2; SOEM ecx_dcsync0),
// as a master that follows the ESI must. Without it such a device refuses
// SafeOp (0x0027/0x0028) and every case past PreOp fails for that reason.
struct DcSync0 {
  std::uint32_t cycle_ns = 0;
  std::uint32_t shift_ns = 0;
  std::string why;  // printed by the front end and kept in the report
};

struct SuiteOptions {
  std::string filter;  // substring or glob ('*', '?') on the case name; empty = all
  std::optional<ExpectedIdentity> identity;
  std::size_t slave = 0;
  // Lets time pass with the bus idle (watchdog tests). In-process: advance
  // the manual clock and poll the slaves; on a wire: sleep.
  std::function<void(Nanoseconds)> wait;
  // Max objects walked by the SDO-info/upload consistency case (0 = all).
  std::size_t max_objects = 0;
  // Run the cases in DC Sync0 mode (see DcSync0); empty = free run.
  std::optional<DcSync0> dc;
  // Switches the slave off and on again (in-process: slave::FaultCatalogue
  // power_cycle). Returns false or an empty function when the runner cannot,
  // and the power-up register cases skip saying so.
  std::function<bool()> power_cycle;
  // FoE properties an ESI cannot express (ecat-conform --foe-*): the password
  // the device's files need (sent in every RRQ/WRQ; the wrong-password case
  // runs only with it), a file name the device denies access to, and how many
  // bytes it can store (the disk-full case writes more). Unset: those cases skip.
  std::optional<std::uint32_t> foe_password;
  std::string foe_denied_file;
  std::optional<std::size_t> foe_capacity;
  // The device answers FoE read/write requests with BUSY before it serves
  // them (a file that is not ready at once; ecat-conform --foe-busy): runs
  // foe.busy_then_complete, which skips otherwise.
  bool foe_busy = false;
};

// Registers 0x0000-0x0FFF as the ESC shows them right after power-up, read by
// position (APRD) before the master addresses the slave again.
inline constexpr std::size_t kRegisterSpace = 0x1000;

class Context {
 public:
  Context(Master& master, const SuiteOptions& options) : master_(master), options_(options) {}
  Master& master() noexcept { return master_; }
  std::size_t slave() const noexcept { return options_.slave; }
  const SuiteOptions& options() const noexcept { return options_; }
  SlaveInfo& info() { return master_.slave(options_.slave); }
  CoeClient coe() { return CoeClient(master_, options_.slave); }
  void wait(Nanoseconds d) const {
    if (options_.wait) options_.wait(d);
  }

  // Brings the slave to `state` the standard way (acknowledging errors,
  // mailbox SMs, PDO sizes + SM2/SM3/FMMUs, process data before Op).
  Expected<void, std::string> go_to(AlState state);
  // Process data set up from CoE (0x1C12/0x1C13) or the SII defaults.
  Expected<void, std::string> prepare_process_data();
  // One cyclic exchange if process data is configured.
  void cycle();
  // With options().dc: the DC clocks (once) and SYNC0 of the slave, before
  // PreOp->SafeOp; nothing otherwise.
  Expected<void, std::string> program_sync0();
  // With options().dc, before SafeOp->Op: cycles one SYNC0 period apart until
  // SYNC0 has started and outputs came with it (a DC slave refuses Op with
  // 0x002D while no SYNC0 arrives); nothing otherwise.
  void run_until_sync0();
  // Power-cycles the slave (options().power_cycle) once per run, reads its
  // register space by position, and gives the slave its station address
  // again (Master::readdress). Later calls return the same snapshot.
  // nullopt: the runner cannot power-cycle; an error: it went wrong.
  std::optional<Expected<const std::vector<std::uint8_t>*, std::string>> power_up_registers();

 private:
  Master& master_;
  const SuiteOptions& options_;
  bool dc_configured_ = false;
  std::vector<std::uint8_t> power_up_;
};

struct Case {
  std::string name;    // "esm.init_to_safeop_refused"
  std::string clause;  // "ETG.1000.6 §6.4.1, Table 11 (0x0011)"
  std::function<CaseResult(Context&)> run;
};

struct Report {
  std::string name;
  std::string clause;
  CaseResult result;
};

std::vector<Case> esm_cases();
std::vector<Case> config_cases();
std::vector<Case> mailbox_cases();
std::vector<Case> sdo_cases();
std::vector<Case> consistency_cases();
// ESC/SII-level areas (issue 31 item 3): register defaults, identification,
// process-data watchdog, DC and synchronisation, SII rules beyond the schema.
std::vector<Case> register_cases();
std::vector<Case> identification_cases();
std::vector<Case> watchdog_cases();
std::vector<Case> dc_cases();
std::vector<Case> sii_rule_cases();
// Application-level areas: CiA402, emergencies and 10F3h, FoE, EoE.
std::vector<Case> cia402_cases();
std::vector<Case> emergency_cases();
std::vector<Case> foe_cases();
std::vector<Case> eoe_cases();
// 1003h pre-defined error field (CiA 301), filled by the CiA 402 fault.
std::vector<Case> error_field_cases();
std::vector<Case> all_cases();

bool matches_filter(const std::string& name, const std::string& filter);

// Scans the bus first (failure -> one failed "scan" case) and runs every
// selected case in order, each from a fresh Init.
// `extra` cases (e.g. checks against a device file the caller knows) run after the standard ones.
std::vector<Report> run_suite(Master& master, const SuiteOptions& options, const std::vector<Case>& extra = {});
std::vector<Report> run_cases(Master& master, const std::vector<Case>& cases, const SuiteOptions& options);

std::size_t failures(const std::vector<Report>& reports);
std::string format_table(const std::vector<Report>& reports);
std::string junit_xml(const std::vector<Report>& reports, const std::string& suite_name);

// "PreOp", "Init+E 0x0011" ...
std::string format_status(const AlStatus& s);
std::string hex(std::uint32_t value, int digits);
// "abort 0x06020000" for a slave abort, else the master-side cause.
std::string describe_sdo(const SdoError& e);

}  // namespace ecat::master::conformance
