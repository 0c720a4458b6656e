#include "web/web_server.hpp"

#include <fstream>
#include <sstream>
#include <thread>
#include <utility>

#include <fmt/format.h>
#include <httplib.h>
#include <nlohmann/json.hpp>

#include "control/control_server.hpp"
#include "control/event_watcher.hpp"
#include "control/request_handler.hpp"
#include "web/event_stream.hpp"
#include "web/live_snapshot.hpp"
#include "web/request_queue.hpp"
#include "web/static_files.hpp"

namespace ecat::web {
namespace {

using nlohmann::json;

constexpr int kHttpOk = 200;
constexpr int kHttpBadRequest = 400;
constexpr int kHttpForbidden = 403;
constexpr int kHttpNotFound = 404;
constexpr int kHttpUnsupportedMediaType = 415;
constexpr int kHttpServiceUnavailable = 503;
// HTTP threads: pages' event streams hold one each, requests the rest.
constexpr std::size_t kHttpThreads = StreamSet::kMaxStreams + 8;
// How long an HTTP thread waits for the loop to answer (it answers within a tick).
constexpr std::chrono::milliseconds kReplyTimeout{5000};
// How long a stream waits for data before it sends a keep-alive comment.
constexpr std::chrono::milliseconds kStreamIdle{1000};
constexpr std::size_t kMaxEventsPerTick = 1000;
constexpr std::string_view kJson = "application/json";

std::string error_body(std::string_view code, std::string_view message) {
  return json{{"error", {{"code", code}, {"message", message}}}}.dump();
}

bool is_loopback(const std::string& host) { return host == "::1" || host.rfind("127.", 0) == 0; }

}  // namespace

struct WebServer::Impl {
  Impl(control::RequestHandler& h, const WebOptions& o)
      : handler(h), watcher(h.chain()), snapshot(h), www(o.www_dir), sample_events(o.sample_events) {}

  control::RequestHandler& handler;
  control::EventWatcher watcher;
  LiveSnapshot snapshot;
  RequestQueue queue;
  StreamSet streams;
  std::vector<std::shared_ptr<EventStream>> live;  // the loop's, kept between ticks
  std::uint64_t live_version = 0;                   // ... as StreamSet::live last gave it
  std::string www;
  bool sample_events;
  bool watching = false;
  Nanoseconds next_snapshot{Nanoseconds::min()};
  httplib::Server http;
  std::thread thread;
  std::string url;
  std::uint16_t port = 0;
  bool loopback = true;

  void routes();
  void api(const httplib::Request& req, httplib::Response& res);
  void events(httplib::Response& res);
  void file(const httplib::Request& req, httplib::Response& res);
};

void WebServer::Impl::routes() {
  http.new_task_queue = [] { return new httplib::ThreadPool(kHttpThreads); };
  http.set_payload_max_length(kMaxBodyBytes);
  http.Post("/api", [this](const httplib::Request& q, httplib::Response& r) { api(q, r); });
  http.Get("/events", [this](const httplib::Request&, httplib::Response& r) { events(r); });
  http.Get(R"(/.*)", [this](const httplib::Request& q, httplib::Response& r) { file(q, r); });
}

void WebServer::Impl::api(const httplib::Request& req, httplib::Response& res) {
  // A page of another site may POST text/plain without asking; only
  // application/json makes its browser ask first (CORS), and nothing here says yes.
  if (req.get_header_value("Content-Type").rfind(kJson, 0) != 0) {
    res.status = kHttpUnsupportedMediaType;
    res.set_content(error_body("bad_request", "POST /api takes one JSON request with Content-Type: application/json"),
                    std::string(kJson));
    return;
  }
  auto reply = queue.call(req.body, kReplyTimeout);
  if (!reply) {
    res.status = kHttpServiceUnavailable;
    res.set_content(error_body("busy", "the live loop did not answer in time (too many requests, or stopping)"),
                    std::string(kJson));
    return;
  }
  const bool refused = json::parse(*reply, nullptr, false).contains("error");
  res.status = refused ? kHttpBadRequest : kHttpOk;
  res.set_content(std::move(*reply), std::string(kJson));
}

void WebServer::Impl::events(httplib::Response& res) {
  std::shared_ptr<EventStream> stream = streams.open();
  if (!stream) {
    res.status = kHttpServiceUnavailable;
    res.set_content(error_body("busy", fmt::format("at most {} pages at once", StreamSet::kMaxStreams)),
                    std::string(kJson));
    return;
  }
  res.set_header("Cache-Control", "no-cache");
  res.set_chunked_content_provider(
      "text/event-stream",
      [stream](std::size_t, httplib::DataSink& sink) {
        std::string data = stream->take(kStreamIdle);
        if (data.empty() && stream->closed()) {
          sink.done();
          return true;
        }
        if (data.empty()) data = ": idle\n\n";  // finds a page that has gone
        return sink.write(data.data(), data.size());
      },
      [stream](bool) { stream->close(); });
}

void WebServer::Impl::file(const httplib::Request& req, httplib::Response& res) {
  const auto path = resolve_static(www, req.path);
  if (!path) {
    res.status = kHttpForbidden;
    res.set_content("refused: a path of plain names below the page's directory only\n", "text/plain");
    return;
  }
  std::ifstream in(*path, std::ios::binary);
  if (!in) {
    res.status = kHttpNotFound;
    res.set_content("not found: " + req.path + "\n", "text/plain");
    return;
  }
  std::ostringstream body;
  body << in.rdbuf();
  res.set_content(body.str(), std::string(content_type(*path)));
}

Expected<std::unique_ptr<WebServer>, std::string> WebServer::open(const WebOptions& options,
                                                                  control::RequestHandler& handler) {
  auto ep = control::parse_control_endpoint(options.listen);
  if (!ep || !ep->tcp) {
    return fail(fmt::format("--http {}: expected PORT or ADDR:PORT{}", options.listen, ep ? "" : ": " + ep.error()));
  }
  auto impl = std::make_unique<Impl>(handler, options);
  impl->routes();
  int port = ep->port;
  if (port == 0) {
    port = impl->http.bind_to_any_port(ep->host);
  } else if (!impl->http.bind_to_port(ep->host, port)) {
    port = -1;
  }
  if (port <= 0) return fail(fmt::format("--http {}: cannot listen on {}:{}", options.listen, ep->host, ep->port));
  impl->port = static_cast<std::uint16_t>(port);
  impl->loopback = is_loopback(ep->host);
  const bool v6 = ep->host.find(':') != std::string::npos;
  impl->url = fmt::format("http://{}{}{}:{}/", v6 ? "[" : "", ep->host, v6 ? "]" : "", port);
  Impl* m = impl.get();
  impl->thread = std::thread([m] { m->http.listen_after_bind(); });
  // stop() only ends a server that is running: wait until it is, so that
  // closing right after open() cannot leave the thread listening for ever.
  const auto deadline = std::chrono::steady_clock::now() + std::chrono::seconds(10);
  while (!impl->http.is_running() && std::chrono::steady_clock::now() < deadline) {
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  }
  return std::unique_ptr<WebServer>(new WebServer(std::move(impl)));
}

WebServer::WebServer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

WebServer::~WebServer() {
  impl_->streams.close_all();
  impl_->queue.close();
  impl_->http.stop();
  if (impl_->thread.joinable()) impl_->thread.join();
}

const std::string& WebServer::url() const noexcept { return impl_->url; }
std::uint16_t WebServer::port() const noexcept { return impl_->port; }
bool WebServer::loopback_only() const noexcept { return impl_->loopback; }
std::size_t WebServer::streams() const { return impl_->streams.size(); }

void WebServer::tick(Nanoseconds now) {
  next_ = now + kTick;
  Impl& m = *impl_;
  m.queue.serve(m.handler);
  std::vector<std::shared_ptr<EventStream>>& live = m.live;
  m.streams.live(live, m.live_version);
  if (live.empty()) {
    m.watching = false;
    return;
  }
  if (m.sample_events) {
    if (m.watching) {
      m.watcher.sample(now, m.handler.events());
    } else {
      m.watcher.rebase();  // a page sees what happens from now on
      m.watching = true;
    }
  }
  bool fresh = false;
  for (const auto& s : live) {
    if (!s->started) {
      s->started = true;
      s->cursor = m.handler.events().next_seq();
      fresh = true;
    }
    if (s->cursor == m.handler.events().next_seq()) continue;  // nothing new: no list built
    const json batch = m.handler.events().since(s->cursor, kMaxEventsPerTick);
    if (batch.value("lost", std::uint64_t{0}) > 0) s->send("event", json{{"type", "events_lost"}, {"count", batch["lost"]}}.dump());
    for (const json& e : batch["events"]) s->send("event", e.dump());
    s->cursor = batch["next"].get<std::uint64_t>();
  }
  if (fresh || now >= m.next_snapshot) {
    m.next_snapshot = now + kSnapshotPeriod;
    const std::string& text = m.snapshot.take();
    for (const auto& s : live) s->send("snapshot", text);
  }
}

}  // namespace ecat::web
