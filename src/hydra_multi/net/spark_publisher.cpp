#include "hydra_multi/net/spark_publisher.h"

#include <atomic>
#include <condition_variable>
#include <mutex>
#include <optional>
#include <thread>
#include <variant>
#include <zmq.hpp>

#include "hydra_multi/dsg/io/spark_binary.h"
#include "hydra_multi/dsg/io/spark_graph.h"

namespace hydra_multi::net {

struct SparkPublisher::Impl {
  zmq::context_t context;
  zmq::socket_t pub{context, zmq::socket_type::pub};
  std::string endpoint;
  bool include_mesh = true;
  io::spark::Version version = io::spark::kVersion;
  std::mutex mutex;
  std::condition_variable wake;
  std::optional<std::variant<SceneGraph, io::spark::Graph>> pending;
  bool stopping = false;
  std::atomic<uint64_t> published{0};
  std::atomic<size_t> last_bytes{0};
  std::thread thread;

  void loop() {
    for (;;) {
      std::optional<std::variant<SceneGraph, io::spark::Graph>> graph;
      {
        std::unique_lock<std::mutex> lock(mutex);
        wake.wait(lock, [&] { return pending.has_value() || stopping; });
        if (!pending) return;
        graph = std::move(pending);
        pending.reset();
      }
      io::spark::Graph spark;
      if (const SceneGraph* ours = std::get_if<SceneGraph>(&*graph)) {
        spark = io::sparkFromSceneGraph(*ours, include_mesh);
      } else {
        spark = std::move(std::get<io::spark::Graph>(*graph));
        if (!include_mesh) spark.mesh.reset();
      }
      const std::string message = io::spark::encodeWire(spark, version);
      // Counted before it is handed over: a subscriber that has it sees the count include it.
      last_bytes = message.size();
      ++published;
      (void)pub.send(zmq::buffer(message), zmq::send_flags::none);
    }
  }
};

Result<std::unique_ptr<SparkPublisher>> SparkPublisher::create(const std::string& endpoint,
                                                               bool include_mesh,
                                                               io::spark::Version version) {
  if (const std::string why = io::spark::unsupported(version); !why.empty()) return Error{why};
  auto impl = std::make_unique<Impl>();
  impl->include_mesh = include_mesh;
  impl->version = version;
  try {
    impl->pub.set(zmq::sockopt::linger, 1000);
    impl->pub.bind(endpoint);
    impl->endpoint = impl->pub.get(zmq::sockopt::last_endpoint);
  } catch (const zmq::error_t& e) {
    return Error{"--spark-publish " + endpoint + ": cannot bind: " + e.what()};
  }
  Impl* raw = impl.get();
  impl->thread = std::thread([raw] { raw->loop(); });
  return std::unique_ptr<SparkPublisher>(new SparkPublisher(std::move(impl)));
}

SparkPublisher::SparkPublisher(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}

SparkPublisher::~SparkPublisher() {
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->stopping = true;
  }
  impl_->wake.notify_all();
  if (impl_->thread.joinable()) impl_->thread.join();
}

const std::string& SparkPublisher::endpoint() const { return impl_->endpoint; }
uint64_t SparkPublisher::published() const { return impl_->published; }
size_t SparkPublisher::lastBytes() const { return impl_->last_bytes; }

void SparkPublisher::publish(const SceneGraph& graph) {
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->pending = graph;
  }
  impl_->wake.notify_all();
}

void SparkPublisher::publish(io::spark::Graph graph) {
  {
    std::lock_guard<std::mutex> lock(impl_->mutex);
    impl_->pending = std::move(graph);
  }
  impl_->wake.notify_all();
}

struct SparkSubscriber::Impl {
  zmq::context_t context;
  zmq::socket_t sub{context, zmq::socket_type::sub};
};

Result<std::unique_ptr<SparkSubscriber>> SparkSubscriber::create(const std::string& endpoint) {
  auto impl = std::make_unique<Impl>();
  try {
    impl->sub.set(zmq::sockopt::subscribe, "");
    impl->sub.set(zmq::sockopt::linger, 0);
    impl->sub.connect(endpoint);
  } catch (const zmq::error_t& e) {
    return Error{endpoint + ": cannot connect: " + e.what()};
  }
  return std::unique_ptr<SparkSubscriber>(new SparkSubscriber(std::move(impl)));
}

SparkSubscriber::SparkSubscriber(std::unique_ptr<Impl> impl) : impl_(std::move(impl)) {}
SparkSubscriber::~SparkSubscriber() = default;

std::optional<std::string> SparkSubscriber::receive(std::chrono::milliseconds timeout) {
  impl_->sub.set(zmq::sockopt::rcvtimeo, static_cast<int>(timeout.count()));
  zmq::message_t message;
  if (!impl_->sub.recv(message)) return std::nullopt;
  return message.to_string();
}

}  // namespace hydra_multi::net
