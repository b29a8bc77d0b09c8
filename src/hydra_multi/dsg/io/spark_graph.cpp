#include "hydra_multi/dsg/io/spark_graph.h"

#include <algorithm>
#include <limits>
#include <nlohmann/json.hpp>
#include <set>

#include "hydra_multi/dsg/graph_delta.h"

namespace hydra_multi::io {
namespace {

constexpr int64_t kAgentsAndObjects = 2, kPlaces = 3, kRooms = 4, kBuildings = 5;

std::optional<Layer> layerOf(const spark::Node& n) {
  switch (n.layer) {
    case kAgentsAndObjects:
      if (n.partition == 0) return Layer::kObjects;
      if (n.attributes.type == "AgentNodeAttributes") return Layer::kAgents;
      return std::nullopt;
    case kPlaces:
      if (n.partition == 0 && n.attributes.type == "PlaceNodeAttributes") return Layer::kPlaces;
      return std::nullopt;
    case kRooms:
      return n.partition == 0 ? std::optional<Layer>(Layer::kRooms) : std::nullopt;
    case kBuildings:
      return n.partition == 0 ? std::optional<Layer>(Layer::kBuildings) : std::nullopt;
    default:
      return std::nullopt;
  }
}

void readSemantic(const spark::Attributes& a, SemanticAttributes& s) {
  s.label = a.semantic_label;
  s.name = a.name;
  s.color = {a.color[0], a.color[1], a.color[2]};
  if (a.bounding_box.type != 0) {
    const auto& d = a.bounding_box.dimensions;
    const auto& c = a.bounding_box.center;
    const Eigen::Vector3d half(0.5 * d[0], 0.5 * d[1], 0.5 * d[2]);
    const Eigen::Vector3d centre(c[0], c[1], c[2]);
    s.bounding_box = BoundingBox{centre - half, centre + half};
  }
}

void writeSemantic(const SemanticAttributes& s, spark::Attributes& a) {
  a.semantic_label = s.label;
  a.name = s.name;
  a.color = {s.color.r, s.color.g, s.color.b, 255};
  a.bounding_box.rotation = {3, 3, 0xca, {1, 0, 0, 0, 1, 0, 0, 0, 1}};
  if (s.bounding_box) {
    const Eigen::Vector3d d = s.bounding_box->max - s.bounding_box->min;
    const Eigen::Vector3d c = s.bounding_box->center();
    a.bounding_box.type = 1;  // AABB
    a.bounding_box.dimensions = {float(d.x()), float(d.y()), float(d.z())};
    a.bounding_box.center = {float(c.x()), float(c.y()), float(c.z())};
  }
  a.semantic_feature = {0, 0, 0xca, {}};
}

std::string describe(const spark::Node& n) {
  return "nodes of layer " + std::to_string(n.layer) + " partition " + std::to_string(n.partition) +
         " (" + n.attributes.type + ")";
}

}  // namespace

Result<SparkImport> sceneGraphFromSpark(const spark::Graph& spark) {
  SparkImport out;
  GraphDelta snapshot;
  std::set<uint64_t> kept;
  for (const spark::Node& n : spark.nodes) {
    const std::optional<Layer> layer = layerOf(n);
    if (!layer) {
      ++out.left_out[describe(n)];
      continue;
    }
    const spark::Attributes& a = n.attributes;
    const NodeId id(n.id);
    if (*layer == Layer::kAgents && uint32_t(static_cast<uint8_t>(id.category())) != n.partition)
      return Error{"Spark-DSG graph: agent " + id.str() + " is in partition " +
                   std::to_string(n.partition) + ", not its prefix's (" +
                   std::to_string(static_cast<uint8_t>(id.category())) + ")"};
    Node node = makeNode(id, *layer, {a.position[0], a.position[1], a.position[2]});
    node.last_update_time_ns = a.last_update_time_ns > uint64_t(std::numeric_limits<int64_t>::max())
                                   ? 0
                                   : static_cast<int64_t>(a.last_update_time_ns);
    node.is_active = a.is_active;
    if (AgentAttributes* agent = node.find<AgentAttributes>()) {
      const auto& q = a.world_R_body;
      agent->orientation = Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
      agent->timestamp_ns = a.timestamp_ns;
      agent->keyframe_id = a.external_key;
    } else {
      readSemantic(a, *node.semantic());
    }
    if (ObjectAttributes* object = node.find<ObjectAttributes>())
      object->mesh_vertices = a.mesh_connections;
    if (PlaceAttributes* place = node.find<PlaceAttributes>()) {
      place->distance = a.distance;
      place->mesh_vertices = a.pcl_mesh_connections;
    }
    kept.insert(n.id);
    snapshot.nodes.push_back(std::move(node));
  }
  for (const spark::Edge& e : spark.edges) {
    if (!kept.count(e.source) || !kept.count(e.target)) {
      ++out.left_out["edges to nodes left out"];
      continue;
    }
    snapshot.edges.push_back(
        {NodeId(e.source), NodeId(e.target), {e.attributes.weight, e.attributes.weighted}});
  }
  if (spark.mesh) {
    const spark::Mesh& m = *spark.mesh;
    snapshot.mesh.vertices.resize(m.points.size());
    for (size_t i = 0; i < m.points.size(); ++i) {
      MeshVertex& v = snapshot.mesh.vertices[i];
      v.position = {m.points[i][0], m.points[i][1], m.points[i][2]};
      if (i < m.colors.size()) v.color = {m.colors[i][0], m.colors[i][1], m.colors[i][2]};
      if (i < m.labels.size()) v.label = m.labels[i];
      if (i < m.stamps.size())
        v.time_ns = static_cast<int64_t>(
            std::min<uint64_t>(m.stamps[i], uint64_t(std::numeric_limits<int64_t>::max())));
    }
    for (const auto& f : m.faces) {
      snapshot.mesh.faces.push_back(
          {static_cast<uint32_t>(f[0]), static_cast<uint32_t>(f[1]), static_cast<uint32_t>(f[2])});
    }
    // Which robot mapped which vertices, where we wrote it (Spark's mesh has no such field).
    const nlohmann::json metadata = nlohmann::json::parse(spark.metadata, nullptr, false);
    if (metadata.is_object() && metadata.contains("hydra_multi") &&
        metadata["hydra_multi"].is_object() && metadata["hydra_multi"].contains("mesh_robots")) {
      for (const auto& range : metadata["hydra_multi"]["mesh_robots"]) {
        const std::optional<RobotId> robot = range.size() == 3 && range[0].is_string()
                                                 ? RobotId::parse(range[0].get<std::string>())
                                                 : std::nullopt;
        if (!robot || !range[1].is_number_unsigned() || !range[2].is_number_unsigned())
          return Error{"Spark-DSG graph: metadata hydra_multi.mesh_robots: " + range.dump() +
                       " is not [robot, first vertex, vertices]"};
        const uint64_t first = range[1].get<uint64_t>(), n = range[2].get<uint64_t>();
        if (first + n > snapshot.mesh.vertices.size())
          return Error{"Spark-DSG graph: metadata hydra_multi.mesh_robots: " + range.dump() +
                       " runs past the " + std::to_string(snapshot.mesh.vertices.size()) +
                       " vertices"};
        for (uint64_t i = first; i < first + n; ++i) snapshot.mesh.vertices[i].robot = *robot;
      }
    }
  }
  auto graph = graphFromSnapshot(snapshot);
  if (!graph) return Error{"Spark-DSG graph: " + graph.error()};
  out.graph = std::move(graph).value();
  return out;
}

spark::Graph sparkFromSceneGraph(const SceneGraph& graph, bool include_mesh) {
  spark::Graph g;
  g.node_types = spark::knownNodeTypes();
  g.edge_types = {"EdgeAttributes"};
  const auto typeId = [&g](const char* name) {
    return static_cast<uint8_t>(std::find(g.node_types.begin(), g.node_types.end(), name) -
                                g.node_types.begin());
  };
  std::set<std::pair<int64_t, uint32_t>> keys = {
      {kAgentsAndObjects, 0}, {kPlaces, 0}, {kRooms, 0}, {kBuildings, 0}};
  // Spark's order: the primary layers by layer id, then the partitions; nodes by id in each.
  std::map<std::pair<uint32_t, int64_t>, std::vector<spark::Node>> layers;
  for (const auto& [id, node] : graph.nodes()) {
    spark::Node n;
    n.id = id.value();
    spark::Attributes& a = n.attributes;
    a.position = {node.position.x(), node.position.y(), node.position.z()};
    a.last_update_time_ns = static_cast<uint64_t>(std::max<int64_t>(0, node.last_update_time_ns));
    a.is_active = node.is_active;
    const std::optional<RobotId> robot = node.robot();
    a.metadata = nlohmann::json{{"robot", robot ? robot->str() : ""}, {"id", id.str()}}.dump();
    switch (node.layer()) {
      case Layer::kAgents: {
        const AgentAttributes& agent = *node.find<AgentAttributes>();
        n.layer = kAgentsAndObjects;
        n.partition = static_cast<uint8_t>(id.category());
        a.type = "AgentNodeAttributes";
        const Eigen::Quaterniond& q = agent.orientation;
        a.world_R_body = {q.w(), q.x(), q.y(), q.z()};
        a.timestamp_ns = agent.timestamp_ns;
        a.external_key = agent.keyframe_id;
        a.dbow_ids = {0, 1, 0xce, {}};
        a.dbow_values = {0, 1, 0xca, {}};
        break;
      }
      case Layer::kObjects:
        n.layer = kAgentsAndObjects;
        a.type = "ObjectNodeAttributes";
        writeSemantic(node.find<ObjectAttributes>()->semantic, a);
        a.mesh_connections = node.find<ObjectAttributes>()->mesh_vertices;
        a.registered = true;
        break;
      case Layer::kPlaces: {
        const PlaceAttributes& place = *node.find<PlaceAttributes>();
        n.layer = kPlaces;
        a.type = "PlaceNodeAttributes";
        writeSemantic(place.semantic, a);
        a.distance = place.distance;
        a.pcl_mesh_connections = place.mesh_vertices;
        break;
      }
      case Layer::kRooms:
        n.layer = kRooms;
        a.type = "RoomNodeAttributes";
        writeSemantic(node.find<RoomAttributes>()->semantic, a);
        break;
      case Layer::kBuildings:
        n.layer = kBuildings;
        a.type = "SemanticNodeAttributes";
        writeSemantic(node.find<BuildingAttributes>()->semantic, a);
        break;
    }
    n.type_id = typeId(a.type.c_str());
    keys.insert({n.layer, n.partition});
    layers[{n.partition, n.layer}].push_back(std::move(n));
  }
  for (const auto& [layer, partition] : keys) g.layer_keys.push_back({layer, partition});
  g.layer_names = {{"AGENTS", {kAgentsAndObjects, 0}},
                   {"BUILDINGS", {kBuildings, 0}},
                   {"OBJECTS", {kAgentsAndObjects, 0}},
                   {"PLACES", {kPlaces, 0}},
                   {"ROOMS", {kRooms, 0}}};
  for (auto& [key, nodes] : layers) {
    for (spark::Node& n : nodes) g.nodes.push_back(std::move(n));
  }
  for (const auto& [key, info] : graph.edges()) {
    spark::Edge e;
    e.source = key.first().value();
    e.target = key.second().value();
    e.attributes.type = "EdgeAttributes";
    e.attributes.weight = info.weight;
    e.attributes.weighted = info.weighted;
    g.edges.push_back(std::move(e));
  }
  if (include_mesh && !graph.mesh().empty()) {
    spark::Mesh m;
    m.has_colors = m.has_stamps = m.has_labels = true;
    for (const MeshVertex& v : graph.mesh().vertices) {
      m.points.push_back({v.position.x(), v.position.y(), v.position.z()});
      m.colors.push_back({v.color.r, v.color.g, v.color.b, 255});
      m.stamps.push_back(static_cast<uint64_t>(std::max<int64_t>(0, v.time_ns)));
      m.labels.push_back(v.label);
    }
    for (const MeshFace& f : graph.mesh().faces) m.faces.push_back({f[0], f[1], f[2]});
    g.mesh = std::move(m);
    // Spark's mesh has no robot per vertex: the runs of each robot's vertices go in the graph's
    // metadata ({"hydra_multi": {"mesh_robots": [[robot, first vertex, vertices], ...]}}).
    nlohmann::json runs = nlohmann::json::array();
    const std::vector<MeshVertex>& vertices = graph.mesh().vertices;
    for (size_t i = 0; i < vertices.size();) {
      size_t j = i;
      while (j < vertices.size() && vertices[j].robot == vertices[i].robot) ++j;
      runs.push_back({vertices[i].robot.str(), i, j - i});
      i = j;
    }
    g.metadata = nlohmann::json{{"hydra_multi", {{"mesh_robots", runs}}}}.dump();
  }
  return g;
}

void moveSparkGraph(spark::Graph& graph, const Eigen::Vector3d& offset, double yaw) {
  const Eigen::Matrix3d R = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const Eigen::Quaterniond q_R(R);
  const auto point = [&](std::array<double, 3>& p) {
    const Eigen::Vector3d moved = R * Eigen::Vector3d(p[0], p[1], p[2]) + offset;
    p = {moved.x(), moved.y(), moved.z()};
  };
  const auto turn = [&](spark::Quaternion& q) {
    const Eigen::Quaterniond turned = q_R * Eigen::Quaterniond(q[0], q[1], q[2], q[3]);
    q = {turned.w(), turned.x(), turned.y(), turned.z()};
  };
  // A 2x2 matrix on xy offsets, row-major: M' = R2 M R2^T.
  const auto turn2d = [&](spark::Matrix& m) {
    if (m.rows != 2 || m.cols != 2 || m.values.size() != 4) return;
    Eigen::Matrix2d M;
    M << m.values[0], m.values[1], m.values[2], m.values[3];
    const Eigen::Matrix2d R2 = R.topLeftCorner<2, 2>();
    const Eigen::Matrix2d turned = R2 * M * R2.transpose();
    m.values = {turned(0, 0), turned(0, 1), turned(1, 0), turned(1, 1)};
  };
  for (spark::Node& n : graph.nodes) {
    spark::Attributes& a = n.attributes;
    point(a.position);
    turn(a.world_R_body);
    turn(a.world_R_object);
    turn(a.orientation);
    for (auto& p : a.boundary) point(p);
    point(a.ellipse_centroid);
    turn2d(a.ellipse_matrix_compress);
    turn2d(a.ellipse_matrix_expand);
    spark::BoundingBox& box = a.bounding_box;
    if (box.type == 0) continue;
    const Eigen::Vector3f c =
        (R * Eigen::Vector3d(box.center[0], box.center[1], box.center[2]) + offset).cast<float>();
    box.center = {c.x(), c.y(), c.z()};
    if (box.type == 1) {  // axis-aligned: the box that holds the turned one
      const Eigen::Vector3d d(box.dimensions[0], box.dimensions[1], box.dimensions[2]);
      const Eigen::Vector3f held = (R.cwiseAbs() * d).cast<float>();
      box.dimensions = {held.x(), held.y(), held.z()};
    } else if (box.rotation.rows == 3 && box.rotation.cols == 3 &&
               box.rotation.values.size() == 9) {
      Eigen::Matrix3d Rb;
      for (int i = 0; i < 9; ++i) Rb(i / 3, i % 3) = box.rotation.values[static_cast<size_t>(i)];
      const Eigen::Matrix3d turned = R * Rb;
      for (int i = 0; i < 9; ++i)
        box.rotation.values[static_cast<size_t>(i)] = double(float(turned(i / 3, i % 3)));
    }
  }
  if (graph.mesh) {
    for (auto& p : graph.mesh->points) {
      const Eigen::Vector3f moved = (R * Eigen::Vector3d(p[0], p[1], p[2]) + offset).cast<float>();
      p = {moved.x(), moved.y(), moved.z()};
    }
  }
}

Result<SceneGraph> sceneGraphFromSparkFile(const std::string& bytes) {
  auto spark = spark::decodeFile(bytes);
  if (!spark) return Error{spark.error()};
  auto imported = sceneGraphFromSpark(spark.value());
  if (!imported) return Error{imported.error()};
  return std::move(imported).value().graph;
}

std::string sceneGraphToSparkFile(const SceneGraph& graph) {
  return spark::encodeFile(sparkFromSceneGraph(graph));
}

}  // namespace hydra_multi::io
