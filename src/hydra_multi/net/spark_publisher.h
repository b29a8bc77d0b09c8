#pragma once
// The fused graph in Spark-DSG's form (../shared/reference/spark-dsg-wire.md §2), as Spark-DSG's
// ZmqSender sends it: a PUB socket that binds, one single-part message per backend round holding
// the whole graph in the wire form (dsg/io/spark_binary.h, no header, format 1.1.3 or the version
// given: the receivers' Spark-DSG; node ids and
// robots as dsg/io/spark_graph.h maps them), the mesh with it unless told not to. Spark-DSG's
// ZmqReceiver, Hydra's tools and Spark-DSG's viewer read it by connecting a SUB. The graph is
// encoded on the publisher's own thread; a round not yet sent is overtaken by the next.

#include <chrono>
#include <memory>
#include <optional>
#include <string>

#include "hydra_multi/core/result.h"
#include "hydra_multi/dsg/io/spark_binary.h"
#include "hydra_multi/dsg/scene_graph.h"

namespace hydra_multi::net {

class SparkPublisher {
 public:
  /// Binds `endpoint` (tcp://HOST:PORT, '*' for a free port); an error names it.
  static Result<std::unique_ptr<SparkPublisher>> create(
      const std::string& endpoint, bool include_mesh,
      io::spark::Version version = io::spark::kVersion);
  /// Sends what is queued, then stops.
  ~SparkPublisher();
  const std::string& endpoint() const;  ///< as bound, with the port '*' picked
  /// Queues a round's graph (any thread).
  void publish(const SceneGraph& graph);
  /// Queues a graph in Spark-DSG's form as it is (its mesh left out unless included).
  void publish(io::spark::Graph graph);
  uint64_t published() const;  ///< messages handed to the socket
  size_t lastBytes() const;    ///< of the last message handed to the socket

 private:
  struct Impl;
  explicit SparkPublisher(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace hydra_multi::net

namespace hydra_multi::net {

/// The other end, as Spark-DSG's ZmqReceiver: a SUB that connects to a Spark-DSG publisher (a
/// Hydra robot's ZmqSink, or a SparkPublisher) and takes every message (no conflation).
class SparkSubscriber {
 public:
  /// Connects; an error names the endpoint.
  static Result<std::unique_ptr<SparkSubscriber>> create(const std::string& endpoint);
  ~SparkSubscriber();
  /// The next message (one whole graph in the wire form), or nullopt after `timeout`.
  std::optional<std::string> receive(std::chrono::milliseconds timeout);

 private:
  struct Impl;
  explicit SparkSubscriber(std::unique_ptr<Impl> impl);
  std::unique_ptr<Impl> impl_;
};

}  // namespace hydra_multi::net
