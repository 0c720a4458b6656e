#include "master/conformance/cia402_axis.hpp"

#include <algorithm>

namespace ecat::master::conformance {

namespace cia402 {

namespace {
constexpr std::uint16_t kMask4F = 0x004F;
constexpr std::uint16_t kMask6F = 0x006F;
}  // namespace

State decode(std::uint16_t sw) noexcept {
  switch (sw & kMask4F) {
    case 0x00: return State::NotReady;
    case 0x40: return State::SwitchOnDisabled;
    case 0x0F: return State::FaultReactionActive;
    case 0x08: return State::Fault;
    default: break;
  }
  switch (sw & kMask6F) {
    case 0x21: return State::ReadyToSwitchOn;
    case 0x23: return State::SwitchedOn;
    case 0x27: return State::OperationEnabled;
    case 0x07: return State::QuickStopActive;
    default: return State::Unknown;
  }
}

std::string name(State s) {
  switch (s) {
    case State::NotReady: return "Not ready to switch on";
    case State::SwitchOnDisabled: return "Switch on disabled";
    case State::ReadyToSwitchOn: return "Ready to switch on";
    case State::SwitchedOn: return "Switched on";
    case State::OperationEnabled: return "Operation enabled";
    case State::QuickStopActive: return "Quick stop active";
    case State::FaultReactionActive: return "Fault reaction active";
    case State::Fault: return "Fault";
    case State::Unknown: break;
  }
  return "unknown statusword";
}

}  // namespace cia402

namespace {
constexpr std::uint8_t kCoeServiceShift = 12;
constexpr std::uint8_t kCoeServiceEmergency = 1;
constexpr Nanoseconds kCyclePeriod = std::chrono::milliseconds(1);
constexpr Nanoseconds kEmergencyPoll = std::chrono::milliseconds(5);
constexpr unsigned kBitsPerByte = 8;
constexpr unsigned kStartCycles = 100;
constexpr std::uint32_t kMappingIndexShift = 16;
constexpr std::uint32_t kMappingBitsMask = 0xFF;

std::int64_t sign_extend(std::uint64_t v, std::size_t bytes) {
  const unsigned bits = static_cast<unsigned>(bytes * kBitsPerByte);
  if (bits >= 64) return static_cast<std::int64_t>(v);
  const std::uint64_t sign = 1ull << (bits - 1);
  v &= (1ull << bits) - 1;
  return static_cast<std::int64_t>(v ^ sign) - static_cast<std::int64_t>(sign);
}
}  // namespace

std::uint16_t RawEmergency::code() const noexcept {
  return payload.size() >= 4 ? load_le<std::uint16_t>(payload.data() + 2) : 0;
}
std::uint8_t RawEmergency::error_register() const noexcept { return payload.size() >= 5 ? payload[4] : 0; }

Cia402Axis::~Cia402Axis() {
  if (!open_) return;
  command(cia402::kDisableVoltage);
  run(2);
  CoeClient coe = ctx_.coe();
  for (auto it = restore_.rbegin(); it != restore_.rend(); ++it) {
    (void)coe.download_value(it->index, it->sub, it->value, it->bytes);
  }
}

std::optional<CaseResult> Cia402Axis::open() {
  if (auto r = ctx_.go_to(AlState::PreOp); !r) return CaseResult::failed("reach PreOp", r.error());
  if (!ctx_.info().sii.has_coe()) return CaseResult::skip("no CoE: no CiA 402 objects");
  {
    CoeClient coe = ctx_.coe();
    for (std::uint16_t index : {cia402::kControlword, cia402::kStatusword}) {
      if (auto r = coe.upload(index, 0); !r) {
        return CaseResult::skip("no CiA 402 drive: " + hex(index, 4) + " " + describe_sdo(r.error()));
      }
    }
  }
  locate();
  if (auto r = ctx_.go_to(AlState::SafeOp); !r) return CaseResult::failed("reach SafeOp", r.error());
  Bytes out = ctx_.master().outputs(ctx_.slave());
  std::fill(out.begin(), out.end(), 0);
  if (auto r = ctx_.go_to(AlState::Op); !r) return CaseResult::failed("reach Op", r.error());
  open_ = true;
  command(cia402::kDisableVoltage);
  // Fault left from an earlier case or power-up: reset it (transition 15).
  const cia402::State first = command_until(cia402::kDisableVoltage, cia402::State::SwitchOnDisabled, kStartCycles);
  if (first == cia402::State::NotReady) {
    // Transition 1 is the drive's own (self-test, power stage): a drive that
    // stays in Not ready to switch on says it cannot start.
    const std::uint16_t sw = statusword();
    return CaseResult::skip("the drive stays in Not ready to switch on (statusword " + hex(sw, 4) +
                            "): it reports it cannot start (a device twin without a drive simulation shows this too)");
  }
  if (first == cia402::State::Fault) {
    (void)command_until(cia402::kFaultReset, cia402::State::SwitchOnDisabled, 50);
    command(cia402::kDisableVoltage);
    run(2);
  }
  emergencies_.clear();
  return std::nullopt;
}

void Cia402Axis::locate() {
  CoeClient coe = ctx_.coe();
  auto read = [&](std::uint16_t assign, std::vector<Mapped>& into) {
    auto pdos = coe.read_pdo_assignment(assign);
    if (!pdos) return;
    std::uint32_t bit = 0;
    for (std::uint16_t pdo : *pdos) {
      auto entries = coe.read_pdo_mapping(pdo);
      if (!entries) return;
      for (std::uint32_t e : *entries) {
        const auto index = static_cast<std::uint16_t>(e >> kMappingIndexShift);
        if (bit % kBitsPerByte == 0 && index != 0) into.push_back({index, bit / kBitsPerByte});
        bit += e & kMappingBitsMask;
      }
    }
  };
  read(coe::kRxPdoAssign, outputs_);
  read(coe::kTxPdoAssign, inputs_);
}

std::optional<std::uint32_t> Cia402Axis::out_byte(std::uint16_t index) const {
  for (const auto& m : outputs_) {
    if (m.index == index) return m.byte;
  }
  return std::nullopt;
}
std::optional<std::uint32_t> Cia402Axis::in_byte(std::uint16_t index) const {
  for (const auto& m : inputs_) {
    if (m.index == index) return m.byte;
  }
  return std::nullopt;
}

Expected<void, SdoError> Cia402Axis::set(std::uint16_t index, std::int64_t value, std::size_t bytes) {
  if (auto at = out_byte(index)) {
    Bytes out = ctx_.master().outputs(ctx_.slave());
    if (*at + bytes <= out.size()) {
      for (std::size_t i = 0; i < bytes; ++i) {
        out[*at + i] = static_cast<std::uint8_t>(static_cast<std::uint64_t>(value) >> (kBitsPerByte * i));
      }
      return {};
    }
  }
  CoeClient coe = ctx_.coe();
  auto r = coe.download_value(index, 0, static_cast<std::uint32_t>(value), bytes);
  keep_emergencies(coe);
  return r;
}

// An emergency that came in while the client waited for an SDO reply is
// kept by the client: it is the axis's as much as one polled for.
void Cia402Axis::keep_emergencies(const CoeClient& coe) {
  for (const auto& e : coe.emergencies()) {
    RawEmergency raw;
    raw.payload = {0x00, 0x10, static_cast<std::uint8_t>(e.error_code), static_cast<std::uint8_t>(e.error_code >> 8),
                   e.error_register};
    raw.payload.insert(raw.payload.end(), e.data.begin(), e.data.end());
    emergencies_.push_back(std::move(raw));
  }
}

Expected<std::int64_t, SdoError> Cia402Axis::get(std::uint16_t index, std::size_t bytes) {
  if (auto at = in_byte(index)) {
    ConstBytes in = ctx_.master().inputs(ctx_.slave());
    if (*at + bytes <= in.size()) {
      std::uint64_t v = 0;
      for (std::size_t i = 0; i < bytes; ++i) v |= static_cast<std::uint64_t>(in[*at + i]) << (kBitsPerByte * i);
      return sign_extend(v, bytes);
    }
  }
  collect_emergencies();
  CoeClient coe = ctx_.coe();
  auto r = coe.upload(index, 0);
  keep_emergencies(coe);
  if (!r) return fail(r.error());
  std::uint64_t v = 0;
  for (std::size_t i = 0; i < std::min<std::size_t>(r->size(), 8); ++i) {
    v |= static_cast<std::uint64_t>((*r)[i]) << (kBitsPerByte * i);
  }
  return sign_extend(v, std::min(bytes, r->size()));
}

Expected<void, SdoError> Cia402Axis::change(std::uint16_t index, std::uint8_t sub, std::uint32_t value,
                                            std::size_t bytes) {
  CoeClient coe = ctx_.coe();
  auto old = coe.upload_value(index, sub);
  if (!old) {
    keep_emergencies(coe);
    return fail(old.error());
  }
  auto r = coe.download_value(index, sub, value, bytes);
  keep_emergencies(coe);  // the client's list holds both exchanges' emergencies
  if (!r) return r;
  restore_.push_back({index, sub, *old, bytes});
  return {};
}

std::uint16_t Cia402Axis::statusword() {
  auto v = get(cia402::kStatusword, 2);
  return v ? static_cast<std::uint16_t>(*v) : 0xFFFF;
}

void Cia402Axis::command(std::uint16_t controlword) { (void)set(cia402::kControlword, controlword, 2); }

void Cia402Axis::collect_emergencies() {
  Master& m = ctx_.master();
  for (unsigned guard = 0; guard < 16; ++guard) {
    auto full = m.mailbox_has_reply(ctx_.slave());
    if (!full || !*full) return;
    auto msg = m.mailbox_receive(ctx_.slave(), kEmergencyPoll);
    if (!msg) return;
    if (msg->header.type != mbx::kTypeCoe || msg->payload.size() < 2) continue;
    const auto service = static_cast<std::uint8_t>(load_le<std::uint16_t>(msg->payload.data()) >> kCoeServiceShift);
    if (service != kCoeServiceEmergency) continue;
    RawEmergency raw;
    raw.payload.assign(msg->payload.begin(), msg->payload.end());
    emergencies_.push_back(std::move(raw));
  }
}

void Cia402Axis::run(unsigned cycles) {
  for (unsigned i = 0; i < cycles; ++i) {
    ctx_.wait(kCyclePeriod);
    ctx_.cycle();
  }
  if (ctx_.info().sii.has_mailbox()) collect_emergencies();
}

cia402::State Cia402Axis::command_until(std::uint16_t controlword, cia402::State want, unsigned max_cycles) {
  command(controlword);
  cia402::State s = state();
  for (unsigned i = 0; i < max_cycles && s != want; ++i) {
    run(1);
    s = state();
  }
  return s;
}

Expected<void, std::string> Cia402Axis::reach(cia402::State target) {
  using cia402::State;
  struct Step {
    std::uint16_t cw;
    State state;
  };
  const Step steps[]{{cia402::kShutdown, State::ReadyToSwitchOn},
                     {cia402::kSwitchOn, State::SwitchedOn},
                     {cia402::kEnableOperation, State::OperationEnabled}};
  if (auto s = command_until(cia402::kDisableVoltage, State::SwitchOnDisabled); s != State::SwitchOnDisabled) {
    return fail("disable voltage -> " + cia402::name(s));
  }
  for (const Step& step : steps) {
    if (auto s = command_until(step.cw, step.state); s != step.state) {
      return fail(hex(step.cw, 4) + " -> " + cia402::name(s));
    }
    if (step.state == target) return {};
  }
  return {};
}

Expected<void, std::string> Cia402Axis::enable() { return reach(cia402::State::OperationEnabled); }

std::optional<std::uint32_t> Cia402Axis::supported_modes() {
  CoeClient coe = ctx_.coe();
  auto v = coe.upload_value(cia402::kSupportedModes, 0);
  if (!v) return std::nullopt;
  return *v;
}

std::int64_t Cia402Axis::select_mode(std::int8_t mode, unsigned max_cycles) {
  (void)set(cia402::kModes, mode, 1);
  std::int64_t seen = 0;
  for (unsigned i = 0; i < max_cycles; ++i) {
    run(1);
    auto v = get(cia402::kModesDisplay, 1);
    seen = v ? *v : -128;
    if (seen == mode) break;
  }
  return seen;
}

}  // namespace ecat::master::conformance
