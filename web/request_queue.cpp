#include "web/request_queue.hpp"

#include <utility>

#include "control/request_handler.hpp"

namespace ecat::web {

std::optional<std::string> RequestQueue::call(std::string request, std::chrono::milliseconds timeout) {
  std::future<std::string> reply;
  {
    const std::lock_guard lock(mutex_);
    if (closed_ || waiting_.size() >= kMaxWaiting) return std::nullopt;
    waiting_.push_back(Pending{std::move(request), {}});
    reply = waiting_.back().reply.get_future();
    count_.store(waiting_.size(), std::memory_order_release);
  }
  if (reply.wait_for(timeout) != std::future_status::ready) return std::nullopt;
  try {
    return reply.get();
  } catch (const std::future_error&) {  // closed before it was answered
    return std::nullopt;
  }
}

std::size_t RequestQueue::serve(control::RequestHandler& handler) {
  if (count_.load(std::memory_order_acquire) == 0) return 0;
  std::deque<Pending> batch;
  {
    const std::lock_guard lock(mutex_);
    batch.swap(waiting_);
    count_.store(0, std::memory_order_release);
  }
  for (Pending& p : batch) p.reply.set_value(handler.handle_line(p.request));
  return batch.size();
}

void RequestQueue::close() {
  const std::lock_guard lock(mutex_);
  closed_ = true;
  count_.store(0, std::memory_order_release);
  waiting_.clear();  // each promise broken: its caller gets nothing
}

}  // namespace ecat::web
