// The hand-off between the HTTP threads and the live loop (issue 27): the
// slave's state is single-threaded, so an HTTP thread never touches the
// chain. It submits the request text and waits for the reply; the loop's
// tick (WebServer::service) answers every waiting request through the
// RequestHandler, between frames, as ControlServer does for its sockets.
#pragma once

#include <atomic>
#include <chrono>
#include <cstddef>
#include <deque>
#include <future>
#include <mutex>
#include <optional>
#include <string>

namespace ecat::control {
class RequestHandler;
}

namespace ecat::web {

class RequestQueue {
 public:
  // Most requests waiting at once; more are refused at once (busy).
  static constexpr std::size_t kMaxWaiting = 64;

  // From an HTTP thread: queues `request` and waits up to `timeout` for the
  // reply. Empty when the queue is full, the wait timed out or the queue closed.
  std::optional<std::string> call(std::string request, std::chrono::milliseconds timeout);

  // From the loop: answers every waiting request. Returns how many.
  std::size_t serve(control::RequestHandler& handler);
  // Refuses what waits and all later calls (the server stops).
  void close();

 private:
  struct Pending {
    std::string request;
    std::promise<std::string> reply;
  };
  std::mutex mutex_;
  std::deque<Pending> waiting_;
  // waiting_.size(), read by serve() without the lock: an idle loop's tick
  // costs one load, not a lock and an empty deque (which allocates).
  std::atomic<std::size_t> count_{0};
  bool closed_ = false;
};

}  // namespace ecat::web
