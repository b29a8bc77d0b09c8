#include "support/random_graphs.h"

#include "hydra_multi/core/se3.h"

namespace hydra_multi::testing {
namespace {

double uniform(std::mt19937& rng, double lo, double hi) {
  return std::uniform_real_distribution<double>(lo, hi)(rng);
}
int integer(std::mt19937& rng, int lo, int hi) {
  return std::uniform_int_distribution<int>(lo, hi)(rng);
}
Eigen::Vector3d randomPoint(std::mt19937& rng) {
  return {uniform(rng, -20, 20), uniform(rng, -20, 20), uniform(rng, 0, 6)};
}
Color randomColor(std::mt19937& rng) {
  return {static_cast<uint8_t>(integer(rng, 0, 255)), static_cast<uint8_t>(integer(rng, 0, 255)),
          static_cast<uint8_t>(integer(rng, 0, 255))};
}
SemanticAttributes randomSemantic(std::mt19937& rng, const std::string& name) {
  SemanticAttributes s;
  s.label = static_cast<uint32_t>(integer(rng, 0, 40));
  s.name = name;
  s.color = randomColor(rng);
  if (integer(rng, 0, 3) > 0) {
    const Eigen::Vector3d lo = randomPoint(rng);
    s.bounding_box = BoundingBox{
        lo, lo + Eigen::Vector3d(uniform(rng, 0.1, 2), uniform(rng, 0.1, 2), uniform(rng, 0.1, 2))};
  }
  return s;
}
std::vector<uint64_t> randomIndices(std::mt19937& rng, int max_index) {
  if (max_index < 0) return {};
  std::vector<uint64_t> indices(static_cast<size_t>(integer(rng, 0, 12)));
  for (auto& index : indices) index = static_cast<uint64_t>(integer(rng, 0, max_index));
  return indices;
}
Node commonFields(std::mt19937& rng, Node node) {
  node.last_update_time_ns = static_cast<int64_t>(integer(rng, 0, 1 << 30)) * 1000;
  node.is_active = integer(rng, 0, 1) == 1;
  return node;
}

}  // namespace

SceneGraph makeRandomGraph(std::mt19937& rng, const RandomGraphSize& size) {
  SceneGraph graph;
  const NodeId building('B', 0);
  {
    Node node = commonFields(rng, makeNode(building, Layer::kBuildings, randomPoint(rng)));
    *node.semantic() = randomSemantic(rng, "B(0)");
    graph.addOrUpdateNode(node);
  }
  std::vector<NodeId> rooms, places;
  for (int i = 0; i < size.rooms; ++i) {
    Node node = commonFields(rng, makeNode(NodeId('R', i), Layer::kRooms, randomPoint(rng)));
    *node.semantic() = randomSemantic(rng, "room " + std::to_string(i));
    graph.addOrUpdateNode(node);
    graph.addOrUpdateEdge(building, node.id);
    rooms.push_back(node.id);
  }
  for (int i = 0; i < size.places; ++i) {
    Node node = commonFields(rng, makeNode(NodeId('p', i), Layer::kPlaces, randomPoint(rng)));
    auto& place = *node.find<PlaceAttributes>();
    place.semantic = randomSemantic(rng, "");
    place.distance = uniform(rng, 0.3, 2.5);
    place.mesh_vertices = randomIndices(rng, size.mesh_vertices - 1);
    graph.addOrUpdateNode(node);
    if (!rooms.empty()) {
      graph.addOrUpdateEdge(rooms[static_cast<size_t>(integer(rng, 0, size.rooms - 1))], node.id,
                            {uniform(rng, 0, 1), true});
    }
    if (!places.empty()) {
      graph.addOrUpdateEdge(places[static_cast<size_t>(integer(rng, 0, i - 1))], node.id,
                            {uniform(rng, 0.2, 2.0), true});
    }
    places.push_back(node.id);
  }
  for (int i = 0; i < size.objects; ++i) {
    Node node = commonFields(rng, makeNode(NodeId('O', i), Layer::kObjects, randomPoint(rng)));
    auto& object = *node.find<ObjectAttributes>();
    object.semantic = randomSemantic(rng, "O(" + std::to_string(i) + ")");
    object.mesh_vertices = randomIndices(rng, size.mesh_vertices - 1);
    graph.addOrUpdateNode(node);
    if (!places.empty()) {
      graph.addOrUpdateEdge(places[static_cast<size_t>(integer(rng, 0, size.places - 1))], node.id);
    }
  }
  for (int i = 0; i < size.agents; ++i) {
    const RobotId robot(static_cast<uint8_t>(i % 2));
    const NodeId id(robot.prefix(), static_cast<uint64_t>(i / 2));
    Node node = commonFields(rng, makeNode(id, Layer::kAgents, randomPoint(rng)));
    auto& agent = *node.find<AgentAttributes>();
    agent.orientation = Eigen::Quaterniond::UnitRandom();
    agent.timestamp_ns = static_cast<int64_t>(i) * 100'000'000 + integer(rng, 0, 1000);
    agent.keyframe_id = static_cast<uint64_t>(integer(rng, 0, 1 << 20));
    graph.addOrUpdateNode(node);
    if (i >= 2) graph.addOrUpdateEdge(NodeId(robot.prefix(), static_cast<uint64_t>(i / 2 - 1)), id);
    if (!places.empty()) {
      graph.addOrUpdateEdge(places[static_cast<size_t>(integer(rng, 0, size.places - 1))], id);
    }
  }
  Mesh& mesh = graph.mesh();
  for (int i = 0; i < size.mesh_vertices; ++i) {
    MeshVertex v;
    v.position = randomPoint(rng).cast<float>();
    v.color = randomColor(rng);
    v.label = integer(rng, 0, 9) == 0 ? MeshVertex::kUnlabeled
                                      : static_cast<uint32_t>(integer(rng, 0, 40));
    v.robot = RobotId(static_cast<uint8_t>(integer(rng, 0, 2)));
    v.time_ns = 1'000'000'000LL + i * 1000LL + integer(rng, 0, 999);
    mesh.vertices.push_back(v);
  }
  for (int i = 0; i < size.mesh_faces && size.mesh_vertices > 2; ++i) {
    const int base = integer(rng, 0, size.mesh_vertices - 3);
    mesh.faces.push_back({static_cast<uint32_t>(base), static_cast<uint32_t>(base + 1),
                          static_cast<uint32_t>(base + integer(rng, 2, 2))});
  }
  return graph;
}

RobotUpdate makeRandomUpdate(std::mt19937& rng, uint64_t sequence) {
  RobotUpdate u;
  u.robot = RobotId(1);
  u.sequence = sequence;
  u.time_ns = 5'000'000'000LL + static_cast<int64_t>(sequence);
  u.is_snapshot = false;
  u.provided_layers = kProvidesAgents | kProvidesMesh | kProvidesVisual;
  const SceneGraph graph = makeRandomGraph(rng, {6, 3, 8, 1, 40, 60});
  u.graph = snapshotOf(graph);
  u.graph.removed_nodes = {NodeId('O', 99), NodeId('p', 98)};
  u.graph.removed_edges = {EdgeKey(NodeId('p', 1), NodeId('p', 2))};
  u.graph.mesh.vertex_start = 0;
  for (int i = 0; i < 3; ++i) {
    PoseGraphEdge e;
    e.from = NodeId('b', static_cast<uint64_t>(i));
    e.to = NodeId('b', static_cast<uint64_t>(i + 1));
    e.kind = i == 2 ? PoseGraphEdge::Kind::kLoopClosure : PoseGraphEdge::Kind::kOdometry;
    e.T_from_to.linear() = Eigen::Quaterniond::UnitRandom().toRotationMatrix();
    e.T_from_to.translation() = randomPoint(rng);
    Matrix6d A = Matrix6d::Random();
    e.information = A * A.transpose() + Matrix6d::Identity();
    u.pose_graph.push_back(e);
  }
  for (uint64_t i = 0; i < 5; ++i) {
    u.deformation.points.push_back(
        {100 + i, randomPoint(rng), static_cast<int64_t>(i) * 7, NodeId('b', i % 3)});
    if (i > 0) u.deformation.edges.push_back({99 + i, 100 + i});
  }
  for (uint64_t k = 0; k < 2; ++k) {
    KeyframeDescriptor d;
    d.keyframe = NodeId('b', k);
    for (uint32_t w = 0; w < 10; ++w) {
      d.bow.push_back({w * 37 + static_cast<uint32_t>(k), static_cast<float>(uniform(rng, 0, 1))});
      d.keypoints.push_back({randomPoint(rng).cast<float>(), w * 37});
    }
    u.descriptors.push_back(d);
  }
  return u;
}

std::string dataDir() { return HYDRA_MULTI_DATA_DIR; }

std::map<NodeId, Eigen::Isometry3d> randomTrajectory(std::mt19937& rng, int n) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::map<NodeId, Eigen::Isometry3d> poses;
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  for (int i = 0; i < n; ++i) {
    poses[NodeId('x', static_cast<uint64_t>(i))] = T;
    Vector6d step;
    step << 1.0, 0.2 * gauss(rng), 0.1 * gauss(rng), 0.05 * gauss(rng), 0.05 * gauss(rng),
        0.3 * gauss(rng);
    T = T * expSE3(step);
  }
  return poses;
}

std::map<NodeId, Eigen::Isometry3d> perturbPoses(std::map<NodeId, Eigen::Isometry3d> poses,
                                                 NodeId anchor, double sigma, std::mt19937& rng) {
  std::normal_distribution<double> gauss(0.0, sigma);
  for (auto& [id, T] : poses) {
    if (id == anchor) continue;
    Vector6d xi;
    for (int k = 0; k < 6; ++k) xi[k] = gauss(rng);
    T = T * expSE3(xi);
  }
  return poses;
}

}  // namespace hydra_multi::testing
