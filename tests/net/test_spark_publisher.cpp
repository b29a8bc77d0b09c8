#include "hydra_multi/net/spark_publisher.h"

#include <gtest/gtest.h>

#include <chrono>
#include <zmq.hpp>

#include "hydra_multi/dsg/io/graph_file.h"
#include "hydra_multi/dsg/io/spark_binary.h"
#include "hydra_multi/dsg/io/spark_graph.h"
#include "support/random_graphs.h"

namespace hydra_multi::net {
namespace {

// What a plain SUB (as Spark-DSG's ZmqReceiver) receives first, published again every 50 ms
// until it does (a SUB that has just connected misses what was sent before: the slow joiner).
std::optional<std::string> receive(SparkPublisher& publisher, const SceneGraph& graph) {
  zmq::context_t context;
  zmq::socket_t sub(context, zmq::socket_type::sub);
  sub.set(zmq::sockopt::subscribe, "");
  sub.set(zmq::sockopt::rcvtimeo, 50);
  sub.connect(publisher.endpoint());
  for (int attempt = 0; attempt < 100; ++attempt) {
    publisher.publish(graph);
    zmq::message_t message;
    if (sub.recv(message)) {
      EXPECT_FALSE(message.more()) << "one single-part message per graph";
      return message.to_string();
    }
  }
  return std::nullopt;
}

TEST(SparkPublisher, APlainSubReceivesTheGraphInSparkDsgsWireForm) {
  auto loaded = io::loadSceneGraph(testing::dataDir() + "/spark/apartment_mesh.sparkdsg");
  ASSERT_TRUE(loaded) << loaded.error();
  for (const bool mesh : {true, false}) {
    auto publisher = SparkPublisher::create("tcp://127.0.0.1:*", mesh);
    ASSERT_TRUE(publisher) << publisher.error();
    const auto message = receive(*publisher.value(), loaded.value());
    ASSERT_TRUE(message) << "nothing received in 5 s";
    auto wire = io::spark::decodeWire(*message);
    ASSERT_TRUE(wire) << wire.error();
    EXPECT_EQ(wire.value().mesh.has_value(), mesh);
    auto graph = io::sceneGraphFromSpark(wire.value());
    ASSERT_TRUE(graph) << graph.error();
    SceneGraph expected = loaded.value();
    if (!mesh) expected.mesh() = Mesh();
    EXPECT_TRUE(graph.value().graph == expected) << "mesh " << mesh;
    EXPECT_GE(publisher.value()->published(), 1u);
  }
}

TEST(SparkPublisher, ABadEndpointIsNamed) {
  auto publisher = SparkPublisher::create("tcp://nowhere", true);
  ASSERT_FALSE(publisher);
  EXPECT_NE(publisher.error().find("tcp://nowhere"), std::string::npos) << publisher.error();
}

}  // namespace
}  // namespace hydra_multi::net
