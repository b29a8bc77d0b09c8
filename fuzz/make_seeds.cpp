// Writes the fuzz targets' seed corpus (fuzz/README.md) into OUT_DIR/NAME/: small real inputs of
// every decoder, made by the simulator's tiny team (seed 4, its updates cut to a few nodes) and
// our own encoders: .dsgb records
// and their payloads, our JSON, Spark-DSG JSON, files and wire payloads, g2o and TORO text,
// protocol messages and the first messages of a robot's connection. Deterministic.
//   usage: fuzz_seeds OUT_DIR

#include <cstdio>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "fuzz/fuzz_input.h"
#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/dsg/io/binary_record.h"
#include "hydra_multi/dsg/io/json_format.h"
#include "hydra_multi/dsg/io/spark_binary.h"
#include "hydra_multi/dsg/io/spark_graph.h"
#include "hydra_multi/dsg/io/spark_json.h"
#include "hydra_multi/frontend/scene_graph_processor.h"
#include "hydra_multi/net/payload.h"
#include "hydra_multi/net/protocol.h"
#include "hydra_multi/optim/io/g2o_format.h"
#include "hydra_multi/sim/dataset.h"
#include "hydra_multi/sim/presets.h"

using namespace hydra_multi;
namespace fs = std::filesystem;

namespace {

fs::path out_dir;

void write(const std::string& target, const std::string& name, const std::string& bytes) {
  fs::create_directories(out_dir / target);
  std::ofstream(out_dir / target / name, std::ios::binary) << bytes;
}

std::string payloadOf(const std::string& record) {
  io::RecordReader reader(record);
  auto next = reader.next();
  return std::string(next.value().value().payload);
}

std::string message(const net::Message& m, bool last = true) {
  return fuzz::frameInput(net::encodeMessage(m), last);
}

// A small version of an update (seeds of a few KB fuzz faster): at most 4 nodes of each layer and
// what refers only to them, 24 new mesh vertices (appended to the `mesh_size` kept so far) and
// no faces, 16 words and keypoints per descriptor.
RobotUpdate small(const RobotUpdate& update, size_t& mesh_size) {
  RobotUpdate out = update;
  std::map<Layer, int> per_layer;
  std::set<NodeId> kept;
  out.graph.nodes.clear();
  for (const Node& node : update.graph.nodes) {
    if (per_layer[node.layer()]++ >= 4) continue;
    out.graph.nodes.push_back(node);
    kept.insert(node.id);
  }
  const auto keeps = [&kept](NodeId id) { return kept.count(id) != 0; };
  out.graph.edges.clear();
  for (const Edge& e : update.graph.edges)
    if (keeps(e.source) && keeps(e.target)) out.graph.edges.push_back(e);
  out.graph.removed_edges.clear();
  out.graph.removed_nodes.clear();
  MeshDelta& mesh = out.graph.mesh;
  if (mesh.vertices.size() > 24) mesh.vertices.resize(24);
  mesh.vertex_start = mesh_size;
  mesh_size += mesh.vertices.size();
  mesh.faces.clear();
  mesh.face_start = 0;
  out.pose_graph.clear();
  for (const PoseGraphEdge& e : update.pose_graph)
    if (keeps(e.from) && keeps(e.to)) out.pose_graph.push_back(e);
  out.deformation.points.clear();
  std::set<uint64_t> points;
  for (const ControlPoint& p : update.deformation.points) {
    if (!keeps(p.keyframe) || points.size() >= 8) continue;
    out.deformation.points.push_back(p);
    points.insert(p.id);
  }
  out.deformation.edges.clear();
  for (const ControlPointEdge& e : update.deformation.edges)
    if (points.count(e.from) && points.count(e.to)) out.deformation.edges.push_back(e);
  out.descriptors.clear();
  for (KeyframeDescriptor d : update.descriptors) {
    if (!keeps(d.keyframe)) continue;
    if (d.bow.size() > 16) d.bow.resize(16);
    if (d.keypoints.size() > 16) d.keypoints.resize(16);
    out.descriptors.push_back(d);
  }
  return out;
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: fuzz_seeds OUT_DIR\n");
    return 2;
  }
  out_dir = argv[1];
  auto config = sim::presetConfig("tiny", 4);
  if (!config) {
    std::fprintf(stderr, "%s\n", config.error().c_str());
    return 1;
  }
  auto dataset = sim::simulateDataset(config.value());
  if (!dataset) {
    std::fprintf(stderr, "%s\n", dataset.error().c_str());
    return 1;
  }
  std::vector<RobotUpdate> a, b;
  size_t mesh_a = 0, mesh_b = 0;
  for (const RobotUpdate& u : dataset.value().streams[0]) a.push_back(small(u, mesh_a));
  for (const RobotUpdate& u : dataset.value().streams[1]) b.push_back(small(u, mesh_b));
  SceneGraphProcessor processor;
  for (size_t k = 0; k < 3; ++k) {
    for (const RobotUpdate* u : {&a[k], &b[k]}) {
      const UpdateReport report = processor.process(*u);
      if (report.outcome != UpdateOutcome::kApplied) {
        std::fprintf(stderr, "a seed update is not applied: %s\n", report.message.c_str());
        return 1;
      }
    }
  }
  const SceneGraph& graph = processor.graph();

  // Our binary records, whole and as payloads.
  const std::string update0 = io::encodeRobotUpdateBinary(a[0]);
  const std::string update1 = io::encodeRobotUpdateBinary(a[1]);
  const std::string graph_record = io::encodeSceneGraphBinary(graph);
  write("dsgb_records", "updates_a_0_1.dsgb", update0 + update1);
  write("dsgb_records", "graph.dsgb", graph_record);
  write("binary_payloads", "update_a_0.payload", payloadOf(update0));
  write("binary_payloads", "update_b_1.payload", payloadOf(io::encodeRobotUpdateBinary(b[1])));
  write("binary_payloads", "graph.payload", payloadOf(graph_record));
  write("binary_payloads", "update_a_1.dsgb", update1);

  // JSON, ours and Spark-DSG's.
  write("json", "update_a_0.json", io::robotUpdateToJson(a[0], true));
  write("json", "graph.json", io::sceneGraphToJson(graph, true));
  write("spark_json", "graph.json", io::sceneGraphToSparkJson(graph));

  // Spark-DSG binary: a file, and wire payloads of two versions (the first byte picks it).
  write("spark_binary", "graph.sparkdsg", io::sceneGraphToSparkFile(graph));
  const io::spark::Graph spark = io::sparkFromSceneGraph(graph, false);
  write("spark_binary", "wire_1.1.3", std::string(1, '\x08') + io::spark::encodeWire(spark));
  write("spark_binary", "wire_1.0.2",
        std::string(1, '\x00') + io::spark::encodeWire(spark, io::spark::Version{1, 0, 2}));

  // g2o and TORO, 3D and 2D.
  PoseGraph pose_graph;
  for (const PoseGraphEdge& e : processor.robot(RobotId(0))->pose_graph) {
    pose_graph.edges.push_back(e);
    if (pose_graph.edges.size() == 6) break;
  }
  for (const PoseGraphEdge& e : pose_graph.edges) {
    pose_graph.poses[e.from] = Eigen::Isometry3d::Identity();
    pose_graph.poses[e.to] = e.T_from_to;
  }
  write("g2o", "robot_a.g2o", io::writeG2o(pose_graph));
  write("g2o", "se2.g2o",
        "VERTEX_SE2 0 0 0 0\nVERTEX_SE2 1 1 0 0.1\nVERTEX_SE2 2 2 0.1 0.2\n"
        "EDGE_SE2 0 1 1 0 0.1 500 0 0 500 0 5000\nEDGE_SE2 1 2 1 0.1 0.1 500 0 0 500 0 5000\n"
        "EDGE_SE2 0 2 2 0.1 0.2 100 0 0 100 0 1000\n");
  write("g2o", "toro.graph",
        "VERTEX2 0 0 0 0\nVERTEX2 1 1 0 0.1\nEDGE2 0 1 1 0 0.1 500 0 500 5000 0 0\n"
        "VERTEX3 2 0 0 0 0 0 0\nVERTEX3 3 1 0 0 0 0 0.1\n"
        "EDGE3 2 3 1 0 0 0 0 0.1 100 0 0 0 0 0 100 0 0 0 0 100 0 0 0 100 0 0 100 0 100\n");

  // Protocol messages, one per type, and an update compressed.
  const uint64_t epoch = 1;
  write("protocol", "hello", message(net::hello(RobotId(0), epoch, kProvidesAll)));
  write("protocol", "welcome", message(net::welcome(3)));
  write("protocol", "update", message(net::update(epoch, 0, update0)));
  write("protocol", "update_zstd", message(net::update(epoch, 1, net::compressPayload(update1))));
  write("protocol", "ack", message(net::ack(epoch, 0, 1)));
  write("protocol", "refuse",
        message(net::refuse(net::RefuseCode::kBadPayload, "UPDATE 0: payload", epoch, 0)));
  write("protocol", "snapshot_request", message(net::snapshotRequest(epoch, 2)));
  write("protocol", "heartbeat", message(net::heartbeat()));
  write("protocol", "bye", message(net::bye()));

  // A robot's connection: HELLO, then its first updates (one compressed), then BYE.
  std::string connection = message(net::hello(RobotId(0), epoch, kProvidesAll), false);
  for (uint64_t k = 0; k < 3; ++k) {
    const std::string record = io::encodeRobotUpdateBinary(a[k]);
    connection +=
        message(net::update(epoch, k, k == 1 ? net::compressPayload(record) : record), false);
  }
  write("connection", "hello_3_updates_bye", connection + message(net::bye()));
  std::string out_of_order = message(net::hello(RobotId(1), epoch, kProvidesAll), false);
  for (const uint64_t k : {1, 0, 2})
    out_of_order += message(net::update(epoch, k, io::encodeRobotUpdateBinary(b[k])), false);
  write("connection", "hello_out_of_order", out_of_order);
  std::printf("seeds written to %s\n", out_dir.c_str());
  return 0;
}
