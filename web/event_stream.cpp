#include "web/event_stream.hpp"

#include <algorithm>

namespace ecat::web {

bool EventStream::send(std::string_view type, std::string_view data) {
  {
    const std::lock_guard lock(mutex_);
    if (closed_) return false;
    if (pending_.size() + data.size() > kMaxPendingBytes) {
      closed_ = true;
    } else {
      pending_.append("event: ").append(type).append("\ndata: ").append(data).append("\n\n");
    }
  }
  ready_.notify_all();
  return !closed();
}

void EventStream::close() {
  {
    const std::lock_guard lock(mutex_);
    closed_ = true;
  }
  ready_.notify_all();
}

bool EventStream::closed() const { return closed_.load(std::memory_order_acquire); }

std::string EventStream::take(std::chrono::milliseconds timeout) {
  std::unique_lock lock(mutex_);
  ready_.wait_for(lock, timeout, [&] { return closed_ || !pending_.empty(); });
  std::string out;
  out.swap(pending_);
  return out;
}

std::shared_ptr<EventStream> StreamSet::open() {
  const std::lock_guard lock(mutex_);
  std::erase_if(streams_, [](const auto& s) { return s->closed(); });
  if (streams_.size() >= kMaxStreams) return nullptr;
  streams_.push_back(std::make_shared<EventStream>());
  version_.fetch_add(1, std::memory_order_release);
  return streams_.back();
}

void StreamSet::live(std::vector<std::shared_ptr<EventStream>>& out, std::uint64_t& version) {
  const auto closed = [](const auto& s) { return s->closed(); };
  if (version == version_.load(std::memory_order_acquire) && std::none_of(out.begin(), out.end(), closed)) return;
  out.clear();
  const std::lock_guard lock(mutex_);
  std::erase_if(streams_, closed);
  out.assign(streams_.begin(), streams_.end());
  version = version_.load(std::memory_order_relaxed);
}

void StreamSet::close_all() {
  const std::lock_guard lock(mutex_);
  for (auto& s : streams_) s->close();
  streams_.clear();
  version_.fetch_add(1, std::memory_order_release);
}

std::size_t StreamSet::size() const {
  const std::lock_guard lock(mutex_);
  return streams_.size();
}

}  // namespace ecat::web
