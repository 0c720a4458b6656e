#include "master/process_image_plan.hpp"

#include <algorithm>
#include <limits>

namespace ecat::master {

namespace {

// Cuts one region into datagrams and packs them into frames; the frame state
// carries over from one region to the next (LWR and LRD share frames).
class Packer {
 public:
  Packer(ProcessImagePlan& plan, PlanLimits limits) noexcept
      : plan_(plan), limits_(limits), room_(kFrameDatagramRoom - limits.first_frame_reserved) {}

  void region(Command command, std::uint32_t begin, std::span<const FmmuSpan> units) {
    command_ = command;
    start_ = begin;
    length_ = 0;
    for (const FmmuSpan& u : units) {
      std::size_t left = u.length;
      while (left > 0) {
        if (length_ == 0) fresh_frame_unless_fits(std::min(left, fresh_capacity()));
        if (length_ + left <= capacity()) {
          length_ += left;
          left = 0;
        } else if (length_ > 0 && left <= fresh_capacity()) {
          close();  // SOEM: a span that fits one datagram starts the next one
        } else {
          const std::size_t take = capacity() - length_;  // larger than any datagram: cut it
          length_ += take;
          left -= take;
          close();
        }
      }
    }
    if (length_ > 0) close();
  }

  void finish() noexcept { plan_.frames = plan_.datagrams.empty() ? 0 : frame_ + 1; }

 private:
  std::size_t fresh_capacity() const noexcept {
    return std::min(limits_.max_datagram_data, kFrameDatagramRoom - kDatagramOverhead);
  }
  std::size_t capacity() const noexcept {
    return room_ > kDatagramOverhead ? std::min(limits_.max_datagram_data, room_ - kDatagramOverhead) : 0;
  }
  void fresh_frame_unless_fits(std::size_t want) noexcept {
    if (capacity() >= want) return;
    ++frame_;
    room_ = kFrameDatagramRoom;
  }
  void close() {
    plan_.datagrams.push_back(PdDatagram{command_, start_, static_cast<std::uint16_t>(length_), 0,
                                         static_cast<std::uint32_t>(frame_)});
    room_ -= kDatagramOverhead + length_;
    start_ += static_cast<std::uint32_t>(length_);
    length_ = 0;
  }

  ProcessImagePlan& plan_;
  PlanLimits limits_;
  std::size_t room_;
  std::size_t frame_ = 0;
  Command command_ = Command::Lrw;
  std::uint32_t start_ = 0;
  std::size_t length_ = 0;
};

bool overlaps(const FmmuSpan& s, const PdDatagram& d) noexcept {
  return s.length > 0 && s.logical < d.logical + d.length && d.logical < s.logical + s.length;
}

// Each ESC once per direction per datagram (ETG.1000.4 §5.4.3).
void count_wkc(std::span<const FmmuSpan> spans, ProcessImagePlan& plan) {
  constexpr std::uint32_t kNone = std::numeric_limits<std::uint32_t>::max();
  std::uint32_t slaves = 0;
  for (const FmmuSpan& s : spans) slaves = std::max(slaves, s.slave + 1);
  std::vector<std::uint32_t> wrote(slaves, kNone), read(slaves, kNone);
  for (std::uint32_t i = 0; i < plan.datagrams.size(); ++i) {
    PdDatagram& d = plan.datagrams[i];
    unsigned w = 0, r = 0;
    for (const FmmuSpan& s : spans) {
      if (!overlaps(s, d)) continue;
      auto& mark = s.write ? wrote[s.slave] : read[s.slave];
      if (mark == i) continue;
      mark = i;
      ++(s.write ? w : r);
    }
    switch (d.command) {
      case Command::Lwr: d.expected_wkc = static_cast<std::uint16_t>(w); break;
      case Command::Lrd: d.expected_wkc = static_cast<std::uint16_t>(r); break;
      default: d.expected_wkc = static_cast<std::uint16_t>(2 * w + r); break;
    }
  }
}

}  // namespace

Expected<ProcessImagePlan, MasterError> plan_process_image(std::span<const FmmuSpan> spans,
                                                           std::uint32_t output_bytes, std::uint32_t total_bytes,
                                                           bool use_lrw, PlanLimits limits) {
  if (limits.max_datagram_data == 0 || limits.max_datagram_data > kMaxDatagramData ||
      limits.first_frame_reserved + kDatagramOverhead >= kFrameDatagramRoom || output_bytes > total_bytes) {
    return fail(MasterError::InvalidArgument);
  }
  std::uint32_t at = 0;
  for (const FmmuSpan& s : spans) {
    if (s.logical != at) return fail(MasterError::InvalidArgument);  // gaps or overlaps
    at += s.length;
  }
  if (at != total_bytes) return fail(MasterError::InvalidArgument);

  ProcessImagePlan plan;
  Packer packer(plan, limits);
  if (use_lrw) {
    packer.region(Command::Lrw, 0, spans);
  } else {
    const auto split = std::find_if(spans.begin(), spans.end(), [&](const FmmuSpan& s) { return s.logical >= output_bytes; });
    const auto n = static_cast<std::size_t>(split - spans.begin());
    packer.region(Command::Lwr, 0, spans.first(n));
    packer.region(Command::Lrd, output_bytes, spans.subspan(n));
  }
  packer.finish();
  count_wkc(spans, plan);
  return plan;
}

}  // namespace ecat::master
