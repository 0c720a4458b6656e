#include "slave/chain.hpp"

#include <cstdio>

#include <fmt/format.h>

#include "common/frame_parser.hpp"
#include "slave/firmware.hpp"
#include "slave/frame_tally.hpp"

namespace ecat::slave {

Expected<void, std::string> Chain::add(od::DeviceDescription device, const SlaveOptions& options) {
  auto s = VirtualSlave::create(std::move(device), clock_, options);
  if (!s) return fail(s.error());
  segment_.add((*s)->esc());
  slaves_.push_back(std::move(*s));
  return {};
}

bool Chain::process_frame(std::span<std::uint8_t> frame, Nanoseconds now) noexcept {
  const bool returned = pass_frame(frame, now);
  run_firmware(now);
  return returned;
}

bool Chain::pass_frame(std::span<std::uint8_t> frame, Nanoseconds now) noexcept {
  ++stats_.frames_received;
  const bool returned = segment_.process_frame(frame, now);
  if (returned) {
    ++stats_.frames_returned;
    count_returned(frame);
  } else if (!parse_frame(frame)) {
    ++stats_.frames_malformed;  // rare path: parse again only to tell why
  } else {
    ++stats_.frames_lost;
  }
  return returned;
}

void Chain::run_firmware(Nanoseconds now) noexcept {
  // The firmware of a slave reacts to what the frame left behind when its
  // ESC raised the IRQ (or it has work due), as its interrupt handler would
  // within microseconds; the others stay asleep (a few loads each:
  // VirtualSlave::after_frame_due).
  for (auto& s : slaves_) {
    if (s->after_frame_due(now)) s->after_frame(now);
  }
}

void Chain::count_returned(std::span<const std::uint8_t> frame) noexcept {
  const FrameTally t = tally_frame(frame);
  stats_.datagrams += t.datagrams;
  stats_.wkc_total += t.wkc_total;
}

std::optional<Nanoseconds> Chain::poll(Nanoseconds now) noexcept {
  std::optional<Nanoseconds> next;
  for (auto& s : slaves_) {
    const auto t = s->poll(now);
    if (t && (!next || *t < *next)) next = t;
  }
  return next;
}

Expected<void, std::string> Chain::open_trace(const std::string& path) {
  trace_file_.reset(std::fopen(path.c_str(), "w"));
  if (!trace_file_) return fail(fmt::format("{}: cannot open for writing", path));
  std::vector<std::string> names;
  for (std::size_t i = 0; i < slaves_.size(); ++i) names.push_back(fmt::format("slave{}", i + 1));
  trace_ = std::make_unique<esc::VcdTrace>(trace_file_.get(), names, clock_);
  for (std::size_t i = 0; i < slaves_.size(); ++i) slaves_[i]->attach_trace(trace_->probe(i));
  return {};
}

Expected<void, std::string> Chain::write_plot(const std::string& path) const {
  for (const auto& s : slaves_) {
    Application* app = s->firmware().application();
    if (app && app->write_plot(path)) return {};
  }
  return fail(fmt::format("{}: no drive in the chain has a motion trace", path));
}

void Chain::shutdown() noexcept {
  for (auto& s : slaves_) s->shutdown();
  if (trace_) trace_->flush();
  if (trace_file_) std::fflush(trace_file_.get());
}

}  // namespace ecat::slave
