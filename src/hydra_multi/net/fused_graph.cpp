#include "hydra_multi/net/fused_graph.h"

#include <atomic>
#include <condition_variable>
#include <deque>
#include <mutex>
#include <nlohmann/json.hpp>
#include <thread>
#include <zmq.hpp>
#include <zmq_addon.hpp>

#include "hydra_multi/dsg/graph_delta.h"
#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/dsg/io/byte_codec.h"
#include "hydra_multi/dsg/io/decode_error.h"
#include "hydra_multi/net/clock.h"
#include "hydra_multi/net/interruptible_poll.h"

namespace hydra_multi::net {
namespace {

using Json = nlohmann::json;

constexpr uint8_t kVersion = 1;
enum Type : uint8_t { kDelta = 1, kSnapshotRequest = 2, kSnapshot = 3 };

std::string header(Type type, uint64_t sequence) {
  io::ByteWriter w;
  w.raw("HG");
  w.u8(kVersion);
  w.u8(type);
  if (type != kSnapshotRequest) w.u64(sequence);
  return w.release();
}

// The type and sequence of a header; an error names what is wrong.
Result<std::pair<Type, uint64_t>> readHeader(const std::string& frame) {
  if (frame.size() < 4 || frame.compare(0, 2, "HG") != 0)
    return Error{"frame 0: not a fused-graph message (no \"HG\" header)"};
  if (static_cast<uint8_t>(frame[2]) != kVersion)
    return Error{"frame 0: fused-graph version " + std::to_string(uint8_t(frame[2])) +
                 ", this one reads " + std::to_string(kVersion)};
  const uint8_t type = static_cast<uint8_t>(frame[3]);
  if (type < kDelta || type > kSnapshot)
    return Error{"frame 0: unknown fused-graph message type " + std::to_string(type)};
  const size_t want = type == kSnapshotRequest ? 4 : 12;
  if (frame.size() != want)
    return Error{"frame 0: a header of " + std::to_string(frame.size()) + " bytes, not " +
                 std::to_string(want)};
  uint64_t sequence = 0;
  if (want == 12) {
    io::ByteReader r(std::string_view(frame).substr(4), 4);
    sequence = r.u64("sequence");
  }
  return std::pair<Type, uint64_t>{static_cast<Type>(type), sequence};
}

Json summaryJson(const FusedSummary& s) {
  Json nodes = Json::object();
  for (const Layer layer : kAllLayers)
    nodes[layerName(layer)] = s.nodes[static_cast<size_t>(layer)];
  return Json{{"round", s.round},
              {"robots", s.robots},
              {"robots_aligned", s.robots_aligned},
              {"nodes", nodes},
              {"final", s.final}};
}

Result<FusedSummary> parseSummary(const std::string& text, uint64_t sequence) {
  const Json j = Json::parse(text, nullptr, false);
  if (j.is_discarded() || !j.is_object()) return Error{"frame 1: not a JSON object"};
  FusedSummary s;
  s.sequence = sequence;
  try {
    s.round = j.at("round").get<size_t>();
    s.robots = j.at("robots").get<size_t>();
    s.robots_aligned = j.at("robots_aligned").get<size_t>();
    s.final = j.value("final", false);
    for (const Layer layer : kAllLayers)
      s.nodes[static_cast<size_t>(layer)] = j.at("nodes").value(layerName(layer), size_t{0});
  } catch (const Json::exception& e) {
    return Error{std::string("frame 1: ") + e.what()};
  }
  return s;
}

FusedSummary summaryOf(const SceneGraph& graph, uint64_t sequence, size_t round, size_t robots,
                       size_t aligned) {
  FusedSummary s;
  s.sequence = sequence;
  s.round = round;
  s.robots = robots;
  s.robots_aligned = aligned;
  for (const Layer layer : kAllLayers) s.nodes[static_cast<size_t>(layer)] = graph.numNodes(layer);
  return s;
}

// The host part of "tcp://HOST:PORT", and the port.
std::pair<std::string, std::string> splitEndpoint(const std::string& endpoint) {
  const size_t colon = endpoint.rfind(':');
  if (colon == std::string::npos) return {endpoint, ""};
  return {endpoint.substr(0, colon), endpoint.substr(colon + 1)};
}

void sendFrames(zmq::socket_t& socket, const std::vector<std::string>& frames) {
  std::vector<zmq::message_t> parts;
  for (const std::string& f : frames) parts.emplace_back(f.data(), f.size());
  (void)zmq::send_multipart(socket, parts, zmq::send_flags::dontwait);
}

}  // namespace

std::string describeFused(const FusedSummary& s) {
  std::string text =
      "sequence " + std::to_string(s.sequence) + " (round " + std::to_string(s.round) + "):";
  for (const Layer layer : kAllLayers)
    text += std::string(layer == kAllLayers.front() ? " " : ", ") + layerName(layer) + " " +
            std::to_string(s.nodes[static_cast<size_t>(layer)]);
  text +=
      "; robots aligned " + std::to_string(s.robots_aligned) + " of " + std::to_string(s.robots);
  if (s.final) text += "; the station's final graph";
  return text;
}

// --- the publisher ---

struct GraphPublisher::Impl {
  struct Round {
    SceneGraph graph;
    size_t round = 0, robots = 0, aligned = 0;
    bool final = false;
  };
  Impl(GraphPublisherOptions o)
      : options(std::move(o)),
        router(context, zmq::socket_type::router),
        pub(context, zmq::socket_type::pub) {}
  void log(const std::string& line) const {
    if (options.log) options.log(line);
  }
  void loop();
  void answer(const std::string& id);

  GraphPublisherOptions options;
  zmq::context_t context;
  zmq::socket_t router, pub;
  std::string endpoint, publish_endpoint;
  int publish_port = 0;
  std::mutex mutex;
  std::condition_variable drained;
  std::deque<Round> queue;
  bool stopping = false, closed = false;
  std::atomic<uint64_t> published{0};
  // The thread's own.
  SceneGraph last;
  FusedSummary last_summary;
  std::thread thread;
};

void GraphPublisher::Impl::answer(const std::string& id) {
  Json summary = summaryJson(last_summary);
  summary["publish_port"] = publish_port;
  std::vector<zmq::message_t> parts;
  parts.emplace_back(id.data(), id.size());
  for (const std::string& f :
       {header(kSnapshot, last_summary.sequence), summary.dump(), io::encodeSceneGraphBinary(last)})
    parts.emplace_back(f.data(), f.size());
  (void)zmq::send_multipart(router, parts, zmq::send_flags::dontwait);
}

void GraphPublisher::Impl::loop() {
  for (;;) {
    zmq::pollitem_t items[] = {{router.handle(), 0, ZMQ_POLLIN, 0}};
    interruptiblePoll(items, 1, std::chrono::milliseconds(20));
    for (int i = 0; i < 100; ++i) {
      std::vector<zmq::message_t> parts;
      if (!zmq::recv_multipart(router, std::back_inserter(parts), zmq::recv_flags::dontwait)) break;
      if (parts.size() < 2) continue;
      const auto head = readHeader(parts[1].to_string());
      if (head && head.value().first == kSnapshotRequest)
        answer(parts[0].to_string());
      else
        log("publisher: ignored a message that is not a snapshot request" +
            (head ? std::string() : ": " + head.error()));
    }
    std::optional<Round> round;
    {
      std::lock_guard<std::mutex> lock(mutex);
      if (!queue.empty()) {
        round = std::move(queue.front());
        queue.pop_front();
      } else if (stopping) {
        drained.notify_all();
        return;
      } else {
        drained.notify_all();
      }
    }
    if (!round) continue;
    // The final marker changes nothing (an empty GraphDelta would cut the mesh: its starts are 0).
    const GraphDelta delta = diffGraphs(last, round->final ? last : round->graph);
    if (!round->final) last = std::move(round->graph);
    FusedSummary summary = round->final
                               ? last_summary
                               : summaryOf(last, 0, round->round, round->robots, round->aligned);
    summary.sequence = last_summary.sequence + 1;
    summary.final = round->final;
    last_summary = summary;
    sendFrames(pub, {header(kDelta, summary.sequence), summaryJson(summary).dump(),
                     io::encodeGraphDeltaBinary(delta)});
    ++published;
  }
}

Result<std::unique_ptr<GraphPublisher>> GraphPublisher::create(GraphPublisherOptions options) {
  auto impl = std::make_unique<Impl>(std::move(options));
  try {
    for (zmq::socket_t* s : {&impl->router, &impl->pub}) s->set(zmq::sockopt::linger, 1000);
    impl->router.bind(impl->options.endpoint);
    impl->endpoint = impl->router.get(zmq::sockopt::last_endpoint);
    const auto [host, port] = splitEndpoint(impl->options.endpoint);
    const auto bound_port = splitEndpoint(impl->endpoint).second;
    const std::string pub_port = port == "*" ? "*" : std::to_string(std::stoi(bound_port) + 1);
    impl->pub.bind(host + ":" + pub_port);
    impl->publish_endpoint = impl->pub.get(zmq::sockopt::last_endpoint);
    impl->publish_port = std::stoi(splitEndpoint(impl->publish_endpoint).second);
  } catch (const zmq::error_t& e) {
    return Error{impl->options.endpoint + ": cannot publish: " + e.what()};
  } catch (const std::exception&) {
    return Error{impl->options.endpoint + ": cannot publish: not tcp://HOST:PORT"};
  }
  Impl* raw = impl.get();
  impl->thread = std::thread([raw] { raw->loop(); });
  return std::unique_ptr<GraphPublisher>(new GraphPublisher(std::move(impl)));
}

GraphPublisher::GraphPublisher(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

GraphPublisher::~GraphPublisher() {
  close();
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->stopping = true;
  }
  if (impl_->thread.joinable()) impl_->thread.join();
}

const std::string& GraphPublisher::endpoint() const { return impl_->endpoint; }
const std::string& GraphPublisher::publishEndpoint() const { return impl_->publish_endpoint; }
uint64_t GraphPublisher::published() const { return impl_->published; }

void GraphPublisher::publish(const SceneGraph& graph, size_t round, size_t robots,
                             size_t robots_aligned) {
  std::lock_guard<std::mutex> lock(impl_->mutex);
  if (impl_->closed) return;
  // A round not yet published is overtaken by this one: subscribers want the latest.
  if (!impl_->queue.empty()) impl_->queue.pop_back();
  impl_->queue.push_back({graph, round, robots, robots_aligned, false});
}

void GraphPublisher::close(std::chrono::milliseconds timeout) {
  std::unique_lock<std::mutex> lock(impl_->mutex);
  if (impl_->closed) return;
  impl_->closed = true;
  impl_->queue.push_back({SceneGraph(), 0, 0, 0, true});
  impl_->drained.wait_for(lock, timeout, [&] { return impl_->queue.empty(); });
}

// --- the subscriber ---

WatchState::Outcome WatchState::onSnapshot(const FusedSummary& summary, SceneGraph graph) {
  if (started_ && summary.sequence <= summary_.sequence) return Outcome::kStale;
  summary_ = summary;
  graph_ = std::move(graph);
  started_ = true;
  return Outcome::kApplied;
}

WatchState::Outcome WatchState::onDelta(const FusedSummary& summary, const GraphDelta& delta) {
  if (!started_) return Outcome::kGap;
  if (summary.sequence <= summary_.sequence) return Outcome::kStale;
  if (summary.sequence > summary_.sequence + 1) return Outcome::kGap;
  if (!applyDelta(graph_, delta).ok()) return Outcome::kBroken;
  summary_ = summary;
  return Outcome::kApplied;
}

struct GraphWatcher::Impl {
  explicit Impl(GraphWatcherOptions o)
      : options(std::move(o)), dealer(context, zmq::socket_type::dealer) {
    dealer.set(zmq::sockopt::linger, 0);
    dealer.connect(options.connect);
  }
  void log(const std::string& line) const {
    if (options.log) options.log(line);
  }
  void request() {
    sendFrames(dealer, {header(kSnapshotRequest, 0)});
    requested_at = Clock::now();
    waiting = true;
  }

  GraphWatcherOptions options;
  zmq::context_t context;
  zmq::socket_t dealer;
  std::optional<zmq::socket_t> sub;
  WatchState state;
  bool waiting = false, ended = false;
  Clock::time_point requested_at;
  size_t snapshots = 0, deltas = 0;
};

GraphWatcher::GraphWatcher(GraphWatcherOptions options)
    : impl_(std::make_unique<Impl>(std::move(options))) {}
GraphWatcher::~GraphWatcher() = default;
const WatchState& GraphWatcher::state() const { return impl_->state; }
bool GraphWatcher::ended() const { return impl_->ended; }
size_t GraphWatcher::snapshots() const { return impl_->snapshots; }
size_t GraphWatcher::deltas() const { return impl_->deltas; }

Status GraphWatcher::pump(std::chrono::milliseconds budget,
                          const std::function<void(const WatchState&)>& each) {
  Impl& w = *impl_;
  const Clock::time_point end = Clock::now() + budget;
  do {
    if (!w.state.started() && !w.waiting) w.request();
    if (w.waiting && secondsSince(w.requested_at) > w.options.request_timeout_s)
      return Error{w.options.connect + ": no answer to a snapshot request within " +
                   secondsText(w.options.request_timeout_s) + " s"};
    zmq::pollitem_t items[] = {{w.dealer.handle(), 0, ZMQ_POLLIN, 0},
                               {w.sub ? w.sub->handle() : nullptr, 0, ZMQ_POLLIN, 0}};
    interruptiblePoll(items, w.sub ? 2 : 1, std::chrono::milliseconds(20));
    std::vector<zmq::message_t> parts;
    while (zmq::recv_multipart(w.dealer, std::back_inserter(parts), zmq::recv_flags::dontwait)) {
      const auto head = parts.empty() ? Result<std::pair<Type, uint64_t>>(Error{"empty"})
                                      : readHeader(parts[0].to_string());
      if (!head || head.value().first != kSnapshot || parts.size() != 3)
        return Error{w.options.connect + ": not a fused-graph snapshot" +
                     (head ? std::string() : ": " + head.error())};
      auto summary = parseSummary(parts[1].to_string(), head.value().second);
      auto graph = io::decodeSceneGraphBinary(parts[2].to_string());
      if (!summary || !graph)
        return Error{w.options.connect +
                     ": snapshot: " + (summary ? graph.error() : summary.error())};
      w.waiting = false;
      if (!w.sub) {  // the PUB's port is in the reply
        const Json j = Json::parse(parts[1].to_string(), nullptr, false);
        const int port = j.is_object() ? j.value("publish_port", 0) : 0;
        w.sub.emplace(w.context, zmq::socket_type::sub);
        w.sub->set(zmq::sockopt::linger, 0);
        w.sub->set(zmq::sockopt::subscribe, "");
        w.sub->connect(splitEndpoint(w.options.connect).first + ":" + std::to_string(port));
      }
      ++w.snapshots;
      if (w.state.onSnapshot(summary.value(), std::move(graph).value()) ==
          WatchState::Outcome::kApplied) {
        w.ended |= w.state.summary().final;
        if (each) each(w.state);
      }
      parts.clear();
    }
    while (w.sub &&
           zmq::recv_multipart(*w.sub, std::back_inserter(parts), zmq::recv_flags::dontwait)) {
      const auto head = parts.empty() ? Result<std::pair<Type, uint64_t>>(Error{"empty"})
                                      : readHeader(parts[0].to_string());
      auto summary = head && parts.size() == 3
                         ? parseSummary(parts[1].to_string(), head.value().second)
                         : Result<FusedSummary>(Error{"not a fused-graph delta"});
      auto delta = summary ? io::decodeGraphDeltaBinary(parts[2].to_string())
                           : Result<GraphDelta>(Error{summary.error()});
      parts.clear();
      if (!delta) {
        w.log("watch: a published message refused: " + delta.error());
        continue;
      }
      switch (w.state.onDelta(summary.value(), delta.value())) {
        case WatchState::Outcome::kApplied:
          ++w.deltas;
          w.ended |= w.state.summary().final;
          if (each) each(w.state);
          break;
        case WatchState::Outcome::kStale:
          break;
        case WatchState::Outcome::kGap:
        case WatchState::Outcome::kBroken:
          if (!w.waiting) {
            w.log("watch: sequence " + std::to_string(summary.value().sequence) + " after " +
                  std::to_string(w.state.sequence()) + ": asking for a snapshot");
            w.request();
          }
          break;
      }
    }
  } while (Clock::now() < end && !w.ended);
  return Status::Ok();
}

}  // namespace hydra_multi::net
