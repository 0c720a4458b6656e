// VCD writer; format per IEEE 1364-2005 §18 (four-state value change dump).
#include "esc/dc/vcd_trace.hpp"

#include <algorithm>
#include <charconv>

namespace ecat::esc {
namespace {

constexpr char kFirstIdChar = 33;  // '!'
constexpr unsigned kIdChars = 94;  // '!'..'~'
constexpr unsigned kStateBits = 4;
constexpr std::array<std::string_view, VcdTrace::kSignals> kNames{"sync0", "sync1", "sm2_event",
                                                                   "sm3_event", "app_cycle", "esm_state"};

}  // namespace

void VcdProbe::on_sync(unsigned signal, bool level, Nanoseconds t) noexcept {
  if (trace_ == nullptr || signal > 1) return;
  trace_->change(index_, signal == 0 ? VcdTrace::kSync0 : VcdTrace::kSync1, level ? 1 : 0, t);
}

void VcdProbe::on_state_changed(AlState from, AlState to, AlStatusCode code) noexcept {
  (void)from;
  (void)code;
  if (trace_ != nullptr) trace_->change(index_, VcdTrace::kEsmState, static_cast<std::uint32_t>(to), trace_->clock().now());
}

void VcdProbe::sm_event(unsigned sm, Nanoseconds t) noexcept {
  if (trace_ == nullptr) return;
  constexpr unsigned kOutputsSm = 2;
  trace_->marker(index_, sm == kOutputsSm ? VcdTrace::kSm2 : VcdTrace::kSm3, t);
}

void VcdProbe::app_cycle(bool running, Nanoseconds t) noexcept {
  if (trace_ != nullptr) trace_->change(index_, VcdTrace::kAppCycle, running ? 1 : 0, t);
}

VcdTrace::VcdTrace(std::FILE* out, std::span<const std::string> slave_names, const Clock& clock)
    : out_(out), clock_(clock), probes_(slave_names.size()), marker_end_(slave_names.size()) {
  for (std::size_t i = 0; i < probes_.size(); ++i) {
    probes_[i].trace_ = this;
    probes_[i].index_ = static_cast<unsigned>(i);
    marker_end_[i].fill(-1);
  }
  header(slave_names);
}

VcdTrace::~VcdTrace() { flush(); }

void VcdTrace::header(std::span<const std::string> names) {
  put("$version ecatslave $end\n$timescale 1ns $end\n$scope module chain $end\n");
  for (std::size_t i = 0; i < names.size(); ++i) {
    std::string scope = names[i].empty() ? "slave" + std::to_string(i) : names[i];
    std::replace_if(scope.begin(), scope.end(), [](char c) { return c == ' ' || c == '\t' || c == '$'; }, '_');
    put("$scope module ");
    put(scope);
    put(" $end\n");
    for (unsigned s = 0; s < kSignals; ++s) {
      put(s == kEsmState ? "$var wire 4 " : "$var wire 1 ");
      put_id(static_cast<unsigned>(i), static_cast<Signal>(s));
      put(" ");
      put(kNames[s]);
      put(" $end\n");
    }
    put("$upscope $end\n");
  }
  put("$upscope $end\n$enddefinitions $end\n#0\n$dumpvars\n");
  for (std::size_t i = 0; i < names.size(); ++i) {
    for (unsigned s = 0; s < kSignals; ++s) {
      put(s == kEsmState ? "b0001 " : "0");
      put_id(static_cast<unsigned>(i), static_cast<Signal>(s));
      put("\n");
    }
  }
  put("$end\n");
  now_ = 0;
}

void VcdTrace::put(std::string_view text) noexcept {
  while (!text.empty()) {
    if (used_ == buffer_.size()) flush();
    const std::size_t n = std::min(text.size(), buffer_.size() - used_);
    std::copy_n(text.data(), n, buffer_.data() + used_);
    used_ += n;
    text.remove_prefix(n);
  }
}

void VcdTrace::put_id(unsigned slave, Signal s) noexcept {
  unsigned id = slave * kSignals + s;
  std::array<char, 8> text{};
  std::size_t n = 0;
  do {
    text[n++] = static_cast<char>(kFirstIdChar + id % kIdChars);
    id /= kIdChars;
  } while (id != 0 && n < text.size());
  put(std::string_view(text.data(), n));
}

void VcdTrace::advance(Nanoseconds t) noexcept {
  if (t.count() <= now_) return;  // clamp: VCD time never goes back
  now_ = t.count();
  std::array<char, 24> text{};
  text[0] = '#';
  auto [end, ec] = std::to_chars(text.data() + 1, text.data() + text.size() - 1, now_);
  (void)ec;
  *end++ = '\n';
  put(std::string_view(text.data(), static_cast<std::size_t>(end - text.data())));
}

void VcdTrace::end_markers_before(Nanoseconds t) noexcept {
  for (;;) {
    std::int64_t first = -1;
    unsigned slave = 0;
    unsigned signal = 0;
    for (unsigned i = 0; i < marker_end_.size(); ++i) {
      for (unsigned s = 0; s < kSignals; ++s) {
        const std::int64_t e = marker_end_[i][s];
        if (e >= 0 && e <= t.count() && (first < 0 || e < first)) {
          first = e;
          slave = i;
          signal = s;
        }
      }
    }
    if (first < 0) return;
    marker_end_[slave][signal] = -1;
    advance(Nanoseconds{first});
    put("0");
    put_id(slave, static_cast<Signal>(signal));
    put("\n");
  }
}

void VcdTrace::change(unsigned slave, Signal s, std::uint32_t value, Nanoseconds t) noexcept {
  if (slave >= probes_.size()) return;
  end_markers_before(t);
  advance(t);
  if (s == kEsmState) {
    std::array<char, kStateBits + 2> text{'b'};
    for (unsigned b = 0; b < kStateBits; ++b) text[1 + b] = (value >> (kStateBits - 1 - b)) & 1u ? '1' : '0';
    text[kStateBits + 1] = ' ';
    put(std::string_view(text.data(), text.size()));
  } else {
    put(value != 0 ? "1" : "0");
  }
  put_id(slave, s);
  put("\n");
}

void VcdTrace::marker(unsigned slave, Signal s, Nanoseconds t) noexcept {
  if (slave >= probes_.size()) return;
  std::int64_t& end = marker_end_[slave][s];
  if (end >= 0 && end > t.count()) {
    end = (t + VcdProbe::kEventWidth).count();  // still high: extend
    return;
  }
  change(slave, s, 1, t);
  marker_end_[slave][s] = (t + VcdProbe::kEventWidth).count();
}

bool VcdTrace::flush() noexcept {
  if (out_ == nullptr) return true;
  if (used_ != 0 && std::fwrite(buffer_.data(), 1, used_, out_) != used_) failed_ = true;
  used_ = 0;
  if (std::fflush(out_) != 0) failed_ = true;
  return !failed_;
}

bool VcdTrace::finish() noexcept {
  const bool ok = flush();
  out_ = nullptr;
  return ok;
}

}  // namespace ecat::esc
