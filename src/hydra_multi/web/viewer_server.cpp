#include "hydra_multi/web/viewer_server.h"

#include <httplib.h>
#include <sys/socket.h>
#include <unistd.h>

#include <atomic>
#include <filesystem>
#include <thread>

namespace hydra_multi::web {
namespace {

namespace fs = std::filesystem;
using nlohmann::json;
using Clock = std::chrono::steady_clock;

// "EPOCH-SEQ" -> (epoch, seq); nullopt when malformed.
std::optional<std::pair<std::string, uint64_t>> parseEventId(const std::string& id) {
  const size_t dash = id.rfind('-');
  if (dash == std::string::npos || dash == 0 || dash + 1 == id.size()) return std::nullopt;
  uint64_t seq = 0;
  for (size_t i = dash + 1; i < id.size(); ++i) {
    if (id[i] < '0' || id[i] > '9' || seq > (UINT64_MAX - 9) / 10) return std::nullopt;
    seq = seq * 10 + uint64_t(id[i] - '0');
  }
  return std::make_pair(id.substr(0, dash), seq);
}

std::string event(const std::string& type, const std::string& id, const std::string& data) {
  std::string out = "event: " + type + "\n";
  if (!id.empty()) out += "id: " + id + "\n";
  out += "data: " + data + "\n\n";
  return out;
}

// One client's event stream; the content provider is called again and again until it ends.
struct Stream {
  std::shared_ptr<ViewerFeed> feed;
  const std::atomic<bool>* stopping = nullptr;
  std::function<std::map<RobotId, RobotLink>()> links;
  std::optional<std::pair<std::string, uint64_t>> resume;
  uint64_t sent = 0;  // the last view this client has
  bool started = false, ended = false;
  Clock::time_point last_write = Clock::now(), last_status = Clock::now();

  bool write(httplib::DataSink& sink, const std::string& text) {
    last_write = Clock::now();
    return sink.write(text.data(), text.size());
  }

  // One step: false ends the stream.
  bool step(httplib::DataSink& sink) {
    if (stopping->load()) return false;
    if (ended) {
      sink.done();
      return true;
    }
    if (!started) {
      const uint64_t latest = feed->latest();
      if (resume && resume->first == feed->epoch() && resume->second <= latest &&
          resume->second > 0) {
        sent = resume->second;  // deltas after it follow
        started = true;
      } else if (latest > 0) {
        const std::optional<std::string> snapshot = feed->snapshot(latest);
        if (!snapshot) return false;
        if (!write(sink,
                   event("snapshot", feed->epoch() + "-" + std::to_string(latest), *snapshot)))
          return false;
        sent = latest;
        started = true;
      }
    }
    if (started) {
      for (const std::string& delta : feed->deltasAfter(sent)) {
        ++sent;
        if (!write(sink, event("delta", feed->epoch() + "-" + std::to_string(sent), delta)))
          return false;
      }
      if (feed->ended() && sent >= feed->latest()) {
        ended = true;
        return write(sink, event("end", "", json{{"seq", sent}}.dump()));
      }
    }
    const Clock::time_point now = Clock::now();
    if (links && now - last_status >= std::chrono::seconds(1)) {
      last_status = now;
      json robots = json::object();
      for (const auto& [robot, link] : links()) {
        robots[robot.str()] = {{"connected", link.connected},
                               {"silent_s", std::round(link.silent_s * 10) / 10},
                               {"bytes", link.bytes},
                               {"done", link.done}};
      }
      if (!write(sink, event("status", "", json{{"robots", robots}}.dump()))) return false;
    }
    if (now - last_write >= std::chrono::seconds(10) && !write(sink, ": keep-alive\n\n"))
      return false;
    feed->waitNewer(sent, std::chrono::milliseconds(250));
    return true;
  }
};

}  // namespace

std::string defaultPageFolder() {
  std::error_code error;
  const fs::path exe = fs::read_symlink("/proc/self/exe", error);
  if (error) return {};
  for (const fs::path& candidate :
       {exe.parent_path() / "web", exe.parent_path().parent_path() / "web"}) {
    if (fs::exists(candidate / "index.html")) return candidate.string();
  }
  return {};
}

struct ViewerServer::Impl {
  std::shared_ptr<ViewerFeed> feed;
  ViewerServerOptions options;
  httplib::Server server;
  std::thread thread;
  std::atomic<bool> stopping{false}, listening_ended{false};
  std::atomic<size_t> streams{0};
  std::string url;
};

ViewerServer::ViewerServer(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

ViewerServer::~ViewerServer() {
  impl_->stopping = true;
  impl_->server.stop();
  if (impl_->thread.joinable()) impl_->thread.join();
}

const std::string& ViewerServer::url() const { return impl_->url; }
size_t ViewerServer::streamsServed() const { return impl_->streams.load(); }

Result<std::unique_ptr<ViewerServer>> ViewerServer::start(std::shared_ptr<ViewerFeed> feed,
                                                          ViewerServerOptions options) {
  const size_t colon = options.http.rfind(':');
  if (colon == std::string::npos || colon == 0)
    return Error{"--http " + options.http + ": not HOST:PORT (e.g. 127.0.0.1:7880)"};
  const std::string host = options.http.substr(0, colon);
  const std::string port_text = options.http.substr(colon + 1);
  int port = -1;
  try {
    size_t used = 0;
    port = std::stoi(port_text, &used);
    if (used != port_text.size()) port = -1;
  } catch (const std::exception&) {
    port = -1;
  }
  if (port < 0 || port > 65535)
    return Error{"--http " + options.http + ": the port '" + port_text + "' is not 0-65535"};
  if (options.page.empty() || !fs::exists(fs::path(options.page) / "index.html"))
    return Error{"the viewer page is not built (no index.html in '" + options.page +
                 "'): `make build` builds it with npm"};

  auto impl = std::make_unique<Impl>();
  impl->feed = std::move(feed);
  impl->options = std::move(options);
  Impl* self = impl.get();
  httplib::Server& server = impl->server;
  server.new_task_queue = [] { return new httplib::ThreadPool(16); };
  // SO_REUSEADDR only: httplib's default adds SO_REUSEPORT, which lets a second viewer share a
  // port in use instead of saying it is taken.
  server.set_socket_options([](socket_t sock) {
    int yes = 1;
    ::setsockopt(sock, SOL_SOCKET, SO_REUSEADDR, &yes, sizeof(yes));
  });
  if (!server.set_mount_point("/", self->options.page))
    return Error{"the viewer page folder '" + self->options.page + "' cannot be served"};

  const auto jsonReply = [](httplib::Response& res, int status, const std::string& body) {
    res.status = status;
    res.set_header("Cache-Control", "no-store");
    res.set_content(body, "application/json");
  };
  server.Get("/api/rounds", [self, jsonReply](const httplib::Request&, httplib::Response& res) {
    jsonReply(res, 200, self->feed->roundsJson());
  });
  server.Get("/api/view", [self, jsonReply](const httplib::Request& req, httplib::Response& res) {
    uint64_t seq = 0;
    if (req.has_param("seq")) {
      const auto parsed = parseEventId("x-" + req.get_param_value("seq"));
      if (!parsed) return jsonReply(res, 400, json{{"error", "seq is not a number"}}.dump());
      seq = parsed->second;
    }
    const std::optional<std::string> view = self->feed->snapshot(seq);
    if (!view) {
      return jsonReply(res, 404,
                       json{{"error", "no view " + std::to_string(seq) + ": the feed has " +
                                          std::to_string(self->feed->latest())}}
                           .dump());
    }
    jsonReply(res, 200, *view);
  });
  server.Get("/api/mesh", [self, jsonReply](const httplib::Request& req, httplib::Response& res) {
    const std::shared_ptr<const std::string> mesh = self->feed->mesh();
    if (!mesh) return jsonReply(res, 404, json{{"error", "no mesh yet"}}.dump());
    if (req.has_param("after")) {
      const auto after = parseEventId("x-" + req.get_param_value("after"));
      if (!after) return jsonReply(res, 400, json{{"error", "after is not a number"}}.dump());
      if (self->feed->meshSequence() <= after->second) {
        res.status = 204;  // the viewer has it
        return;
      }
    }
    res.set_header("Cache-Control", "no-store");
    res.set_header("X-Mesh-Seq", std::to_string(self->feed->meshSequence()));
    res.set_content(*mesh, "application/octet-stream");
  });
  server.Get("/api/events", [self](const httplib::Request& req, httplib::Response& res) {
    auto stream = std::make_shared<Stream>();
    stream->feed = self->feed;
    stream->stopping = &self->stopping;
    stream->links = self->options.links;
    std::string last = req.get_header_value("Last-Event-ID");
    if (last.empty() && req.has_param("last")) last = req.get_param_value("last");
    if (!last.empty()) stream->resume = parseEventId(last);
    ++self->streams;
    res.set_header("Cache-Control", "no-store");
    res.set_header("X-Accel-Buffering", "no");
    res.set_chunked_content_provider(
        "text/event-stream",
        [stream](size_t, httplib::DataSink& sink) { return stream->step(sink); });
  });

  const int bound =
      port == 0 ? server.bind_to_any_port(host) : (server.bind_to_port(host, port) ? port : -1);
  if (bound < 0) return Error{"--http " + self->options.http + ": cannot listen there (in use?)"};
  impl->url = "http://" + host + ":" + std::to_string(bound) + "/";
  impl->thread = std::thread([self] {
    self->server.listen_after_bind();
    self->listening_ended = true;
  });
  // Until it runs, httplib's stop() does nothing: a server stopped sooner would never end.
  while (!self->server.is_running() && !self->listening_ended)
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
  if (self->listening_ended) {
    impl->thread.join();
    return Error{"--http " + self->options.http + ": the server stopped as it started"};
  }
  if (self->options.log) self->options.log("viewer: " + impl->url);
  const bool loopback = host == "localhost" || host == "::1" || host.rfind("127.", 0) == 0;
  if (!loopback && self->options.log)
    self->options.log("viewer: WARNING: serving on " + host +
                      " without authentication or TLS: whoever reaches it sees the team's map");
  return std::unique_ptr<ViewerServer>(new ViewerServer(std::move(impl)));
}

}  // namespace hydra_multi::web
