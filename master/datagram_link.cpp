#include "master/datagram_link.hpp"

#include <cstring>

#include "common/frame_builder.hpp"
#include "common/frame_parser.hpp"

namespace ecat::master {

namespace {
// Bound on frames read while waiting for one reply (stale or foreign frames).
constexpr unsigned kMaxFramesPerWait = 64;
}  // namespace

Expected<std::uint16_t, MasterError> DatagramLink::exchange(Command command, std::uint32_t address, Bytes data) {
  Datagram d{command, address, data, 0};
  if (auto r = exchange(std::span<Datagram>(&d, 1)); !r) return fail(r.error());
  return d.wkc;
}

std::size_t DatagramLink::fitting_in_one_frame(std::span<const Datagram> datagrams) noexcept {
  constexpr std::size_t kRoom = kMaxEthernetPayload - kFrameHeaderSize;
  // The index byte of a datagram is the frame's first index + its position:
  // a frame holds at most 256 distinct indices.
  constexpr std::size_t kMaxIndices = 256;
  std::size_t used = 0;
  std::size_t n = 0;
  for (const Datagram& d : datagrams) {
    const std::size_t need = kDatagramOverhead + d.data.size();
    if (used + need > kRoom || n == kMaxDatagramsPerFrame || n == kMaxIndices) break;
    used += need;
    ++n;
  }
  return n;
}

Expected<std::size_t, MasterError> DatagramLink::exchange_batch(std::span<Datagram> datagrams) {
  std::size_t frames = 0;
  while (!datagrams.empty()) {
    const std::size_t n = fitting_in_one_frame(datagrams);
    if (n == 0) return fail(MasterError::InvalidFrame);
    if (auto r = exchange(datagrams.first(n)); !r) return fail(r.error());
    datagrams = datagrams.subspan(n);
    ++frames;
  }
  return frames;
}

bool DatagramLink::matches(Bytes reply, std::uint8_t index, std::span<const Datagram> sent) const noexcept {
  auto view = parse_frame(reply);  // only reads
  if (!view || view->size() != sent.size()) return false;
  for (std::size_t i = 0; i < sent.size(); ++i) {
    const DatagramView d = (*view)[i];
    if (d.index() != static_cast<std::uint8_t>(index + i) || d.command() != sent[i].command ||
        d.length() != sent[i].data.size()) {
      return false;
    }
  }
  return true;
}

Expected<void, MasterError> DatagramLink::exchange(std::span<Datagram> datagrams) {
  if (datagrams.empty()) return fail(MasterError::InvalidArgument);
  const std::uint8_t index = next_index_;
  next_index_ = static_cast<std::uint8_t>(next_index_ + datagrams.size());

  FrameBuilder builder(tx_, kBroadcastMac, config_.source);
  for (std::size_t i = 0; i < datagrams.size(); ++i) {
    const Datagram& d = datagrams[i];
    if (!builder.append(d.command, static_cast<std::uint8_t>(index + i), d.address, d.data)) {
      return fail(MasterError::InvalidFrame);
    }
  }
  const Bytes frame = builder.finish();

  for (unsigned attempt = 0; attempt <= config_.retries; ++attempt) {
    if (auto s = transport_.send(frame); !s) {
      last_transport_error_ = s.error();
      return fail(MasterError::Transport);
    }
    ++stats_.frames_sent;
    const Nanoseconds deadline = clock_.now() + config_.frame_timeout;
    for (unsigned n = 0; n < kMaxFramesPerWait; ++n) {
      const Nanoseconds left = deadline - clock_.now();
      auto got = transport_.receive(rx_, left > Nanoseconds{0} ? left : Nanoseconds{0});
      if (!got) {
        last_transport_error_ = got.error();
        if (got.error() == transport::TransportError::Timeout) break;
        if (got.error() == transport::TransportError::BufferTooSmall) continue;
        return fail(MasterError::Transport);
      }
      const Bytes reply(rx_.data(), *got);
      if (!matches(reply, index, datagrams)) {
        ++stats_.stale_replies;
        continue;
      }
      ++stats_.frames_received;
      auto view = parse_frame(Bytes(rx_.data(), *got));
      for (std::size_t i = 0; i < datagrams.size(); ++i) {
        const DatagramView d = (*view)[i];
        if (!datagrams[i].data.empty()) {
          std::memcpy(datagrams[i].data.data(), d.data().data(), datagrams[i].data.size());
        }
        datagrams[i].wkc = d.wkc();
      }
      return {};
    }
    ++stats_.timeouts;
  }
  return fail(MasterError::Timeout);
}

}  // namespace ecat::master
