#include "hydra_multi/station/hydra_graph_input.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include "hydra_multi/dsg/graph_delta.h"
#include "hydra_multi/dsg/io/spark_graph.h"

namespace hydra_multi {
namespace {

constexpr int64_t kSparkAgentLayer = 2;

bool isAgent(const io::spark::Node& n) {
  return n.layer == kSparkAgentLayer && n.partition != 0 &&
         n.attributes.type == "AgentNodeAttributes";
}

std::string prefixText(char c) { return std::string("'") + c + "'"; }

/// The bag of words of an agent: dbow_ids (uint32) and dbow_values (float), n x 1 each.
std::optional<std::vector<BowEntry>> bowOf(const io::spark::Attributes& a) {
  const io::spark::Matrix& ids = a.dbow_ids;
  const io::spark::Matrix& values = a.dbow_values;
  if (ids.values.size() != values.values.size()) return std::nullopt;
  std::vector<BowEntry> bow;
  bow.reserve(ids.values.size());
  for (size_t i = 0; i < ids.values.size(); ++i) {
    const double word = ids.values[i];
    if (!(word >= 0.0 && word <= double(std::numeric_limits<uint32_t>::max())) ||
        word != std::floor(word))
      return std::nullopt;
    bow.push_back({static_cast<uint32_t>(word), static_cast<float>(values.values[i])});
  }
  return bow;
}

/// The keyframes of the graph's agents, by index.
std::vector<NodeId> keyframesOf(const SceneGraph& graph) {
  std::vector<NodeId> keyframes = graph.nodesInLayer(Layer::kAgents);
  std::sort(keyframes.begin(), keyframes.end(),
            [](NodeId a, NodeId b) { return a.index() < b.index(); });
  return keyframes;
}

/// Mesh vertex indices past the robot's mesh are dropped (the station indexes its meshes by
/// them); returns how many were.
size_t keepMeshIndicesInside(SceneGraph& graph) {
  const size_t n = graph.mesh().vertices.size();
  size_t dropped = 0;
  std::vector<NodeId> ids;
  for (const auto& [id, node] : graph.nodes()) ids.push_back(id);
  for (const NodeId id : ids) {
    Node* node = graph.findMutableNode(id);
    std::vector<uint64_t>* indices = nullptr;
    if (ObjectAttributes* o = node->find<ObjectAttributes>()) indices = &o->mesh_vertices;
    if (PlaceAttributes* p = node->find<PlaceAttributes>()) indices = &p->mesh_vertices;
    if (indices == nullptr) continue;
    const size_t before = indices->size();
    indices->erase(
        std::remove_if(indices->begin(), indices->end(), [n](uint64_t v) { return v >= n; }),
        indices->end());
    dropped += before - indices->size();
  }
  return dropped;
}

}  // namespace

std::string HydraInputOptions::invalid() const {
  if (!(control_point_spacing > 0.0) || !std::isfinite(control_point_spacing))
    return "control_point_spacing must be a positive number of metres";
  if (!(odometry_translation_variance > 0.0) || !(odometry_rotation_variance > 0.0) ||
      !std::isfinite(odometry_translation_variance) || !std::isfinite(odometry_rotation_variance))
    return "the odometry variances must be positive";
  if (!(correction_translation_m >= 0.0) || !(correction_rotation_rad >= 0.0))
    return "the correction tolerances must not be negative";
  return "";
}

HydraGraphInput::HydraGraphInput(RobotId robot, HydraInputOptions options)
    : robot_(robot), options_(options) {}

void HydraGraphInput::resumeAt(uint64_t next_sequence) {
  next_sequence_ = next_sequence;
  whole_next_ = true;
}

void HydraGraphInput::resetDerived() {
  chain_.clear();
  chain_poses_.clear();
  voxels_.clear();
  vertices_scanned_ = 0;
  bow_sent_.clear();
}

Result<std::optional<RobotUpdate>> HydraGraphInput::take(const io::spark::Graph& in,
                                                         HydraGraphNotes* notes_out) {
  HydraGraphNotes notes;
  // The robot's agents under its own prefix; frontiers left out.
  std::set<char> prefixes;
  for (const io::spark::Node& n : in.nodes) {
    if (n.id & NodeId::kStationBit)
      return Error{"node " + std::to_string(n.id) +
                   " has bit 55 set, which the station keeps for its own ids"};
    if (isAgent(n)) prefixes.insert(static_cast<char>(n.id >> 56));
  }
  if (prefixes.size() > 1) {
    std::string list;
    for (const char c : prefixes) list += (list.empty() ? "" : ", ") + prefixText(c);
    return Error{"agents of several prefixes (" + list +
                 "): a Hydra robot sends its own keyframes only"};
  }
  io::spark::Graph g;
  g.layer_keys = in.layer_keys;
  g.node_types = in.node_types;
  g.edge_types = in.edge_types;
  g.layer_names = in.layer_names;
  g.metadata = in.metadata;
  g.mesh = in.mesh;
  std::map<uint64_t, uint64_t> rekeyed;
  std::set<uint64_t> ids;
  const bool rekey = prefixes.size() == 1 && *prefixes.begin() != robot_.prefix();
  if (rekey) notes.agent_prefix = *prefixes.begin();
  std::map<NodeId, std::vector<BowEntry>> bow;
  g.nodes.reserve(in.nodes.size());
  for (const io::spark::Node& n : in.nodes) {
    if (n.attributes.type == "PlaceNodeAttributes" && !n.attributes.real_place) {
      ++notes.left_out["frontiers (places not real)"];
      continue;
    }
    io::spark::Node node = n;
    if (isAgent(n)) {
      if (rekey) {
        node.id = NodeId(robot_.prefix(), NodeId(n.id).index()).value();
        node.partition = static_cast<uint8_t>(robot_.prefix());
        rekeyed[n.id] = node.id;
      }
      if (auto words = bowOf(n.attributes)) {
        if (!words->empty()) bow[NodeId(node.id)] = std::move(*words);
      } else {
        ++notes.bow_refused;
      }
    }
    g.nodes.push_back(std::move(node));
  }
  for (const io::spark::Node& n : g.nodes) {
    if (!ids.insert(n.id).second)
      return Error{"node " + NodeId(n.id).str() + " twice once the agents are re-keyed to robot " +
                   robot_.str() + "'s prefix"};
  }
  g.edges.reserve(in.edges.size());
  for (io::spark::Edge e : in.edges) {
    if (const auto it = rekeyed.find(e.source); it != rekeyed.end()) e.source = it->second;
    if (const auto it = rekeyed.find(e.target); it != rekeyed.end()) e.target = it->second;
    g.edges.push_back(std::move(e));
  }
  auto imported = io::sceneGraphFromSpark(g);
  if (!imported) return Error{imported.error()};
  for (const auto& [what, n] : imported.value().left_out) notes.left_out[what] += n;
  SceneGraph graph = std::move(imported).value().graph;
  for (MeshVertex& v : graph.mesh().vertices) v.robot = robot_;
  if (const size_t dropped = keepMeshIndicesInside(graph))
    notes.left_out["mesh vertex indices past the mesh"] += dropped;

  // Whole or a delta.
  bool whole = whole_next_;
  if (!whole) {
    notes.correction = correctionOf(graph);
    whole = !notes.correction.empty();
  }
  RobotUpdate update;
  update.robot = robot_;
  update.is_snapshot = whole;
  update.provided_layers = kProvidesAgents | kProvidesObjects | kProvidesPlaces | kProvidesMesh;
  for (const MeshVertex& v : graph.mesh().vertices) {
    if (v.label != MeshVertex::kUnlabeled) {
      update.provided_layers |= kProvidesMeshLabels;
      break;
    }
  }
  if (!bow.empty()) update.provided_layers |= kProvidesVisual;
  if (whole) {
    resetDerived();
    update.graph = snapshotOf(graph);
  } else {
    update.graph = diffGraphs(graph_, graph);
  }
  Derived derived = derive(graph, bow, whole ? 0 : vertices_scanned_);
  update.pose_graph = std::move(derived.pose_graph);
  update.deformation = std::move(derived.deformation);
  update.descriptors = std::move(derived.descriptors);
  for (const NodeId k : graph.nodesInLayer(Layer::kAgents))
    time_ns_ = std::max(time_ns_, graph.getNode(k).find<AgentAttributes>()->timestamp_ns);
  update.time_ns = time_ns_;

  const GraphDelta& d = update.graph;
  const bool unchanged = !whole && d.nodes.empty() && d.removed_nodes.empty() && d.edges.empty() &&
                         d.removed_edges.empty() &&
                         d.mesh.isNoOp(graph_.mesh().vertices.size(), graph_.mesh().faces.size()) &&
                         update.pose_graph.empty() && update.deformation.points.empty() &&
                         update.descriptors.empty();
  graph_ = std::move(graph);
  whole_next_ = false;
  if (notes_out != nullptr) *notes_out = std::move(notes);
  if (unchanged) return std::optional<RobotUpdate>();
  update.sequence = next_sequence_++;
  return std::optional<RobotUpdate>(std::move(update));
}

std::string HydraGraphInput::correctionOf(const SceneGraph& graph) const {
  for (size_t i = 0; i < chain_.size(); ++i) {
    const Node* node = graph.findNode(chain_[i]);
    if (node == nullptr) return "keyframe " + chain_[i].str() + " is gone";
    if (i == 0) continue;
    const Node* prev = graph.findNode(chain_[i - 1]);
    const Eigen::Isometry3d sent =
        chain_poses_.at(chain_[i - 1]).inverse() * chain_poses_.at(chain_[i]);
    const Eigen::Isometry3d now = nodePose(*prev).inverse() * nodePose(*node);
    const Eigen::Isometry3d change = sent.inverse() * now;
    const double angle = Eigen::AngleAxisd(change.rotation()).angle();
    if (change.translation().norm() > options_.correction_translation_m ||
        angle > options_.correction_rotation_rad)
      return "the odometry " + chain_[i - 1].str() + " -> " + chain_[i].str() + " moved";
  }
  // A keyframe between two joined by odometry.
  const std::vector<NodeId> keyframes = keyframesOf(graph);
  if (!chain_.empty()) {
    const auto last = std::find(keyframes.begin(), keyframes.end(), chain_.back());
    if (static_cast<size_t>(last - keyframes.begin()) + 1 != chain_.size())
      return "a keyframe was inserted before " + chain_.back().str();
  }
  const Mesh& before = graph_.mesh();
  const Mesh& now = graph.mesh();
  if (now.vertices.size() < before.vertices.size() || now.faces.size() < before.faces.size())
    return "the mesh shrank";
  for (size_t i = 0; i < vertices_scanned_; ++i) {
    if (!(now.vertices[i] == before.vertices[i]))
      return "mesh vertex " + std::to_string(i) + " changed";
  }
  return "";
}

HydraGraphInput::Derived HydraGraphInput::derive(const SceneGraph& graph,
                                                 const std::map<NodeId, std::vector<BowEntry>>& bow,
                                                 size_t first_vertex) {
  Derived out;
  const std::vector<NodeId> keyframes = keyframesOf(graph);
  // Odometry between consecutive keyframes not joined yet.
  for (const NodeId k : keyframes) {
    if (chain_poses_.count(k)) continue;
    const Eigen::Isometry3d pose = nodePose(graph.getNode(k));
    if (!chain_.empty()) {
      PoseGraphEdge e;
      e.from = chain_.back();
      e.to = k;
      e.kind = PoseGraphEdge::Kind::kOdometry;
      e.T_from_to = chain_poses_.at(chain_.back()).inverse() * pose;
      e.information = informationFromVariances(options_.odometry_translation_variance,
                                               options_.odometry_rotation_variance);
      out.pose_graph.push_back(e);
    }
    chain_.push_back(k);
    chain_poses_[k] = pose;
  }
  // Control points from the mesh vertices not scanned yet (they need a keyframe to attach to).
  if (!keyframes.empty()) {
    std::vector<std::pair<int64_t, NodeId>> by_time;
    for (const NodeId k : keyframes)
      by_time.emplace_back(graph.getNode(k).find<AgentAttributes>()->timestamp_ns, k);
    std::sort(by_time.begin(), by_time.end());
    // A mesh with stamps (any vertex's not 0: Hydra's mesh has them) gives each vertex the
    // keyframe of its time; one without, the nearest keyframe.
    const std::vector<MeshVertex>& vertices = graph.mesh().vertices;
    const bool stamped = std::any_of(vertices.begin(), vertices.end(),
                                     [](const MeshVertex& v) { return v.time_ns != 0; });
    const auto keyframeOf = [&](const MeshVertex& v) {
      if (stamped) {
        auto it = std::upper_bound(by_time.begin(), by_time.end(),
                                   std::make_pair(v.time_ns, NodeId(~uint64_t{0})));
        return it == by_time.begin() ? by_time.front().second : std::prev(it)->second;
      }
      NodeId nearest = keyframes.front();
      double best = std::numeric_limits<double>::infinity();
      for (const NodeId k : keyframes) {
        const double d = (graph.getNode(k).position - v.position.cast<double>()).squaredNorm();
        if (d < best) best = d, nearest = k;
      }
      return nearest;
    };
    for (size_t i = first_vertex; i < vertices.size(); ++i) {
      const Eigen::Vector3d p = vertices[i].position.cast<double>();
      const Eigen::Vector3i key = (p / options_.control_point_spacing).array().floor().cast<int>();
      const Voxel voxel{key.x(), key.y(), key.z()};
      if (voxels_.count(voxel)) continue;
      const uint64_t id = voxels_.size();
      voxels_[voxel] = id;
      out.deformation.points.push_back({id, p, vertices[i].time_ns, keyframeOf(vertices[i])});
      for (int dz = -1; dz <= 1; ++dz) {
        for (int dy = -1; dy <= 1; ++dy) {
          for (int dx = -1; dx <= 1; ++dx) {
            const auto it = voxels_.find({key.x() + dx, key.y() + dy, key.z() + dz});
            if (it != voxels_.end() && it->second != id)
              out.deformation.edges.push_back({it->second, id});
          }
        }
      }
    }
    vertices_scanned_ = vertices.size();
  }
  // Bags of words not sent yet, or changed.
  for (const auto& [k, words] : bow) {
    const auto sent = bow_sent_.find(k);
    if (sent != bow_sent_.end() && sent->second == words) continue;
    out.descriptors.push_back({k, words, {}});
    bow_sent_[k] = words;
  }
  return out;
}

Result<io::spark::Graph> hydraGraphOfMap(const RobotUpdate& snapshot) {
  auto graph = graphFromSnapshot(snapshot.graph);
  if (!graph) return Error{graph.error()};
  io::spark::Graph spark = io::sparkFromSceneGraph(graph.value(), true);
  std::map<uint64_t, const KeyframeDescriptor*> bow;
  for (const KeyframeDescriptor& d : snapshot.descriptors) bow[d.keyframe.value()] = &d;
  for (io::spark::Node& n : spark.nodes) {
    const auto it = bow.find(n.id);
    if (n.attributes.type != "AgentNodeAttributes" || it == bow.end()) continue;
    io::spark::Matrix& ids = n.attributes.dbow_ids;
    io::spark::Matrix& values = n.attributes.dbow_values;
    ids.rows = values.rows = static_cast<int64_t>(it->second->bow.size());
    for (const BowEntry& b : it->second->bow) {
      ids.values.push_back(b.word);
      values.values.push_back(b.weight);
    }
  }
  return spark;
}

}  // namespace hydra_multi
