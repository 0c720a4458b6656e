// Register space 0x0000-0x0FFF: reads and writes from either side with their
// side effects (Beckhoff ESC datasheet Section II; shared/spec/esc-registers.md
// §4, §11). The per-side write masks are in esc/register_masks.cpp.
// Bytes that only store or return a value are copied as a block; the
// others go through reg_read_byte / reg_write_byte (esc/register_map.hpp).
#include <algorithm>
#include <cstring>

#include "esc/esc.hpp"
#include "esc/register_map.hpp"
#include "esc/register_masks.hpp"
#include "esc/registers.hpp"
#include "esc/small_copy.hpp"

namespace ecat::esc {

using namespace reg_layout;

namespace {

bool in(std::uint16_t a, std::uint16_t first, std::uint16_t end) noexcept { return a >= first && a < end; }

}  // namespace

// --- Reads --------------------------------------------------------------------------

// Fast path outside the DC block: copy, then run the handler of each byte
// with a read effect, in address order (an acknowledging read may clear a
// later event byte, which the handler then reads afresh).
bool Esc::reg_read(std::uint16_t address, std::span<std::uint8_t> out, Side side) noexcept {
  if (out.empty()) return false;
  const std::uint32_t end = address + static_cast<std::uint32_t>(out.size());
  if (address >= reg::kDcBase && end <= reg::kDcEnd) {
    // Wholly inside the DC block (the ARMW/FRMW of every DC cycle): what
    // reg_read_checked does with it, without the byte loop.
    if (!config_.dc) return false;
    dc_.read(static_cast<std::uint16_t>(address - reg::kDcBase), out, now_, side);
    return true;
  }
  if (!config_.fast_paths || (end > reg::kDcBase && address < reg::kDcEnd)) {
    return reg_read_checked(address, out, side);
  }
  const std::uint8_t effect = register_map::read_effect_flag(side);
  copy_small(out.data(), mem_.get() + address, out.size());
  if (register_map::any_in(address, out.size(), effect)) {
    for (std::size_t i = 0; i < out.size(); ++i) {
      const auto a = static_cast<std::uint16_t>(address + i);
      if (register_map::has(a, effect)) out[i] = reg_read_byte(a, side);
    }
  }
  return true;
}

bool Esc::reg_read_checked(std::uint16_t address, std::span<std::uint8_t> out, Side side) noexcept {
  std::size_t i = 0;
  bool counted = false;
  while (i < out.size()) {
    const auto a = static_cast<std::uint16_t>(address + i);
    if (in(a, reg::kDcBase, reg::kDcEnd)) {
      const std::size_t n = std::min<std::size_t>(out.size() - i, reg::kDcEnd - a);
      if (config_.dc) {
        dc_.read(static_cast<std::uint16_t>(a - reg::kDcBase), out.subspan(i, n), now_, side);
        counted = true;
      }
      i += n;
      continue;
    }
    out[i++] = reg_read_byte(a, side);
    counted = true;
  }
  return counted;
}

std::uint8_t Esc::reg_read_byte(std::uint16_t a, Side side) noexcept {
  std::uint8_t* m = mem_.get();
  if (in(a, reg::kEcatEventRequest, reg::kEcatEventRequest + 2)) {
    return static_cast<std::uint8_t>(ecat_event() >> (8 * (a - reg::kEcatEventRequest)));
  }
  if (in(a, reg::kAlEventRequest, reg::kAlEventRequest + 4)) {
    return static_cast<std::uint8_t>(al_event() >> (8 * (a - reg::kAlEventRequest)));
  }
  const std::uint8_t v = m[a];
  if (side == Side::Pdi) {
    // PDI reads that acknowledge (Section II 0x0120, 0x0440, 0x0806, 0x0805).
    if (a == reg::kAlControl || a == reg::kAlControl + 1) {
      al_control_pending_ = false;
      clear_al_event(bits::kAlEventAlControl);
    } else if (a == reg::kWatchdogStatusProcessData) {
      clear_al_event(bits::kAlEventWatchdog);
    } else if (in(a, reg::kSyncManagerBase, kSmEnd)) {
      pdi_sm_read_acknowledge((a - reg::kSyncManagerBase) / reg::kSyncManagerStride,
                              (a - reg::kSyncManagerBase) % reg::kSyncManagerStride);
    }
  } else {
    // ECAT reads that acknowledge: AL status (0x0210.3), DL status (0x0210.2), SM status.
    if (a == reg::kAlStatus) {
      clear_ecat_event(bits::kEcatEventAlStatus);
    } else if (a == reg::kDlStatus) {
      clear_ecat_event(bits::kEcatEventDlStatus);
    } else if (in(a, reg::kSyncManagerBase, kSmEnd)) {
      const unsigned n = (a - reg::kSyncManagerBase) / reg::kSyncManagerStride;
      const unsigned off = (a - reg::kSyncManagerBase) % reg::kSyncManagerStride;
      if (off == reg::sm::kStatus && n < bits::kEcatEventSmCount) {
        clear_ecat_event(static_cast<std::uint16_t>(1u << (bits::kEcatEventSmShift + n)));
      }
    }
  }
  return v;
}

// --- Writes -------------------------------------------------------------------------

bool Esc::write_protection_active() const noexcept {
  const std::uint8_t* m = mem_.get();
  return ((m[reg::kEscWriteProtection] & bits::kWriteProtect) && !esc_write_enabled_) ||
         ((m[reg::kRegisterWriteProtection] & bits::kWriteProtect) && !register_write_enabled_);
}

// Fast path: a range of plain bytes (all bits writable, nothing else
// happens) is one copy. Write protection (Section I §13) sends every ECAT
// byte through the checks.
bool Esc::reg_write(std::uint16_t address, std::span<const std::uint8_t> in_bytes, Side side) noexcept {
  if (in_bytes.empty()) return false;
  if (address >= reg::kDcBase && address + in_bytes.size() <= reg::kDcEnd) {
    // Wholly inside the DC block (the ARMW/FRMW of every DC cycle): what
    // reg_write_checked does with it, without the byte loop. Write
    // protection covers the DC registers too (Section I §13: 0x0000-0x0F7F
    // but 0x0020/0x0030); a discarded write is not counted.
    if (!config_.dc) return false;
    if (side == Side::Ecat && write_protection_active()) return false;
    dc_.write(static_cast<std::uint16_t>(address - reg::kDcBase), in_bytes, now_, side);
    return true;
  }
  const bool checked = !config_.fast_paths || (side == Side::Ecat && write_protection_active());
  if (!checked && register_map::all_in(address, in_bytes.size(), register_map::write_plain_flag(side))) {
    copy_small(mem_.get() + address, in_bytes.data(), in_bytes.size());
    return true;
  }
  return reg_write_checked(address, in_bytes, side, checked);
}

bool Esc::reg_write_checked(std::uint16_t address, std::span<const std::uint8_t> in_bytes, Side side,
                            bool checked) noexcept {
  const std::uint8_t plain = register_map::write_plain_flag(side);
  std::uint8_t* m = mem_.get();
  std::size_t i = 0;
  bool counted = false;
  while (i < in_bytes.size()) {
    const auto a = static_cast<std::uint16_t>(address + i);
    if (in(a, reg::kDcBase, reg::kDcEnd)) {
      const std::size_t n = std::min<std::size_t>(in_bytes.size() - i, reg::kDcEnd - a);
      if (config_.dc && !(side == Side::Ecat && write_protection_active())) {
        dc_.write(static_cast<std::uint16_t>(a - reg::kDcBase), in_bytes.subspan(i, n), now_, side);
        counted = true;
      }
      i += n;
      continue;
    }
    if (in(a, reg::kEepromConfiguration, reg::kEepromConfiguration + sii_reg::kSize)) {
      const std::size_t n =
          std::min<std::size_t>(in_bytes.size() - i, reg::kEepromConfiguration + sii_reg::kSize - a);
      const auto action = sii_.write(a - reg::kEepromConfiguration, in_bytes.subspan(i, n), side, now_);
      sii_action(action);
      refresh_timers();
      update_dl_status();
      counted = true;
      i += n;
      continue;
    }
    if (!checked && register_map::has(a, plain)) {
      m[a] = in_bytes[i];
      counted = true;
    } else {
      counted = reg_write_byte(a, in_bytes[i], side) || counted;
      // A byte of this access may have changed the protection (0x0020/0x0021/0x0030/0x0031).
      checked = !config_.fast_paths || (side == Side::Ecat && write_protection_active());
    }
    ++i;
  }
  return counted;
}

bool Esc::reg_write_byte(std::uint16_t a, std::uint8_t value, Side side) noexcept {
  std::uint8_t* m = mem_.get();
  if (side == Side::Ecat && a != reg::kRegisterWriteEnable && a != reg::kEscWriteEnable) {
    // Write protection (Section I §13): discarded unless released earlier in this frame.
    if ((m[reg::kEscWriteProtection] & bits::kWriteProtect) && !esc_write_enabled_) return false;
    if (a < bits::kWriteProtectedEnd && (m[reg::kRegisterWriteProtection] & bits::kWriteProtect) &&
        !register_write_enabled_) {
      return false;
    }
  }
  // AL control acts like a mailbox without device emulation: one ECAT write,
  // then no further write until the PDI has read it (Section II 0x0120).
  if (side == Side::Ecat && (a == reg::kAlControl || a == reg::kAlControl + 1) && al_control_pending_ &&
      !(m[reg::kEscConfiguration] & bits::kEscConfigDeviceEmulation)) {
    return false;
  }
  // SM configuration bytes are writable only while the SM is disabled (Section II 0x0800).
  if (in(a, reg::kSyncManagerBase, kSmEnd)) {
    const unsigned n = (a - reg::kSyncManagerBase) / reg::kSyncManagerStride;
    const unsigned off = (a - reg::kSyncManagerBase) % reg::kSyncManagerStride;
    const std::uint8_t activate = m[reg::sync_manager(n) + reg::sm::kActivate];
    if (off <= reg::sm::kControl && (activate & sm_bits::kActivateEnable)) return true;
  }
  const RegisterWriteMask wm = register_write_mask(a, config_);
  const std::uint8_t mask = side == Side::Ecat ? wm.ecat : wm.pdi;
  const std::uint8_t old = m[a];
  m[a] = static_cast<std::uint8_t>((old & ~mask) | (value & mask));
  after_register_write(a, old, side);
  return true;
}

// Side effects of a register write (Section II; esc-registers.md §11).
void Esc::after_register_write(std::uint16_t a, std::uint8_t old, Side side) noexcept {
  std::uint8_t* m = mem_.get();
  const bool ecat = side == Side::Ecat;
  if (ecat && a == reg::kRegisterWriteEnable) {
    register_write_enabled_ = (m[a] & bits::kWriteEnable) != 0;
  } else if (ecat && a == reg::kEscWriteEnable) {
    esc_write_enabled_ = (m[a] & bits::kWriteEnable) != 0;
  } else if (a == reg::kEscResetEcat || a == reg::kEscResetPdi) {
    // 'R', 'E', 'S' in consecutive writes reset the ESC; any other value restarts.
    const unsigned idx = a - reg::kEscResetEcat;
    std::uint8_t& step = reset_step_[idx];
    step = m[a] == bits::kResetSequence[step] ? static_cast<std::uint8_t>(step + 1)
                                              : static_cast<std::uint8_t>(m[a] == bits::kResetSequence[0]);
    if (step == std::size(bits::kResetSequence)) {
      step = 0;
      reset_requested_ = true;
      ++address_epoch_;  // the skip index keeps it (Segment::note_entered)
    }
    m[a] = step;  // reads show the progress of the sequence
  } else if (in(a, reg::kDlControl, reg::kDlControl + 4)) {
    if (a == reg::kDlControl + 1) loop_control_written();
    update_ports();  // advances the address epoch (the alias enable bit too)
    update_dl_status();
  } else if (ecat && a == reg::kAlControl) {
    al_control_pending_ = true;
    set_al_event(bits::kAlEventAlControl);
    if (m[reg::kEscConfiguration] & bits::kEscConfigDeviceEmulation) {
      const std::uint8_t status_old = m[reg::kAlStatus];
      m[reg::kAlStatus] = static_cast<std::uint8_t>(m[a] & bits::kAlStateMask);
      if (status_old != m[reg::kAlStatus]) set_ecat_event(bits::kEcatEventAlStatus);
    }
  } else if (!ecat && a == reg::kAlStatus) {
    if (old != m[a]) set_ecat_event(bits::kEcatEventAlStatus);
  } else if (ecat && in(a, reg::kRxErrorCounter, bits::kRxErrorCountersEnd)) {
    std::fill(m + reg::kRxErrorCounter, m + bits::kRxErrorCountersEnd, std::uint8_t{0});
  } else if (ecat && a == reg::kProcessingUnitErrorCounter) {
    m[a] = 0;
  } else if (ecat && a == reg::kPdiErrorCounter) {
    // Section II 0x030D: writing the counter clears it and the error code 0x030E.
    m[a] = 0;
    m[reg::kPdiErrorCode] = 0;
  } else if (ecat && in(a, reg::kLostLinkCounter, bits::kLostLinkCountersEnd)) {
    std::fill(m + reg::kLostLinkCounter, m + bits::kLostLinkCountersEnd, std::uint8_t{0});
  } else if (ecat && register_map::watchdog_setting(a)) {
    watchdog_times_written();
  } else if (ecat && (a == reg::kWatchdogCounterProcessData || a == reg::kWatchdogCounterPdi)) {
    m[reg::kWatchdogCounterProcessData] = 0;
    m[reg::kWatchdogCounterPdi] = 0;
  } else if (in(a, reg::kFmmuBase, kFmmuEnd)) {
    const unsigned n = (a - reg::kFmmuBase) / reg::kFmmuStride;
    if (n < config_.fmmu_count) {
      fmmus_[n] = Fmmu::decode(m + reg::fmmu(n));
      update_fmmus();
    }
  } else if (in(a, reg::kSyncManagerBase, kSmEnd)) {
    const unsigned n = (a - reg::kSyncManagerBase) / reg::kSyncManagerStride;
    const unsigned off = (a - reg::kSyncManagerBase) % reg::kSyncManagerStride;
    if (n < config_.sync_manager_count) {
      // ECAT writes to the activation byte raise AL event bit 4 (Section II 0x0806).
      if (ecat && off == reg::sm::kActivate) set_al_event(bits::kAlEventSmActivation);
      if (m[a] != old) {
        sms_[n].on_register_written(off, old);
        update_sm_guards();
        if (!sms_[n].enabled() || sms_[n].pdi_deactivated()) {
          // A disabled/deactivated SM has no pending interrupts (Section I §8.3).
          SmSignals clear;
          clear.clear_al = clear.clear_ecat = true;
          apply(n, clear);
        }
      }
    }
  } else if (ecat && a == kMiiControl + 1) {
    // No PHY answers on the management interface: a command completes at
    // once; a read reports "read error", a write without enable or an
    // unknown command reports "command error", idle clears both.
    const std::uint8_t cmd = m[a] & kMiiCommandMask;
    std::uint8_t status = 0;
    if (cmd == kMiiCommandRead) {
      status = kMiiReadError;
    } else if (cmd == kMiiCommandWrite) {
      status = (m[kMiiControl] & kMiiWriteEnable) ? 0 : kMiiCommandError;
    } else if (cmd != 0) {
      status = kMiiCommandError;
    }
    m[a] = status;
  } else if (in(a, reg::kConfiguredStationAddress, reg::kConfiguredStationAlias + 2) ||
             in(a, reg::kEcatEventMask, reg::kEcatEventMask + 2)) {
    ++address_epoch_;  // what esc::Segment's skip index keeps of the addressing
    ecat_event_mask_written();
  }
}

}  // namespace ecat::esc
