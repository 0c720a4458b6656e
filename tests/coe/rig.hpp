// The CoE stack over the FakeEsc, with master-side helpers that build request
// frames and fetch replies, so each test reads as request bytes -> reply bytes.
#pragma once

#include <gtest/gtest.h>

#include <cstddef>
#include <initializer_list>
#include <optional>
#include <vector>

#include "coe/coe_protocol.hpp"
#include "coe/mailbox_server.hpp"
#include "coe/object_store.hpp"
#include "coe/sdo_info.hpp"
#include "coe/sdo_server.hpp"
#include "tests/coe/fake_esc.hpp"
#include "tests/coe/test_device.hpp"

namespace ecat::coe::test {

using Frame = std::vector<std::uint8_t>;

inline constexpr std::uint16_t kSm0 = 0x1000;
inline constexpr std::uint16_t kSm1 = 0x1080;
inline constexpr std::uint16_t kMbxLen = 128;

// `head` then `tail`, byte by byte into a vector reserved at its final size.
// Not by inserting a range into a braced-initialised vector (GCC 12 -O3
// inlines vector::insert's reallocation path, cannot prove it dead and
// reports -Warray-bounds), nor by std::copy into a sized vector (GCC 12 -O2
// then reports the empty tail's copy at the end offset the same way).
inline Frame concat(std::initializer_list<std::uint8_t> head, const Frame& tail) {
  Frame f;
  f.reserve(head.size() + tail.size());
  for (const std::uint8_t b : head) f.push_back(b);
  for (const std::uint8_t b : tail) f.push_back(b);
  return f;
}

// Mailbox header + payload.
inline Frame mbx(std::uint8_t type, std::uint8_t counter, const Frame& payload, std::uint8_t channel = 0) {
  return concat({static_cast<std::uint8_t>(payload.size()), static_cast<std::uint8_t>(payload.size() >> 8), 0, 0,
                 channel, static_cast<std::uint8_t>(type | (counter << 4))},
                payload);
}
// CoE SDO request payload: CoE header (service 2) + 8-byte SDO header + extra.
inline Frame sdo(std::uint8_t cmd, std::uint16_t index, std::uint8_t sub, std::uint32_t data = 0,
                 const Frame& extra = {}) {
  return concat({0x00, 0x20, cmd, static_cast<std::uint8_t>(index), static_cast<std::uint8_t>(index >> 8), sub,
                 static_cast<std::uint8_t>(data), static_cast<std::uint8_t>(data >> 8),
                 static_cast<std::uint8_t>(data >> 16), static_cast<std::uint8_t>(data >> 24)},
                extra);
}
// A segment request: CoE header + command + data, padded to the 10-byte minimum.
inline Frame segment(std::uint8_t cmd, const Frame& data) {
  constexpr std::size_t kMinSegment = 10;
  Frame f = concat({0x00, 0x20, cmd}, data);
  if (f.size() < kMinSegment) f.resize(kMinSegment, 0);
  return f;
}

struct Rig {
  explicit Rig(od::DeviceDescription d = make_device(), std::size_t queue = MailboxServer::kDefaultQueueCapacity)
      : device(std::move(d)), mailbox(esc, kMbxLen, queue) {
    esc.configure_mailboxes(kSm0, kMbxLen, kSm1, kMbxLen);
    mailbox.add_service(coe);
  }

  // Writes a request, polls, and returns the reply frame trimmed to its
  // header length (nullopt when SM1 stayed empty).
  std::optional<Frame> request(const Frame& frame) {
    EXPECT_TRUE(esc.master_write(frame));
    mailbox.poll(Nanoseconds{0});
    return fetch();
  }
  std::optional<Frame> fetch() {
    auto raw = esc.master_read();
    if (!raw) return std::nullopt;
    const std::size_t len = 6 + ((*raw)[0] | ((*raw)[1] << 8));
    raw->resize(std::min(raw->size(), len));
    mailbox.poll(Nanoseconds{0});
    return raw;
  }
  // SDO request payload -> reply payload (mailbox header stripped, counter auto).
  Frame sdo_request(const Frame& payload) {
    counter = MailboxHeader::next_counter(counter);
    auto reply = request(mbx(3, counter, payload));
    if (!reply) return {};
    return Frame(reply->begin() + 6, reply->end());
  }

  od::DeviceDescription device;
  FakeEsc esc;
  ObjectStore store{device.dictionary};
  SdoServer server{store};
  SdoInfo info{store};
  CoeProtocol coe{server, &info};
  MailboxServer mailbox;
  std::uint8_t counter = 0;
};

}  // namespace ecat::coe::test
