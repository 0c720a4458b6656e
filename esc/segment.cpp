// Frame transport through a line of ESCs (Section I §3.4 frame processing order).
#include "esc/segment.hpp"

#include "esc/datagram_engine.hpp"

namespace ecat::esc {

void Segment::add(Esc& esc) {
  esc.set_link(kUpstreamPort, true);  // master or the previous slave
  if (!escs_.empty()) escs_.back()->set_link(kDownstreamPort, true);
  escs_.push_back(&esc);
}

// The frame is validated completely before the first ESC acts (a
// malformed frame changes nothing but the error counters); then each ESC's
// pass (esc/datagram_engine.hpp, inline) walks the datagrams in place.
bool Segment::process_frame(std::span<std::uint8_t> frame, Nanoseconds now) noexcept {
  const detail::EthercatAt at = detail::find_ethercat(frame);
  ValidatedDatagrams valid;
  if (at.ok) [[likely]] {
    valid = validate_ethercat(frame, at.offset);
  } else {
    valid.error = at.error;
  }
  if (valid.count == 0) [[unlikely]] {
    last_error_ = valid.error;
    ++dropped_;
    if (valid.error != FrameError::NotEtherCat) {
      // The first ESC sees a broken frame on port 0; the ones behind it get
      // it already marked and count a forwarded error (Section II 0x0300/0x0308).
      for (std::size_t i = 0; i < escs_.size(); ++i) escs_[i]->count_rx_error(kUpstreamPort, i != 0);
    }
    return false;
  }
  const DatagramView first(valid.first);
  const std::size_t count = valid.count;
  std::size_t reached = 0;
  bool lost = false;
  Nanoseconds t = now;  // when the frame reaches the next ESC's port 0
  for (Esc* esc : escs_) {
    ++reached;
    const bool carried = esc->process_datagrams(first, count, t);
    t += hop_delay_;
    if (!carried) [[unlikely]] {
      lost = true;
      break;
    }
    if (!esc->port_open_[kDownstreamPort]) break;  // closed: the frame turns back here
    if (!esc->link_[kDownstreamPort]) [[unlikely]] {
      lost = true;  // forced open with nothing connected: the frame is gone
      break;
    }
  }
  // On the way back the frame passes each earlier slave's port 1.
  // After the last reached ESC (reached - 1 hops out) it takes as many back:
  // ESC i sees it at 2 (reached - 1) - i hops.
  if (!lost && reached > 1) {
    Nanoseconds back = now + hop_delay_ * static_cast<std::int64_t>(2 * (reached - 1));
    for (std::size_t i = 0; i + 1 < reached; ++i) {
      escs_[i]->dc_.on_frame_arrival(static_cast<int>(kDownstreamPort), back);
      back -= hop_delay_;
    }
  }
  if (lost || escs_.empty()) [[unlikely]] {
    ++dropped_;
    return false;
  }
  // Every frame that passed a processing unit leaves with SOURCE_MAC[1] set (Section I §3.2).
  frame[kMacSize] = static_cast<std::uint8_t>(frame[kMacSize] | kSourceMacProcessedBit);
  ++processed_;
  return true;
}

std::optional<Nanoseconds> Segment::poll(Nanoseconds now) noexcept {
  std::optional<Nanoseconds> next;
  for (Esc* esc : escs_) {
    auto t = esc->poll(now);
    if (t && (!next || *t < *next)) next = t;
  }
  return next;
}

}  // namespace ecat::esc
