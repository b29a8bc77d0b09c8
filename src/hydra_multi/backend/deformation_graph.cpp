#include "hydra_multi/backend/deformation_graph.h"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <limits>
#include <set>
#include <unordered_map>
#include <unordered_set>

#include "hydra_multi/core/nearest_neighbors.h"

namespace hydra_multi {
namespace {

Eigen::Isometry3d at(const Eigen::Vector3d& p) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() = p;
  return T;
}

PoseGraphEdge edge(NodeId from, NodeId to, const Eigen::Isometry3d& T_from_to, double variance,
                   PoseGraphEdge::Kind kind = PoseGraphEdge::Kind::kOdometry) {
  PoseGraphEdge e;
  e.from = from;
  e.to = to;
  e.T_from_to = T_from_to;
  e.information = informationFromVariances(variance, variance);
  e.kind = kind;
  return e;
}

// A gauge prior: the weakest of links from the anchor to a robot's first keyframe, so that a
// robot whose every inter-robot factor GNC rejects still has a defined place (as aligned).
constexpr double kGaugeVariance = 1e6;

struct Placed {  // a node's global pose before optimization
  NodeId id;
  Eigen::Isometry3d pose;
  bool control_point = false;
};

}  // namespace

NodeId controlPointId(RobotId robot, uint64_t index) { return NodeId::station('M', robot, index); }

int64_t madeAtNs(const Node& node, const Mesh* mesh) {
  const ObjectAttributes* object = node.find<ObjectAttributes>();
  if (object == nullptr || mesh == nullptr) return node.last_update_time_ns;
  std::vector<int64_t> times;
  for (const uint64_t v : object->mesh_vertices) {
    if (v < mesh->vertices.size()) times.push_back(mesh->vertices[v].time_ns);
  }
  if (times.empty()) return node.last_update_time_ns;
  const auto middle = times.begin() + static_cast<std::ptrdiff_t>(times.size() / 2);
  std::nth_element(times.begin(), middle, times.end());
  return *middle;
}

ControlPointGraph coarserControlPoints(const std::vector<ControlPoint>& points,
                                       const std::vector<ControlPointEdge>& edges, double voxel) {
  ControlPointGraph coarse;
  std::map<std::array<int64_t, 3>, uint64_t> first_in;  // voxel -> its kept point
  std::unordered_map<uint64_t, uint64_t> kept_for;      // point -> the kept point of its voxel
  kept_for.reserve(points.size());
  for (const ControlPoint& cp : points) {
    const Eigen::Vector3d cell = (cp.position / voxel).array().floor();
    const auto [it, first] =
        first_in.try_emplace({int64_t(cell.x()), int64_t(cell.y()), int64_t(cell.z())}, cp.id);
    kept_for[cp.id] = it->second;
    if (first) coarse.points.push_back(cp);
  }
  std::set<std::pair<uint64_t, uint64_t>> joined;
  for (const ControlPointEdge& e : edges) {
    const auto a = kept_for.find(e.from), b = kept_for.find(e.to);
    if (a == kept_for.end() || b == kept_for.end() || a->second == b->second) continue;
    if (joined.insert(std::minmax(a->second, b->second)).second)
      coarse.edges.push_back({a->second, b->second});
  }
  return coarse;
}

DeformationGraph buildDeformationGraph(const SceneGraph& frontend,
                                       const std::vector<RobotDeformationInput>& robots,
                                       const std::vector<PoseGraphEdge>& inter_robot,
                                       const std::vector<PoseGraphEdge>& merges,
                                       const DeformationGraphOptions& options) {
  DeformationGraph dg;
  // A solve that stops at the skeleton needs no factor of the whole graph.
  const bool whole = dg.whole = !options.two_stage || options.final_iterations > 0;
  const auto toWhole = [&dg, whole](const PoseGraphEdge& e) {
    if (whole) dg.graph.edges.push_back(e);
  };
  std::vector<NodeId> first_keyframes;
  std::unordered_set<NodeId> merged;  // objects in merge candidates become nodes too
  for (const PoseGraphEdge& e : merges) {
    merged.insert(e.from);
    merged.insert(e.to);
  }
  // Every node's global pose and every control point's keyframe, gathered unordered and put in
  // their maps in id order at the end (one tree look-up per node is most of the assembly).
  std::vector<Placed> initial;
  std::vector<std::pair<NodeId, NodeId>> observed_by;
  // At most: the robots' own edges, a place's (or merged object's) tie, a control point's ties,
  // the frames' ties and the robust factors (large at team scale: no growth by copies).
  size_t skeleton_most = inter_robot.size() + merges.size() + robots.size() + merged.size();
  size_t control_most = 0;
  size_t nodes_most = merged.size();
  for (const RobotDeformationInput& input : robots) {
    if (input.pose_graph != nullptr) skeleton_most += input.pose_graph->size();
    if (input.control_points != nullptr) {
      control_most += input.control_points->size();
      nodes_most += input.control_points->size();
    }
    if (input.control_point_edges != nullptr) control_most += input.control_point_edges->size();
    skeleton_most += frontend.numNodes(input.robot, Layer::kPlaces);
    nodes_most += frontend.numNodes(input.robot, Layer::kAgents) +
                  frontend.numNodes(input.robot, Layer::kPlaces);
  }
  if (whole) dg.graph.edges.reserve(skeleton_most + control_most);
  dg.skeleton.edges.reserve(skeleton_most);
  initial.reserve(nodes_most);
  for (const RobotDeformationInput& input : robots) {
    const Eigen::Isometry3d& T = input.T_global_robot;
    // The robot's keyframes in id order, in its own frame, and where each one sits.
    std::vector<NodeId> kf_ids;
    std::vector<Eigen::Isometry3d> kf_local;
    std::vector<Eigen::Vector3d> kf_positions;
    std::vector<int64_t> kf_times;
    std::unordered_map<NodeId, size_t> keyframe;
    std::vector<NodeId> places;
    NodeId first;
    int64_t first_time = std::numeric_limits<int64_t>::max();
    for (const Node* robot_node : frontend.robotNodes(input.robot)) {
      const Node& node = *robot_node;
      const NodeId id = node.id;
      if (node.layer() == Layer::kAgents) {
        const Eigen::Isometry3d local = nodePose(node);
        const int64_t t = node.find<AgentAttributes>()->timestamp_ns;
        keyframe.emplace(id, kf_ids.size());
        kf_ids.push_back(id);
        kf_local.push_back(local);
        kf_positions.push_back(local.translation());
        kf_times.push_back(t);
        initial.push_back({id, T * local});
        if (t < first_time) {
          first_time = t;
          first = id;
        }
      } else if (node.layer() == Layer::kPlaces ||
                 (node.layer() == Layer::kObjects && merged.count(id))) {
        places.push_back(id);
      }
    }
    if (kf_ids.empty()) continue;
    first_keyframes.push_back(first);
    if (input.pose_graph != nullptr) {
      for (const PoseGraphEdge& sent : *input.pose_graph) {
        if (!keyframe.count(sent.from) || !keyframe.count(sent.to)) continue;
        PoseGraphEdge& e = dg.skeleton.edges.emplace_back(sent);
        const bool closure = e.kind == PoseGraphEdge::Kind::kLoopClosure;
        if (!options.use_sent_information) {
          const double variance =
              closure ? options.loop_closure_variance : options.odometry_variance;
          e.information = informationFromVariances(variance, variance);
        }
        if (!closure) {
          e.information.block<3, 3>(0, 3).setZero();
          e.information.block<3, 3>(3, 0).setZero();
          e.information.block<3, 3>(3, 3) =
              Eigen::Matrix3d::Identity() / options.odometry_rotation_variance;
        }
        toWhole(e);
        if (closure) ++dg.robust_factors;
      }
    }
    // Mesh control points, their rigidity and the keyframes that observed them.
    const int64_t window = windowNs(options.link_max_dt_s);
    std::vector<Eigen::Vector3d> cp_positions;
    std::vector<int64_t> cp_times;
    std::vector<NodeId> cp_ids;
    std::unordered_map<uint64_t, const ControlPoint*> cp_by_index;
    if (input.control_points != nullptr) {
      if (whole) cp_by_index.reserve(input.control_points->size());
      for (const ControlPoint& cp : *input.control_points) {
        const NodeId id = controlPointId(input.robot, cp.id);
        initial.push_back({id, T * at(cp.position), true});
        if (whole) {  // for the whole graph's ties
          cp_positions.push_back(cp.position);
          cp_times.push_back(cp.time_ns);
          cp_ids.push_back(id);
          cp_by_index[cp.id] = &cp;
        }
        const auto k = keyframe.find(cp.keyframe);
        if (k != keyframe.end()) {
          observed_by.emplace_back(id, cp.keyframe);
          toWhole(edge(cp.keyframe, id, kf_local[k->second].inverse() * at(cp.position),
                       options.mesh_variance));
        }
      }
    }
    if (whole && input.control_point_edges != nullptr) {
      for (const ControlPointEdge& e : *input.control_point_edges) {
        const auto a = cp_by_index.find(e.from), b = cp_by_index.find(e.to);
        if (a == cp_by_index.end() || b == cp_by_index.end()) continue;
        if (window > 0 && std::abs(a->second->time_ns - b->second->time_ns) > window) continue;
        dg.graph.edges.push_back(
            edge(controlPointId(input.robot, e.from), controlPointId(input.robot, e.to),
                 at(b->second->position - a->second->position), options.mesh_variance));
      }
    }
    // Places (and merge-candidate objects): linked to the nearest control point, or else the
    // nearest keyframe, of those the robot made about when it placed the node (madeAtNs).
    const TimedNeighbors near_cp(cp_positions, cp_times, window);
    const TimedNeighbors near_kf(kf_positions, kf_times, window);
    for (const NodeId place : places) {
      const Node& node = frontend.getNode(place);
      const Eigen::Vector3d p = node.position;
      initial.push_back({place, T * at(p)});
      const int64_t made = madeAtNs(node, input.mesh);
      const size_t k = near_kf.nearest(p, made).front().index;
      const PoseGraphEdge& to_keyframe = dg.skeleton.edges.emplace_back(
          edge(kf_ids[k], place, kf_local[k].inverse() * at(p), options.mesh_variance));
      if (!whole) continue;
      const auto cp = near_cp.nearest(p, made);
      if (!cp.empty() && cp.front().distance <= options.place_link_radius) {
        dg.graph.edges.push_back(edge(cp_ids[cp.front().index], place,
                                      at(p - cp_positions[cp.front().index]),
                                      options.mesh_variance));
      } else {
        dg.graph.edges.push_back(to_keyframe);
      }
    }
  }
  // Into the maps in id order, each insertion at the end. A node given twice keeps its last pose,
  // and stays out of the skeleton if it was ever a control point.
  std::stable_sort(initial.begin(), initial.end(),
                   [](const Placed& a, const Placed& b) { return a.id < b.id; });
  bool control_point = false;
  for (size_t i = 0; i < initial.size(); ++i) {
    control_point = control_point || initial[i].control_point;
    if (i + 1 < initial.size() && initial[i + 1].id == initial[i].id) continue;
    dg.initial.emplace_hint(dg.initial.end(), initial[i].id, initial[i].pose);
    if (!control_point)
      dg.skeleton.poses.emplace_hint(dg.skeleton.poses.end(), initial[i].id, initial[i].pose);
    control_point = false;
  }
  std::stable_sort(observed_by.begin(), observed_by.end(),
                   [](const auto& a, const auto& b) { return a.first < b.first; });
  for (size_t i = 0; i < observed_by.size(); ++i) {
    if (i + 1 < observed_by.size() && observed_by[i + 1].first == observed_by[i].first) continue;
    dg.observed_by.emplace_hint(dg.observed_by.end(), observed_by[i]);
  }
  if (first_keyframes.empty()) return dg;
  dg.anchor = first_keyframes.front();
  for (size_t r = 1; r < first_keyframes.size(); ++r) {
    const PoseGraphEdge gauge =
        edge(dg.anchor, first_keyframes[r],
             dg.initial[dg.anchor].inverse() * dg.initial[first_keyframes[r]], kGaugeVariance);
    toWhole(gauge);
    dg.skeleton.edges.push_back(gauge);
  }
  for (const auto* list : {&inter_robot, &merges}) {
    for (PoseGraphEdge e : *list) {
      if (!dg.initial.count(e.from) || !dg.initial.count(e.to)) continue;
      e.kind = PoseGraphEdge::Kind::kLoopClosure;
      if (!options.use_sent_information && list == &inter_robot)
        e.information =
            informationFromVariances(options.loop_closure_variance, options.loop_closure_variance);
      toWhole(e);
      dg.skeleton.edges.push_back(e);
      ++dg.robust_factors;
      if (list == &inter_robot) ++dg.inter_robot_factors;
      if (list == &merges) dg.merge_factors.insert({e.from, e.to});
    }
  }
  return dg;
}

}  // namespace hydra_multi
