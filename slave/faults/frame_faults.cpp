#include "slave/faults/frame_faults.hpp"

#include <algorithm>

namespace ecat::slave::faults {

bool FrameFaults::remove(FrameFaultId id) noexcept {
  const auto n = drops_.size() + wkcs_.size();
  std::erase_if(drops_, [id](const DropRule& r) { return r.id == id; });
  std::erase_if(wkcs_, [id](const WkcRule& r) { return r.id == id; });
  return drops_.size() + wkcs_.size() != n;
}

bool FrameFaults::addresses(const FrameView& frame, std::uint16_t position, std::uint16_t station) noexcept {
  for (DatagramView d : frame) {
    switch (addressing(d.command())) {
      case Addressing::AutoIncrement:
        // The master sends ADP = -position; each slave on the way adds one
        // (ETG.1000.4 §5.4.1.1): the slave at `position` sees 0.
        if (static_cast<std::uint16_t>(d.adp() + position) == 0) return true;
        break;
      case Addressing::Configured:
        if (d.adp() == station) return true;
        break;
      default:
        break;
    }
  }
  return false;
}

bool FrameFaults::lose_before(std::span<std::uint8_t> frame) noexcept {
  matched_.clear();
  std::optional<FrameView> view;
  bool lost = false;
  for (auto it = drops_.begin(); it != drops_.end();) {
    DropRule& r = *it;
    if (r.position) {
      if (!view) {
        auto v = parse_frame(frame);
        if (!v) return false;  // malformed: the chain counts it
        view = *v;
      }
      if (addresses(*view, *r.position, r.station)) matched_.push_back(r.id);
      ++it;
      continue;
    }
    if (r.after || lost) {
      ++it;
      continue;
    }
    lost = true;
    it = use(r) ? drops_.erase(it) : it + 1;
  }
  return lost;
}

bool FrameFaults::lose_after(std::span<std::uint8_t> frame) noexcept {
  bool lost = false;
  for (auto it = drops_.begin(); it != drops_.end() && !lost;) {
    DropRule& r = *it;
    const bool hit = r.position ? std::find(matched_.begin(), matched_.end(), r.id) != matched_.end() : r.after;
    if (!hit) {
      ++it;
      continue;
    }
    lost = true;
    it = use(r) ? drops_.erase(it) : it + 1;
  }
  matched_.clear();
  if (lost || wkcs_.empty()) return lost;
  auto view = parse_frame(frame);
  if (!view) return false;
  for (auto it = wkcs_.begin(); it != wkcs_.end();) {
    WkcRule& r = *it;
    bool applied = false;
    for (DatagramView d : *view) {
      if (d.command() != r.command) continue;
      d.set_wkc(static_cast<std::uint16_t>(d.wkc() + r.offset));
      applied = true;
    }
    it = applied && use(r) ? wkcs_.erase(it) : it + 1;
  }
  return false;
}

}  // namespace ecat::slave::faults
