#include "hydra_multi/eval/dataset_evaluation.h"

#include <algorithm>
#include <cmath>
#include <queue>
#include <set>
#include <unordered_map>
#include <unordered_set>

#include "hydra_multi/dsg/graph_delta.h"
#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/dsg/io/dataset_files.h"
#include "hydra_multi/dsg/io/graph_file.h"
#include "hydra_multi/dsg/robot_stream.h"
#include "hydra_multi/eval/trajectory_error.h"

namespace hydra_multi {
namespace {

int64_t cellKey(int x, int y, int floor) {
  return (static_cast<int64_t>(floor) << 42) ^ (static_cast<int64_t>(x + (1 << 20)) << 21) ^
         static_cast<int64_t>(y + (1 << 20));
}

}  // namespace

TrueRooms::TrueRooms(const DatasetGroundTruth& truth) : truth_(&truth) {
  for (size_t r = 0; r < truth.room_cells.size(); ++r) {
    for (const Eigen::Vector3i& c : truth.room_cells[r])
      room_of_cell_[cellKey(c.x(), c.y(), c.z())] = truth.room_ids[r];
  }
}

int TrueRooms::at(const Eigen::Vector3d& p) const {
  const GroundTruthGrid* grid = truth_->gridFor(p.z());
  if (grid == nullptr) return -1;
  const Eigen::Vector2i c = grid->cellOf(p.head<2>());
  const auto it = room_of_cell_.find(cellKey(c.x(), c.y(), grid->floor));
  return it == room_of_cell_.end() ? -1 : it->second;
}

bool TrueRooms::inRoom(int x, int y, int floor) const {
  return room_of_cell_.count(cellKey(x, y, floor)) != 0;
}

MergeCheck checkMerge(const TrueRooms& rooms, const MergeSide& a, const MergeSide& b,
                      double min_distance_m) {
  MergeCheck check;
  const DatasetGroundTruth& truth = rooms.truth();
  const Eigen::Isometry3d* world_a = truth.poseAt(a.robot, a.keyframe_stamp_ns);
  const Eigen::Isometry3d* world_b = truth.poseAt(b.robot, b.keyframe_stamp_ns);
  if (world_a == nullptr || world_b == nullptr) return check;
  const Eigen::Vector3d p = *world_a * (a.T_robot_keyframe.inverse() * a.position);
  const Eigen::Vector3d q = *world_b * (b.T_robot_keyframe.inverse() * b.position);
  check.checked = true;
  check.true_distance_m = (p - q).norm();
  const int room_p = rooms.at(p), room_q = rooms.at(q);
  check.room_a = room_p;
  check.room_b = room_q;
  check.across_rooms =
      room_p >= 0 && room_q >= 0 && room_p != room_q && check.true_distance_m > min_distance_m;
  return check;
}

Result<TrajectoryError> keyframeTrajectoryError(const SceneGraph& graph,
                                                const DatasetGroundTruth& truth,
                                                std::vector<ScoredKeyframe>* keyframes) {
  std::vector<Eigen::Vector3d> estimate, reference;
  for (const NodeId id : graph.nodesInLayer(Layer::kAgents)) {
    const Node& node = graph.getNode(id);
    const auto robot = node.robot();
    const AgentAttributes* agent = node.find<AgentAttributes>();
    if (!robot || agent == nullptr) continue;
    if (const Eigen::Isometry3d* T = truth.poseAt(*robot, agent->timestamp_ns)) {
      estimate.push_back(node.position);
      reference.push_back(T->translation());
      if (keyframes != nullptr)
        keyframes->push_back({id, agent->timestamp_ns, node.position, T->translation()});
    }
  }
  return absoluteTrajectoryError(estimate, reference);
}

SceneGraphScore evaluateSceneGraph(const SceneGraph& graph, const DatasetGroundTruth& truth,
                                   std::optional<RobotId> global_robot) {
  SceneGraphScore score;
  score.object_threshold_m = truth.object_threshold_m;
  const Eigen::Isometry3d T_world_global = truth.worldFromGlobal(global_robot);

  const auto ate = keyframeTrajectoryError(graph, truth, &score.keyframes);
  score.matched_keyframes = score.keyframes.size();
  Eigen::Isometry3d T_world_graph = T_world_global;
  if (ate) {
    score.ate_rmse_m = ate.value().statistics.rmse;
    // The paper registers the ground truth to the first robot's frame (by ICP of the meshes):
    // the graph is scored after the best rigid fit of its keyframes to the truth.
    T_world_graph = ate.value().T_reference_estimate;
    score.aligned_by_trajectory = true;
  }

  for (ScoredKeyframe& k : score.keyframes) k.position_world = T_world_graph * k.position_world;

  std::vector<LabelledPoint> objects;
  const auto object_ids = graph.nodesInLayer(Layer::kObjects);
  for (const NodeId id : object_ids) {
    const Node& node = graph.getNode(id);
    objects.push_back({node.semantic()->label, T_world_graph * node.position});
  }
  score.num_objects = objects.size();
  const ObjectMetrics object_metrics =
      objectMetrics(objects, truth.objects, truth.object_threshold_m);
  score.objects_found_pct = object_metrics.found_pct;
  score.objects_correct_pct = object_metrics.correct_pct;
  score.objects_correct = object_metrics.correct;
  score.objects_duplicates = object_metrics.duplicates;
  score.objects_wrong_label = object_metrics.wrong_label;
  score.objects_misplaced = object_metrics.misplaced;
  for (size_t i = 0; i < objects.size(); ++i) {
    score.objects.push_back(
        {object_ids[i], objects[i].label, objects[i].position, object_metrics.verdicts[i]});
  }

  std::vector<Eigen::Vector3d> places;
  for (const NodeId id : graph.nodesInLayer(Layer::kPlaces))
    places.push_back(T_world_graph * graph.getNode(id).position);
  score.num_places = places.size();
  score.places_position_error_m = placesPositionError(places, truth.gvd);

  // Rooms: the true free cells inside the spheres of each room's places.
  const TrueRooms free_cells(truth);
  std::vector<std::vector<Eigen::Vector3i>> estimated;
  for (const NodeId room : graph.nodesInLayer(Layer::kRooms)) {
    std::vector<Eigen::Vector3i> cells;
    for (const NodeId child : graph.children(room)) {
      const Node& place = graph.getNode(child);
      const PlaceAttributes* attributes = place.find<PlaceAttributes>();
      if (attributes == nullptr) continue;
      const Eigen::Vector3d p = T_world_graph * place.position;
      const GroundTruthGrid* grid = truth.gridFor(p.z());
      if (grid == nullptr) continue;
      const int reach = static_cast<int>(std::ceil(attributes->distance / grid->resolution));
      const Eigen::Vector2i centre = grid->cellOf(p.head<2>());
      for (int dy = -reach; dy <= reach; ++dy) {
        for (int dx = -reach; dx <= reach; ++dx) {
          if (std::hypot(dx, dy) * grid->resolution > attributes->distance) continue;
          const int x = centre.x() + dx, y = centre.y() + dy;
          if (free_cells.inRoom(x, y, grid->floor)) cells.emplace_back(x, y, grid->floor);
        }
      }
    }
    estimated.push_back(std::move(cells));
  }
  score.num_rooms = estimated.size();
  const RoomMetrics room_metrics = roomMetrics(estimated, truth.room_cells);
  score.rooms_precision = room_metrics.precision;
  score.rooms_recall = room_metrics.recall;
  return score;
}

SceneGraph combineRobotGraphs(const std::vector<std::pair<RobotId, SceneGraph>>& graphs,
                              const std::map<RobotId, Eigen::Isometry3d>& T_global_robot) {
  SceneGraph combined;
  for (const auto& [robot, graph] : graphs) {
    const auto pose = T_global_robot.find(robot);
    const Eigen::Isometry3d T =
        pose == T_global_robot.end() ? Eigen::Isometry3d::Identity() : pose->second;
    const auto remap = [&, robot = robot](NodeId id) {
      if (graph.getNode(id).layer() == Layer::kAgents || id.isStation()) return id;
      return NodeId::station(id.category(), robot, id.index());
    };
    const uint64_t offset = combined.mesh().vertices.size();
    for (const auto& [id, original] : graph.nodes()) {
      Node node = original;
      node.id = remap(id);
      node.position = T * node.position;
      if (AgentAttributes* agent = node.find<AgentAttributes>())
        agent->orientation = Eigen::Quaterniond(T.linear()) * agent->orientation;
      if (SemanticAttributes* semantic = node.semantic(); semantic && semantic->bounding_box) {
        // The box of the moved corners.
        const BoundingBox box = *semantic->bounding_box;
        BoundingBox moved{Eigen::Vector3d::Constant(1e300), Eigen::Vector3d::Constant(-1e300)};
        for (int c = 0; c < 8; ++c) {
          const Eigen::Vector3d corner((c & 1) ? box.max.x() : box.min.x(),
                                       (c & 2) ? box.max.y() : box.min.y(),
                                       (c & 4) ? box.max.z() : box.min.z());
          moved = moved.merged({T * corner, T * corner});
        }
        semantic->bounding_box = moved;
      }
      if (ObjectAttributes* object = node.find<ObjectAttributes>())
        for (uint64_t& v : object->mesh_vertices) v += offset;
      if (PlaceAttributes* place = node.find<PlaceAttributes>())
        for (uint64_t& v : place->mesh_vertices) v += offset;
      combined.addOrUpdateNode(std::move(node));
    }
    for (const auto& [key, info] : graph.edges())
      combined.addOrUpdateEdge(remap(key.first()), remap(key.second()), info);
    for (MeshVertex vertex : graph.mesh().vertices) {
      vertex.position = (T * vertex.position.cast<double>()).cast<float>();
      combined.mesh().vertices.push_back(vertex);
    }
    for (MeshFace face : graph.mesh().faces) {
      for (uint32_t& v : face) v += static_cast<uint32_t>(offset);
      combined.mesh().faces.push_back(face);
    }
  }
  return combined;
}

LoopClosureCheck checkLoopClosure(const DatasetGroundTruth& truth, RobotId robot_a, int64_t stamp_a,
                                  RobotId robot_b, int64_t stamp_b, const Eigen::Isometry3d& T_a_b,
                                  double max_translation_m, double max_rotation_deg) {
  LoopClosureCheck check;
  const Eigen::Isometry3d* a = truth.poseAt(robot_a, stamp_a);
  const Eigen::Isometry3d* b = truth.poseAt(robot_b, stamp_b);
  if (a == nullptr || b == nullptr) return check;
  check.known = true;
  const Eigen::Isometry3d error = (a->inverse() * *b).inverse() * T_a_b;
  check.translation_error_m = error.translation().norm();
  check.rotation_error_deg = Eigen::AngleAxisd(error.linear()).angle() * 180.0 / M_PI;
  check.correct = check.translation_error_m <= max_translation_m &&
                  check.rotation_error_deg <= max_rotation_deg;
  return check;
}

Result<DatasetDifficulty> measureDatasetDifficulty(const std::string& dir, size_t top_pairs) {
  auto loaded = readDatasetGroundTruth(dir);
  if (!loaded) return Error{loaded.error()};
  const DatasetGroundTruth& truth = loaded.value();
  DatasetDifficulty difficulty;
  difficulty.object_threshold_m = truth.object_threshold_m;
  const TrueRooms free_cells(truth);
  // Keyframes count for aliasing inside rooms proper: a corridor is one "room" however long.
  std::set<int> rooms_proper;
  for (size_t i = 0; i < truth.room_ids.size(); ++i) {
    if (truth.room_kinds[i] != "corridor" && truth.room_kinds[i] != "stairwell")
      rooms_proper.insert(truth.room_ids[i]);
  }
  const Eigen::Isometry3d T_global_world = truth.worldFromGlobal().inverse();

  struct Keyframe {
    RobotId robot;
    int room = -1;
    std::vector<BowEntry> bow;
  };
  std::vector<Keyframe> keyframes;
  std::vector<std::pair<RobotId, SceneGraph>> graphs;
  std::map<RobotId, Eigen::Isometry3d> T_global_robot;
  std::vector<LabelledPoint> undrifted;  // world frame
  for (const RobotId robot : truth.robots) {
    auto records = io::loadRobotStream(truth.streams.at(robot), robot);
    if (!records) return Error{records.error()};
    // The stream as the station replays it (a damaged record leaves its gap).
    RobotStreamReplay replay(robot, io::robotUpdateDigest);
    std::map<NodeId, int64_t> first_sent;
    for (const RobotUpdate& update : records.value().updates) {
      replay.add(update, [&](const RobotUpdate& applied, const SceneGraph& graph) {
        for (const Node& node : applied.graph.nodes) first_sent.emplace(node.id, applied.time_ns);
        for (const KeyframeDescriptor& d : applied.descriptors) {
          const Node* agent = graph.findNode(d.keyframe);
          const AgentAttributes* a = agent ? agent->find<AgentAttributes>() : nullptr;
          const Eigen::Isometry3d* T = a ? truth.poseAt(robot, a->timestamp_ns) : nullptr;
          const int room = T ? free_cells.at(T->translation()) : -1;
          keyframes.push_back({robot, rooms_proper.count(room) ? room : -1, d.bow});
        }
      });
    }
    SceneGraph graph = std::move(replay.graph());
    // The robot's keyframes by time: true and odometric poses.
    std::vector<std::pair<int64_t, Eigen::Isometry3d>> corrections;  // T_world_odom at t
    for (const NodeId id : graph.nodesInLayer(Layer::kAgents)) {
      const Node& node = graph.getNode(id);
      const AgentAttributes* a = node.find<AgentAttributes>();
      const Eigen::Isometry3d* T = truth.poseAt(robot, a->timestamp_ns);
      if (T == nullptr) continue;
      corrections.emplace_back(a->timestamp_ns, *T * nodePose(node).inverse());
    }
    std::sort(corrections.begin(), corrections.end(),
              [](const auto& x, const auto& y) { return x.first < y.first; });
    for (const NodeId id : graph.nodesInLayer(Layer::kObjects)) {
      const Node& node = graph.getNode(id);
      const int64_t t = first_sent.at(id);
      auto it = std::upper_bound(corrections.begin(), corrections.end(), t,
                                 [](int64_t v, const auto& c) { return v < c.first; });
      if (it == corrections.begin()) continue;
      --it;
      undrifted.push_back({node.semantic()->label, it->second * node.position});
    }
    T_global_robot[robot] = T_global_world * truth.start_poses.at(robot);
    graphs.emplace_back(robot, std::move(graph));
  }
  difficulty.odometry = evaluateSceneGraph(combineRobotGraphs(graphs, T_global_robot), truth);
  const ObjectMetrics no_drift = objectMetrics(undrifted, truth.objects, truth.object_threshold_m);
  difficulty.no_drift.objects_found_pct = no_drift.found_pct;
  difficulty.no_drift.objects_correct_pct = no_drift.correct_pct;
  difficulty.no_drift.num_objects = undrifted.size();
  difficulty.no_drift.object_threshold_m = truth.object_threshold_m;

  // Bag-of-words similarity of inter-robot pairs (sum of shared minima of L1-normalized vectors,
  // the same as 1 - L1/2), through an inverted index; the best `top_pairs` kept in a heap.
  std::unordered_map<uint32_t, std::vector<std::pair<size_t, float>>> postings;
  for (size_t i = 0; i < keyframes.size(); ++i) {
    if (keyframes[i].room < 0) continue;
    for (const BowEntry& e : keyframes[i].bow) postings[e.word].emplace_back(i, e.weight);
  }
  using Scored = std::pair<double, std::pair<size_t, size_t>>;
  std::priority_queue<Scored, std::vector<Scored>, std::greater<Scored>> best;
  std::unordered_map<size_t, double> similarity;
  for (size_t i = 0; i < keyframes.size(); ++i) {
    if (keyframes[i].room < 0) continue;
    similarity.clear();
    for (const BowEntry& e : keyframes[i].bow) {
      for (const auto& [j, w] : postings[e.word]) {
        if (!(keyframes[i].robot < keyframes[j].robot)) continue;  // each pair once, inter-robot
        similarity[j] += std::min(e.weight, w);
      }
    }
    for (const auto& [j, s] : similarity) {
      if (best.size() < top_pairs) {
        best.push({s, {i, j}});
      } else if (s > best.top().first) {
        best.pop();
        best.push({s, {i, j}});
      }
    }
  }
  difficulty.top_pairs = best.size();
  size_t aliased = 0;
  while (!best.empty()) {
    const auto [i, j] = best.top().second;
    if (keyframes[i].room != keyframes[j].room) ++aliased;
    difficulty.top_similarity_mean += best.top().first / double(difficulty.top_pairs);
    best.pop();
  }
  difficulty.aliased_pct =
      difficulty.top_pairs ? 100.0 * double(aliased) / double(difficulty.top_pairs) : 0.0;
  return difficulty;
}

}  // namespace hydra_multi
