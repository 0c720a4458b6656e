#include "control/event_queue.hpp"

#include <algorithm>

namespace ecat::control {

void EventQueue::push(nlohmann::json event) {
  event["seq"] = next_++;
  events_.push_back(std::move(event));
  while (events_.size() > capacity_) events_.pop_front();
}

nlohmann::json EventQueue::since(std::uint64_t since, std::size_t max) const {
  const std::uint64_t first = first_seq();
  const std::uint64_t from = std::clamp(since, first, next_);
  nlohmann::json list = nlohmann::json::array();
  std::uint64_t seq = from;
  for (; seq < next_ && list.size() < max; ++seq) list.push_back(events_[seq - first]);
  return nlohmann::json{{"events", std::move(list)}, {"next", seq}, {"lost", since < first ? first - since : 0}};
}

}  // namespace ecat::control
