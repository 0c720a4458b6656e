// What the page redraws from (issue 27): one JSON object built on the loop's
// tick, a few times a second and only while a page is connected, from the
// control interface's own commands - "network", "faults",
// and for CiA 402 drives the objects the plots show - so the page and a
// Python client see the same data. The process data of the slave the page
// shows is its own "pdo" request (one slave, not all of them each time).
#pragma once

#include <cstddef>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>

namespace ecat::control {
class RequestHandler;
}

namespace ecat::web {

class LiveSnapshot {
 public:
  explicit LiveSnapshot(control::RequestHandler& handler) : handler_(handler) {}

  // {"network": .., "drives": [{"slave", objects..}],
  //  "faults": [..], "time_ns": ..}
  nlohmann::json take();

 private:
  // Which slaves have a statusword 6041h (found on the first take).
  const std::vector<bool>& drives(std::size_t slaves);

  control::RequestHandler& handler_;
  std::optional<std::vector<bool>> drives_;
};

}  // namespace ecat::web
