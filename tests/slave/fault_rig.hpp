// A line of generic servos on simulated time whose frames pass a fault
// catalogue (slave::FaultCatalogue), with the project's master on the
// in-process wire: a frame the catalogue does not return is lost to the
// master, and the replies it sends later or besides (reply faults) go on
// the wire before the reply of the frame being processed.
#pragma once

#include <gtest/gtest.h>

#include <array>
#include <map>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "slave/fault_catalogue.hpp"
#include "slave/faults/reply_faults.hpp"
#include "tests/slave/inprocess_fixture.hpp"

namespace ecat::test {

struct FaultRig : InProcess {
  slave::FaultCatalogue faults{chain};
  std::vector<std::pair<slave::FaultId, bool>> events;  // what the observer heard
  std::array<std::uint8_t, slave::faults::ReplyFaults::kMaxFrame> held{};

  explicit FaultRig(std::size_t n) {
    add_default(n);
    wire.set_processor([this](Bytes frame) {
      clock.advance(kWireTime);
      if (!faults.process_frame(frame, clock.now())) wire.drop_next(1);
      while (auto r = faults.take_reply(clock.now(), held)) wire.inject({held.data(), r->length});
    });
    faults.set_observer([this](const slave::EngagedFault& f, bool on) { events.emplace_back(f.id, on); });
  }
  slave::FaultId engage(const std::string& kind, std::optional<std::size_t> slave = std::nullopt,
                        std::map<std::string, std::int64_t> params = {}) {
    auto id = faults.engage(slave::FaultRequest{kind, slave, std::nullopt, std::move(params)});
    EXPECT_TRUE(id) << (id ? "" : id.error());
    return id ? *id : 0;
  }
  // Each bad request is refused with a message starting with the given one; nothing engaged.
  void expect_refused(std::span<const std::pair<slave::FaultRequest, std::string>> bad) {
    for (const auto& [req, message] : bad) {
      auto id = faults.engage(req);
      ASSERT_FALSE(id) << req.kind;
      EXPECT_EQ(id.error().substr(0, message.size()), message);
    }
    EXPECT_TRUE(faults.engaged().empty());
  }
};

}  // namespace ecat::test
