// Cable redundancy (see redundant_transport.hpp and docs/master.md "Cable redundancy").
#include "master/redundant_transport.hpp"

#include <algorithm>
#include <cstring>

#include "common/frame_builder.hpp"
#include "common/frame_parser.hpp"
#include "master/poll_budget.hpp"

namespace ecat::master {

namespace {

// Bytes 2-3 of the source MAC (frame bytes 8-9) carry the port marker.
constexpr std::size_t kMarkerOffset = kMacSize + 2;
constexpr std::size_t kMarkerSize = 2;
// Longest single wait on one port before looking at the other (SOEM polls
// both sockets with 50 µs ppoll slices).
constexpr Nanoseconds kPollSlice = std::chrono::microseconds(50);
// The dummy: BRD of the ESC type register, 2 bytes (SOEM's secondary frame).
constexpr std::uint16_t kDummyRegister = 0x0000;
constexpr std::size_t kDummyLength = 2;

bool marked(ConstBytes frame, const MacAddress& mac) noexcept {
  return frame.size() >= kEthernetHeaderSize &&
         std::memcmp(frame.data() + kMarkerOffset, mac.data() + 2, kMarkerSize) == 0;
}

void mark(Bytes frame, const MacAddress& mac) noexcept {
  if (frame.size() >= kEthernetHeaderSize) std::memcpy(frame.data() + kMarkerOffset, mac.data() + 2, kMarkerSize);
}

}  // namespace

std::string_view describe(RingState s) noexcept {
  switch (s) {
    case RingState::Unknown: return "unknown";
    case RingState::Intact: return "ring intact";
    case RingState::Broken: return "ring broken";
    case RingState::PrimaryLinkDown: return "primary link down";
    case RingState::SecondaryLinkDown: return "secondary link down";
    case RingState::NoReply: return "no reply on either port";
  }
  return "?";
}

RedundantTransport::RedundantTransport(transport::Transport& primary, transport::Transport& secondary,
                                       const Clock& clock, unsigned max_polls) noexcept
    : primary_(primary), secondary_(secondary), clock_(clock), max_polls_(max_polls) {}

Expected<void, transport::TransportError> RedundantTransport::send(ConstBytes frame) {
  if (frame.size() > tx_.size()) return fail(transport::TransportError::FrameTooLarge);
  std::memcpy(tx_.data(), frame.data(), frame.size());
  tx_length_ = frame.size();
  const Bytes tx(tx_.data(), tx_length_);
  auto view = parse_frame(tx);
  if (!view || view->size() == 0) return fail(transport::TransportError::InvalidFrame);
  index_ = (*view)[0].index();
  mark(tx, kPrimarySourceMac);

  FrameBuilder dummy(dummy_, kBroadcastMac, kSecondarySourceMac);
  const std::uint8_t zero[kDummyLength]{};
  if (!dummy.append(Command::Brd, index_, device_address(0, kDummyRegister), zero)) {
    return fail(transport::TransportError::InvalidFrame);
  }
  dummy_length_ = dummy.finish().size();

  auto p = primary_.send(tx);
  auto s = secondary_.send(ConstBytes(dummy_.data(), dummy_length_));
  if (!p && !s) return fail(p.error());
  pending_ = true;
  return {};
}

RedundantTransport::Seen RedundantTransport::poll(transport::Transport& port, Bytes into, std::size_t& length,
                                                  Nanoseconds wait) {
  auto got = port.receive(into, wait);
  if (!got) return Seen::Nothing;  // timeout, or a port that cannot receive (link down)
  (&port == &primary_ ? primary_heard_ : secondary_heard_) = true;
  const Bytes frame(into.data(), *got);
  auto view = parse_frame(frame);
  if (!view || view->size() == 0 || (*view)[0].index() != index_) {
    ++stats_.stale;
    return Seen::Nothing;
  }
  length = *got;
  if (marked(frame, kPrimarySourceMac)) return Seen::PrimaryFrame;
  if (marked(frame, kSecondarySourceMac)) return Seen::SecondaryFrame;
  ++stats_.stale;
  return Seen::Nothing;
}

Expected<std::size_t, transport::TransportError> RedundantTransport::deliver(Bytes from, std::size_t length,
                                                                             Bytes buffer) {
  if (length > buffer.size()) return fail(transport::TransportError::BufferTooSmall);
  std::memcpy(buffer.data(), from.data(), length);
  return length;
}

void RedundantTransport::finish(RingState s) noexcept {
  state_ = s;
  switch (s) {
    case RingState::Intact: ++stats_.intact; break;
    case RingState::Broken: ++stats_.broken; break;
    case RingState::PrimaryLinkDown:
      ++stats_.primary_down;
      primary_heard_ = false;
      break;
    case RingState::SecondaryLinkDown:
      ++stats_.secondary_down;
      secondary_heard_ = false;
      break;
    case RingState::NoReply: ++stats_.no_reply; break;
    case RingState::Unknown: break;
  }
}

Expected<std::size_t, transport::TransportError> RedundantTransport::resend_on_secondary(Bytes frame, Bytes buffer,
                                                                                         Nanoseconds timeout) {
  if (frame.data() != tx_.data()) {
    std::memcpy(tx_.data(), frame.data(), frame.size());
    tx_length_ = frame.size();
  }
  const Bytes tx(tx_.data(), tx_length_);
  mark(tx, kPrimarySourceMac);
  if (auto s = secondary_.send(tx); !s) return fail(s.error());
  ++stats_.resent;
  PollBudget budget(clock_, timeout, max_polls_);
  const Nanoseconds deadline = clock_.now() + timeout;
  std::size_t length = 0;
  while (budget.next()) {
    const Nanoseconds wait = std::clamp(deadline - clock_.now(), Nanoseconds{0}, kPollSlice);
    if (poll(secondary_, rx_secondary_, length, wait) == Seen::PrimaryFrame) {
      return deliver(rx_secondary_, length, buffer);
    }
  }
  return fail(transport::TransportError::Timeout);
}

Expected<std::size_t, transport::TransportError> RedundantTransport::receive(Bytes buffer, Nanoseconds timeout) {
  if (!pending_) return primary_.receive(buffer, timeout);
  pending_ = false;
  PollBudget budget(clock_, timeout, max_polls_);
  const Nanoseconds deadline = clock_.now() + timeout;
  Seen on_primary = Seen::Nothing;
  Seen on_secondary = Seen::Nothing;
  std::size_t primary_length = 0;
  std::size_t secondary_length = 0;
  auto dummy_wkc = [&] {
    auto v = parse_frame(Bytes(rx_secondary_.data(), secondary_length));
    return v && v->size() > 0 ? (*v)[0].wkc() : std::uint16_t{0};
  };
  while (budget.next()) {
    // Block only on the port the reply is expected on (the other is polled):
    // the secondary while the ring was intact, else the primary; once one
    // port has answered, the other.
    const Nanoseconds wait = std::clamp(deadline - clock_.now(), Nanoseconds{0}, kPollSlice);
    const bool expect_secondary = on_primary != Seen::Nothing ||
                                  (on_secondary == Seen::Nothing && (state_ == RingState::Intact ||
                                                                     state_ == RingState::PrimaryLinkDown));
    if (on_primary == Seen::Nothing) {
      on_primary = poll(primary_, rx_primary_, primary_length, expect_secondary ? Nanoseconds{0} : wait);
    }
    if (on_secondary == Seen::Nothing) {
      on_secondary = poll(secondary_, rx_secondary_, secondary_length, expect_secondary ? wait : Nanoseconds{0});
    }
    if (on_secondary == Seen::PrimaryFrame) {
      // Intact: the frame went round. Take the dummy off the primary port if it is there.
      if (on_primary == Seen::Nothing) (void)poll(primary_, rx_primary_, primary_length, Nanoseconds{0});
      finish(RingState::Intact);
      return deliver(rx_secondary_, secondary_length, buffer);
    }
    // A port found down in the last exchange is looked at once more before
    // the other's frame settles the exchange: its reply may have come in
    // while the other port was waited on.
    const bool secondary_was_down = state_ == RingState::SecondaryLinkDown;
    const bool primary_was_down = state_ == RingState::PrimaryLinkDown;
    if (secondary_was_down && on_primary == Seen::PrimaryFrame && on_secondary == Seen::Nothing) {
      on_secondary = poll(secondary_, rx_secondary_, secondary_length, Nanoseconds{0});
    }
    if (primary_was_down && on_secondary == Seen::SecondaryFrame && on_primary == Seen::Nothing) {
      on_primary = poll(primary_, rx_primary_, primary_length, Nanoseconds{0});
    }
    if (on_primary == Seen::PrimaryFrame && on_secondary == Seen::SecondaryFrame) {
      secondary_side_slaves_ = dummy_wkc();
      finish(RingState::Broken);
      return resend_on_secondary(Bytes(rx_primary_.data(), primary_length), buffer, timeout);
    }
    // Such a port is not waited for again, unless a frame has come in on it
    // since it was found down (a late reply of an earlier exchange: a host
    // that was held up, not a cut cable).
    if (secondary_was_down && on_primary == Seen::PrimaryFrame && !secondary_heard_) break;
    if (primary_was_down && on_secondary == Seen::SecondaryFrame && on_primary == Seen::Nothing && !primary_heard_) {
      break;
    }
  }
  if (on_primary == Seen::PrimaryFrame) {
    finish(RingState::SecondaryLinkDown);
    return deliver(rx_primary_, primary_length, buffer);
  }
  if (on_secondary == Seen::SecondaryFrame) {
    secondary_side_slaves_ = dummy_wkc();
    finish(RingState::PrimaryLinkDown);
    return resend_on_secondary(Bytes(tx_.data(), tx_length_), buffer, timeout);
  }
  finish(RingState::NoReply);
  return fail(transport::TransportError::Timeout);
}

std::optional<RingBreak> RedundantTransport::ring_break(std::size_t slave_count) const noexcept {
  if (state_ != RingState::Broken || secondary_side_slaves_ == 0 || secondary_side_slaves_ >= slave_count) {
    return std::nullopt;
  }
  const std::size_t first = slave_count - secondary_side_slaves_;
  return RingBreak{first - 1, first};
}

}  // namespace ecat::master
