// Register values the ESC datasheet gives for the registers a master reads:
// after power-up (reset values, Beckhoff ESC datasheet Section II, as
// collected in shared/spec/esc-registers.md §3-§10) and in Init. Each case
// compares one register group with a table citing where its value comes from.
#include <fmt/format.h>

#include "common/frame.hpp"
#include "master/conformance/suite.hpp"
#include "master/registers.hpp"

namespace ecat::master::conformance {

namespace {

// One row of a datasheet table: `size` bytes at `address`, compared under `mask`.
struct RegisterValue {
  std::uint16_t address;
  std::uint8_t size;  // 1, 2, 4 or 8
  std::uint64_t mask;
  std::uint64_t value;
  const char* what;
};

std::uint64_t load(const std::vector<std::uint8_t>& regs, std::uint16_t address, std::uint8_t size) {
  std::uint64_t v = 0;
  for (std::uint8_t i = 0; i < size; ++i) v |= std::uint64_t{regs[address + i]} << (8 * i);
  return v;
}

std::string show(const RegisterValue& r, std::uint64_t v) {
  return fmt::format("{:#06x}={:#0{}x}", r.address, v & r.mask, 2 + 2 * r.size);
}

// "0x0400=0x09c2 ..." for the table and for what the slave shows.
// A run of at least this many adjacent registers of one size that all hold
// the same expected value is shown as one range, so that a whole FMMU or SM
// block reads as one line; a register that differs keeps its own
// "address=value" on both sides.
constexpr std::size_t kRangeRunMin = 3;

bool holds(const std::vector<std::uint8_t>& regs, const RegisterValue& r) {
  return (load(regs, r.address, r.size) & r.mask) == (r.value & r.mask);
}

CaseResult compare_table(const std::vector<std::uint8_t>& regs, const std::vector<RegisterValue>& table) {
  std::string want, seen;
  auto add = [&](const std::string& w, const std::string& s) {
    if (!want.empty()) want += ' ', seen += ' ';
    want += w;
    seen += s;
  };
  for (std::size_t i = 0; i < table.size();) {
    const RegisterValue& r = table[i];
    std::size_t j = i + 1;
    if (holds(regs, r)) {
      while (j < table.size() && table[j].size == r.size && (table[j].value & table[j].mask) == (r.value & r.mask) &&
             table[j].address == table[j - 1].address + table[j - 1].size && holds(regs, table[j])) {
        ++j;
      }
    }
    if (j - i >= kRangeRunMin) {
      // "0x0800..0x0838=0x0000000000000000": every register of that size from
      // the first to the last address (each compared under its own mask).
      const std::string range =
          fmt::format("{:#06x}..{:#06x}={:#0{}x}", r.address, table[j - 1].address, r.value & r.mask, 2 + 2 * r.size);
      add(range, range);
    } else {
      for (std::size_t k = i; k < j; ++k) add(show(table[k], table[k].value), show(table[k], load(regs, table[k].address, table[k].size)));
    }
    i = j;
  }
  return CaseResult::compare(want, seen);
}

using Table = std::vector<RegisterValue>;

// A power-up case: power cycle, registers by position, then `table(regs, ctx)`.
Case power_up_case(const char* name, const char* clause, Table (*table)(Context&, const std::vector<std::uint8_t>&)) {
  return Case{name, clause, [table](Context& ctx) {
                auto regs = ctx.power_up_registers();
                if (!regs) return CaseResult::skip("the runner cannot power-cycle the slave (in-process targets can)");
                if (!*regs) return CaseResult::failed("registers after power-up", regs->error());
                const std::vector<std::uint8_t>& r = ***regs;
                Table t = table(ctx, r);
                if (t.empty()) return CaseResult::skip("the ESC has none of these registers");
                return compare_table(r, t);
              }};
}

// Reads [from, from + bytes) into a register-space-sized buffer.
Expected<std::vector<std::uint8_t>, std::string> read_block(Context& ctx, std::uint16_t from, std::uint16_t bytes) {
  std::vector<std::uint8_t> regs(kRegisterSpace);
  if (auto r = ctx.master().fprd(ctx.info().station_address, from, Bytes(regs.data() + from, bytes)); !r) {
    return fail(fmt::format("FPRD {:#06x}: {}", from, describe(r.error())));
  }
  return regs;
}

// ESC Section II 0x0010-0x0013: station address 0, alias from SII word 4
// (loaded at the first EEPROM load after power-up, Section I p.93).
Table addresses(Context& ctx, const std::vector<std::uint8_t>&) {
  return {{reg::kConfiguredStationAddress, 2, 0xFFFF, 0, "station address (reset 0)"},
          {reg::kConfiguredStationAlias, 2, 0xFFFF, ctx.info().sii.station_alias, "alias = SII word 4"}};
}

// ESC Section II 0x0100 (esc-registers.md §4.6): forwarding rule 1 (non-EtherCAT frames
// destroyed), every port's loop control Auto (0), alias addressing off
// (bit 24); the RX FIFO size (bits 18:16) is ESC-specific and not compared.
// 0x0108 physical read/write offset reset 0.
Table dl_control(Context&, const std::vector<std::uint8_t>&) {
  return {{reg::kDlControl, 4, 0x0100FF03, 0x00000001, "DL control"}, {0x0108, 2, 0xFFFF, 0, "physical R/W offset"}};
}

// ESC Section I p.115 / Section II 0x0020-0x0031: write protection off after reset.
Table write_protection(Context&, const std::vector<std::uint8_t>&) {
  return {{reg::kRegisterWriteEnable, 1, 0x01, 0, "register write enable"},
          {reg::kRegisterWriteProtection, 1, 0x01, 0, "register write protection"},
          {reg::kEscWriteEnable, 1, 0x01, 0, "ESC write enable"},
          {reg::kEscWriteProtection, 1, 0x01, 0, "ESC write protection"}};
}

// ESC Section II 0x0120/0x0130/0x0134 (esc-registers.md §4.8): Init requested and
// shown, no ErrInd, no ID, code 0.
Table al_registers(Context&, const std::vector<std::uint8_t>&) {
  return {{reg::kAlControl, 2, 0x003F, 0x0001, "AL control reset 1"},
          {reg::kAlStatus, 2, 0x003F, 0x0001, "AL status Init"},
          {reg::kAlStatusCode, 2, 0xFFFF, 0, "AL status code"}};
}

// ESC Section II 0x0400-0x0443 (esc-registers.md §8): divider 0x09C2 (100 µs unit),
// PDI and process-data watchdog 0x03E8 (100 ms), expiry counters 0.
Table watchdog(Context&, const std::vector<std::uint8_t>&) {
  return {{reg::kWatchdogDivider, 2, 0xFFFF, 0x09C2, "divider"},
          {0x0410, 2, 0xFFFF, 0x03E8, "PDI watchdog time"},
          {reg::kWatchdogTimeProcessData, 2, 0xFFFF, 0x03E8, "process-data watchdog time"},
          {0x0442, 1, 0xFF, 0, "PD watchdog counter"},
          {0x0443, 1, 0xFF, 0, "PDI watchdog counter"}};
}

// ESC Section II 0x0500-0x0503 (esc-registers.md §9): EEPROM not offered to the
// PDI, PDI does not hold it; 0x0502 command idle, no checksum error, loaded,
// no ack/write-enable error, not busy (bits 8-15; bits 5-7 are the ESC's
// configuration and not compared).
Table eeprom(Context&, const std::vector<std::uint8_t>&) {
  return {{reg::kEepromConfiguration, 1, 0x03, 0, "EEPROM configuration"},
          {0x0501, 1, 0x01, 0, "EEPROM PDI access state"},
          {reg::kEepromControlStatus, 2, 0xFF01, 0, "EEPROM control/status"}};
}

// ESC Section II 0x0600-0x06FF (esc-registers.md §6): every FMMU the ESC has is 0.
Table fmmus(Context& ctx, const std::vector<std::uint8_t>& regs) {
  Table t;
  const unsigned n = regs[0x0004] != 0 ? regs[0x0004] : ctx.info().esc.fmmus;
  for (unsigned i = 0; i < n && i < 16; ++i) {
    t.push_back({reg::fmmu(i), 8, ~std::uint64_t{0}, 0, "FMMU logical/length/bits"});
    t.push_back({static_cast<std::uint16_t>(reg::fmmu(i) + 8), 8, 0x000000FFFFFFFFFF, 0, "FMMU physical/type/activate"});
  }
  return t;
}

// ESC Section II 0x0800-0x087F (esc-registers.md §7): start, length, control and
// activate 0 for every SM the ESC has (status and PDI control are the
// PDI's and not compared).
Table sync_managers(Context& ctx, const std::vector<std::uint8_t>& regs) {
  Table t;
  const unsigned n = regs[0x0005] != 0 ? regs[0x0005] : ctx.info().esc.sync_managers;
  for (unsigned i = 0; i < n && i < 16; ++i) {
    t.push_back({reg::sync_manager(i), 8, 0x00FF00FFFFFFFFFF, 0, "SM start/length/control/activate"});
  }
  return t;
}

// ESC Section II 0x0920-0x0935, 0x0980-0x09A7 (esc-registers.md §10): offset,
// delay and difference 0, speed counter start 0x1000, filter depths 4 and 12,
// SYNC unit owned by ECAT and off, cycle times 0. Only with DC (0x0008 bit 2).
Table dc(Context& ctx, const std::vector<std::uint8_t>&) {
  if (!ctx.info().esc.has_dc()) return {};
  return {{reg::kDcSystemTimeOffset, 8, ~std::uint64_t{0}, 0, "system time offset"},
          {reg::kDcSystemTimeDelay, 4, 0xFFFFFFFF, 0, "system time delay"},
          {reg::kDcSpeedCounterStart, 2, 0x7FFF, 0x1000, "speed counter start"},
          {0x0934, 1, 0x0F, 0x04, "system time difference filter depth"},
          {0x0935, 1, 0x0F, 0x0C, "speed counter filter depth"},
          {reg::kDcCyclicUnitControl, 1, 0x31, 0, "cyclic unit control"},
          {reg::kDcActivation, 1, 0xFF, 0, "activation"},
          {reg::kDcSync0CycleTime, 4, 0xFFFFFFFF, 0, "SYNC0 cycle"},
          {reg::kDcSync1CycleTime, 4, 0xFFFFFFFF, 0, "SYNC1 cycle"}};
}

constexpr std::uint16_t kPdiControl = 0x0140;
constexpr std::uint16_t kPdiConfiguration = 0x0150;
constexpr std::uint16_t kExtendedPdiConfiguration = 0x0152;
constexpr std::uint16_t kSyncPulseLength = 0x0982;
constexpr std::uint16_t kFeaturesReserved = 0xF000;  // 0x0008 bits 15:12
constexpr std::uint8_t kPortNotImplemented = 0b00;
constexpr std::uint32_t kRamStart = 0x1000;
constexpr std::uint8_t kMaxUnits = 16;  // FMMUs / SMs an ESC can have (Section II 0x0004/0x0005)
constexpr std::uint8_t kSmModeMask = 0x03;
constexpr std::uint8_t kBuffers = 3;

CaseResult esc_information(Context& ctx) {
  auto regs = read_block(ctx, reg::kType, reg::kEscInfoLength);
  if (!regs) return CaseResult::failed("0x0000-0x0009 readable", regs.error());
  const auto& r = *regs;
  const auto& s = ctx.info().sii;
  std::string problems;
  const std::uint8_t fmmus = r[0x0004], sms = r[0x0005], ram = r[0x0006], ports = r[0x0007];
  const auto features = load_le<std::uint16_t>(r.data() + 0x0008);
  if (fmmus == 0 || fmmus > kMaxUnits) problems += fmt::format("0x0004 = {} FMMUs; ", fmmus);
  if (sms == 0 || sms > kMaxUnits) problems += fmt::format("0x0005 = {} SMs; ", sms);
  if (s.sync_managers.size() > sms) problems += fmt::format("SII SYNCM has {} SMs, 0x0005 = {}; ", s.sync_managers.size(), sms);
  std::size_t fmmus_used = 0;
  for (auto u : s.fmmu_usage) fmmus_used += (u != 0x00 && u != 0xFF) ? 1 : 0;
  if (fmmus_used > fmmus) problems += fmt::format("SII FMMU uses {}, 0x0004 = {}; ", fmmus_used, fmmus);
  std::uint32_t end = kRamStart;
  for (const auto& sm : s.sync_managers) {
    if (sm.length == 0) continue;
    const std::uint32_t len = (sm.control & kSmModeMask) == 0 ? std::uint32_t{sm.length} * kBuffers : sm.length;
    end = std::max<std::uint32_t>(end, sm.start + len);
  }
  if (end > kRamStart + std::uint32_t{ram} * 1024u) problems += fmt::format("SMs reach {}, RAM 0x0006 = {} KiB; ", hex(end - 1, 4), ram);
  if ((ports & 0x03) == kPortNotImplemented) problems += "0x0007 port 0 not implemented; ";
  if ((features & kFeaturesReserved) != 0) problems += fmt::format("0x0008 = {} (bits 15:12 reserved); ", hex(features, 4));
  return CaseResult::compare("consistent", problems.empty() ? "consistent" : problems);
}

// ESC Section I p.93 (sii-eeprom.md §1): 0x0140-0x0141 = SII word 0,
// 0x0150-0x0151 = word 1, 0x0152-0x0153 = word 3, 0x0982 = word 2 (with DC).
CaseResult esc_config_from_sii(Context& ctx) {
  const auto& img = ctx.info().sii_image;
  if (img.size() < 8) return CaseResult::failed("SII words 0-3", "image too short");
  std::vector<std::uint8_t> regs(kRegisterSpace);
  const std::uint16_t station = ctx.info().station_address;
  for (auto [from, n] : {std::pair<std::uint16_t, std::uint16_t>{kPdiControl, 2}, {kPdiConfiguration, 4}}) {
    if (!ctx.master().fprd(station, from, Bytes(regs.data() + from, n))) return CaseResult::failed("0x0140/0x0150 readable", "read failed");
  }
  auto w = [&](std::size_t i) { return std::uint64_t{load_le<std::uint16_t>(img.data() + 2 * i)}; };
  Table t{{kPdiControl, 2, 0xFFFF, w(0), "PDI control / ESC configuration = word 0"},
          {kPdiConfiguration, 2, 0xFFFF, w(1), "PDI configuration = word 1"},
          {kExtendedPdiConfiguration, 2, 0xFFFF, w(3), "extended PDI configuration = word 3"}};
  if (ctx.info().esc.has_dc()) {
    if (!ctx.master().fprd(station, kSyncPulseLength, Bytes(regs.data() + kSyncPulseLength, 2))) {
      return CaseResult::failed("0x0982 readable", "read failed");
    }
    t.push_back({kSyncPulseLength, 2, 0xFFFF, w(2), "SYNC pulse length = word 2"});
  }
  return compare_table(regs, t);
}

// ESC Section II 0x0110 (esc-registers.md §4.7): EEPROM loaded (bit 0), PDI
// watchdog not expired (bit 1: the application runs), enhanced link = 0x0141
// bit 1 (bit 2), link and communication on port 0 where the master is
// (bits 4, 9), port 0 open (bit 8 = 0).
CaseResult dl_status(Context& ctx) {
  std::vector<std::uint8_t> regs(kRegisterSpace);
  const std::uint16_t station = ctx.info().station_address;
  if (!ctx.master().fprd(station, reg::kDlStatus, Bytes(regs.data() + reg::kDlStatus, 2)) ||
      !ctx.master().fprd(station, 0x0141, Bytes(regs.data() + 0x0141, 1))) {
    return CaseResult::failed("0x0110 readable", "read failed");
  }
  const std::uint64_t enhanced = (regs[0x0141] & 0x02) != 0 ? 0x0004 : 0;
  return compare_table(regs, {{reg::kDlStatus, 2, 0x0317, 0x0213 | enhanced, "DL status"}});
}

// ETG.1000.6 §6.4.1 / ESC Section II 0x0130-0x0135 after an Init request with
// acknowledge: Init, no ErrInd, no ID flag, reserved 0x0132 0, code 0.
CaseResult init_al_status(Context& ctx) {
  auto regs = read_block(ctx, reg::kAlStatus, 6);
  if (!regs) return CaseResult::failed("0x0130-0x0135 readable", regs.error());
  return compare_table(*regs, {{reg::kAlStatus, 2, 0xFFFF, 0x0001, "AL status Init"},
                               {0x0132, 2, 0xFFFF, 0, "reserved"},
                               {reg::kAlStatusCode, 2, 0xFFFF, 0, "AL status code"}});
}

// ESC Section II 0x0500-0x0503 in Init after the master's SII reads: the
// interface is the master's and idle, without error (esc-registers.md §9).
CaseResult init_eeprom_idle(Context& ctx) {
  auto regs = read_block(ctx, reg::kEepromConfiguration, 4);
  if (!regs) return CaseResult::failed("0x0500-0x0503 readable", regs.error());
  return compare_table(*regs, {{reg::kEepromConfiguration, 1, 0x01, 0, "EEPROM to ECAT"},
                               {0x0501, 1, 0x01, 0, "PDI does not hold it"},
                               {reg::kEepromControlStatus, 2, 0xFF00, 0, "idle, loaded, no error"}});
}

}  // namespace

std::vector<Case> register_cases() {
  return {
      {"reg.esc_information", "ESC Section II 0x0000-0x0009 (esc-registers.md §4.1-§4.2): 1-16 FMMUs/SMs, enough for the SII's FMMU/SYNCM, RAM (0x0006) holds the SMs, port 0 implemented, 0x0008 bits 15:12 reserved 0", esc_information},
      {"reg.esc_config_from_sii", "ESC Section I p.93 EEPROM load: 0x0140/0x0141 = SII word 0, 0x0150/0x0151 word 1, 0x0152 word 3, 0x0982 word 2 (sii-eeprom.md §1)", esc_config_from_sii},
      {"reg.dl_status", "ESC Section II 0x0110: EEPROM loaded, PDI operational, enhanced link = 0x0141 bit 1, port 0 link + communication, port 0 open (esc-registers.md §4.7)", dl_status},
      {"reg.init_al_status", "ETG.1000.6 §6.4.1, ESC Section II 0x0130-0x0135: in Init after acknowledge 0x0130 = 0x0001, 0x0132 = 0, 0x0134 = 0 (esc-registers.md §4.8)", init_al_status},
      {"reg.init_eeprom_idle", "ESC Section II 0x0500-0x0503 in Init: EEPROM with ECAT, command idle, loaded, no checksum/ack/write-enable error, not busy (esc-registers.md §9)", init_eeprom_idle},
      power_up_case("reg.powerup_addresses", "ESC Section II 0x0010-0x0013 reset: station address 0, alias = SII word 4 (Section I p.93; esc-registers.md §4.3)", addresses),
      power_up_case("reg.powerup_dl_control", "ESC Section II 0x0100-0x0103, 0x0108 reset: forwarding rule 1, loops Auto, alias off, R/W offset 0 (esc-registers.md §4.6)", dl_control),
      power_up_case("reg.powerup_write_protection", "ESC Section I p.115, Section II 0x0020-0x0031 reset 0 (esc-registers.md §4.4)", write_protection),
      power_up_case("reg.powerup_al", "ESC Section II 0x0120/0x0130/0x0134 reset: 0x0001, 0x0001, 0 (esc-registers.md §4.8)", al_registers),
      power_up_case("reg.powerup_watchdog", "ESC Section II 0x0400-0x0443 reset: divider 0x09C2, times 0x03E8, counters 0 (esc-registers.md §8)", watchdog),
      power_up_case("reg.powerup_eeprom", "ESC Section II 0x0500-0x0503 after the power-up EEPROM load: ECAT owns it, idle, loaded, no error (esc-registers.md §9)", eeprom),
      power_up_case("reg.powerup_fmmus", "ESC Section II 0x0600-0x06FF reset 0 for every FMMU of 0x0004 (esc-registers.md §6)", fmmus),
      power_up_case("reg.powerup_sync_managers", "ESC Section II 0x0800-0x087F reset: start, length, control, activate 0 for every SM of 0x0005 (esc-registers.md §7)", sync_managers),
      power_up_case("reg.powerup_dc", "ESC Section II 0x0920-0x09A7 reset: offset/delay 0, 0x0930 = 0x1000, filter depths 4/12, 0x0980/0x0981 0, cycle times 0 (esc-registers.md §10)", dc),
  };
}

}  // namespace ecat::master::conformance
