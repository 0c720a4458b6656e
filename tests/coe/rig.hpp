// The CoE stack over the FakeEsc, with master-side helpers that build request
// frames and fetch replies, so each test reads as request bytes -> reply bytes.
#pragma once

#include <gtest/gtest.h>

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

// Mailbox header + payload.
inline Frame mbx(std::uint8_t type, std::uint8_t counter, Frame payload, std::uint8_t channel = 0) {
  Frame f{static_cast<std::uint8_t>(payload.size()), static_cast<std::uint8_t>(payload.size() >> 8), 0, 0, channel,
          static_cast<std::uint8_t>(type | (counter << 4))};
  f.insert(f.end(), payload.begin(), payload.end());
  return f;
}
// CoE SDO request payload: CoE header (service 2) + 8-byte SDO header + extra.
inline Frame sdo(std::uint8_t cmd, std::uint16_t index, std::uint8_t sub, std::uint32_t data = 0, Frame extra = {}) {
  Frame f{0x00, 0x20, cmd, static_cast<std::uint8_t>(index), static_cast<std::uint8_t>(index >> 8), sub,
          static_cast<std::uint8_t>(data), static_cast<std::uint8_t>(data >> 8), static_cast<std::uint8_t>(data >> 16),
          static_cast<std::uint8_t>(data >> 24)};
  f.insert(f.end(), extra.begin(), extra.end());
  return f;
}
inline Frame segment(std::uint8_t cmd, Frame data) {
  Frame f{0x00, 0x20, cmd};
  f.insert(f.end(), data.begin(), data.end());
  while (f.size() < 10) f.push_back(0);
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
