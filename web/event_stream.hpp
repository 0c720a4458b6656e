// The browser's live feed (issue 27, GET /events): server-sent events, one
// per page. The loop's tick appends text (events of the control interface,
// snapshots); the HTTP thread of that page waits for it and writes it out.
// The two sides share only this buffer, under its mutex.
#pragma once

#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstddef>
#include <cstdint>
#include <memory>
#include <mutex>
#include <string>
#include <vector>

namespace ecat::web {

class EventStream {
 public:
  // A page that reads nothing while this much piles up is dropped.
  static constexpr std::size_t kMaxPendingBytes = 4 << 20;

  // Loop side: appends one SSE message ("event: TYPE\ndata: JSON\n\n").
  // False when the page fell too far behind (the stream is then closed).
  bool send(std::string_view type, std::string_view data);
  // Either side: no more data; the HTTP thread ends the response.
  void close();
  bool closed() const;

  // HTTP side: waits up to `timeout` for data; empty when none came (or closed).
  std::string take(std::chrono::milliseconds timeout);

  // Loop side: the next event sequence number this page gets; unset until
  // the loop has seen the page.
  bool started = false;
  std::uint64_t cursor = 0;

 private:
  mutable std::mutex mutex_;
  std::condition_variable ready_;
  std::string pending_;
  // Written under mutex_ (the HTTP side waits on it with ready_); read
  // without it by closed(), which the loop asks for every page on every tick.
  std::atomic<bool> closed_{false};
};

// The pages connected: registered by HTTP threads, fed by the loop.
class StreamSet {
 public:
  static constexpr std::size_t kMaxStreams = 8;

  // Null when kMaxStreams pages are connected.
  std::shared_ptr<EventStream> open();
  // The loop's copy of the open streams (closed ones are dropped), into
  // `out`, whose capacity the loop keeps: no allocation per tick.
  // `version` is the caller's: when no page has connected since its last
  // copy and none of `out` has closed, `out` stays as it is, without the
  // lock or the reference counts (the loop asks every 10 ms).
  void live(std::vector<std::shared_ptr<EventStream>>& out, std::uint64_t& version);
  void close_all();
  // Cheap for the loop's idle test: how many are open.
  std::size_t size() const;

 private:
  mutable std::mutex mutex_;
  std::vector<std::shared_ptr<EventStream>> streams_;
  // Bumped under mutex_ by open() and close_all(); starts at 1 so that a
  // caller's 0 is never current.
  std::atomic<std::uint64_t> version_{1};
};

}  // namespace ecat::web
