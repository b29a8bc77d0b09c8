#include "hydra_multi/backend/deformation_graph.h"

#include <algorithm>
#include <array>
#include <cstdlib>
#include <limits>
#include <set>
#include <unordered_map>

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
  std::set<NodeId> merged;  // objects in merge candidates become nodes too
  std::set<NodeId> control_points;
  for (const PoseGraphEdge& e : merges) {
    merged.insert(e.from);
    merged.insert(e.to);
  }
  // At most: the robots' own edges, a place's (or merged object's) tie, a control point's ties,
  // the frames' ties and the robust factors (large at team scale: no growth by copies).
  size_t skeleton_most = inter_robot.size() + merges.size() + robots.size() + merged.size();
  size_t control_most = 0;
  for (const RobotDeformationInput& input : robots) {
    if (input.pose_graph != nullptr) skeleton_most += input.pose_graph->size();
    if (input.control_points != nullptr) control_most += input.control_points->size();
    if (input.control_point_edges != nullptr) control_most += input.control_point_edges->size();
    skeleton_most += frontend.nodesOfRobot(input.robot, Layer::kPlaces).size();
  }
  if (whole) dg.graph.edges.reserve(skeleton_most + control_most);
  dg.skeleton.edges.reserve(skeleton_most);
  for (const RobotDeformationInput& input : robots) {
    const Eigen::Isometry3d& T = input.T_global_robot;
    std::map<NodeId, Eigen::Isometry3d> local;  // keyframes in the robot's frame
    std::map<NodeId, int64_t> keyframe_time;
    std::vector<NodeId> places;
    NodeId first;
    int64_t first_time = std::numeric_limits<int64_t>::max();
    for (const NodeId id : frontend.nodesOfRobot(input.robot)) {
      const Node& node = frontend.getNode(id);
      if (node.layer() == Layer::kAgents) {
        local[id] = nodePose(node);
        dg.initial[id] = T * local[id];
        const int64_t t = node.find<AgentAttributes>()->timestamp_ns;
        keyframe_time[id] = t;
        if (t < first_time) {
          first_time = t;
          first = id;
        }
      } else if (node.layer() == Layer::kPlaces ||
                 (node.layer() == Layer::kObjects && merged.count(id))) {
        places.push_back(id);
      }
    }
    if (local.empty()) continue;
    first_keyframes.push_back(first);
    if (input.pose_graph != nullptr) {
      for (PoseGraphEdge e : *input.pose_graph) {
        if (!local.count(e.from) || !local.count(e.to)) continue;
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
        dg.skeleton.edges.push_back(e);
        if (closure) ++dg.robust_factors;
      }
    }
    // Mesh control points, their rigidity and the keyframes that observed them.
    const int64_t window = windowNs(options.link_max_dt_s);
    std::vector<Eigen::Vector3d> cp_positions;
    std::vector<int64_t> cp_times;
    std::vector<NodeId> cp_ids;
    std::map<uint64_t, const ControlPoint*> cp_by_index;
    if (input.control_points != nullptr) {
      for (const ControlPoint& cp : *input.control_points) {
        const NodeId id = controlPointId(input.robot, cp.id);
        dg.initial[id] = T * at(cp.position);
        control_points.insert(id);
        if (whole) {  // for the whole graph's ties
          cp_positions.push_back(cp.position);
          cp_times.push_back(cp.time_ns);
          cp_ids.push_back(id);
          cp_by_index[cp.id] = &cp;
        }
        const auto keyframe = local.find(cp.keyframe);
        if (keyframe != local.end()) {
          dg.observed_by[id] = cp.keyframe;
          toWhole(edge(cp.keyframe, id, keyframe->second.inverse() * at(cp.position),
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
    std::vector<Eigen::Vector3d> kf_positions;
    std::vector<int64_t> kf_times;
    std::vector<NodeId> kf_ids;
    for (const auto& [id, pose] : local) {
      kf_positions.push_back(pose.translation());
      kf_times.push_back(keyframe_time[id]);
      kf_ids.push_back(id);
    }
    const TimedNeighbors near_kf(kf_positions, kf_times, window);
    for (const NodeId place : places) {
      const Node& node = frontend.getNode(place);
      const Eigen::Vector3d p = node.position;
      dg.initial[place] = T * at(p);
      const int64_t made = madeAtNs(node, input.mesh);
      const size_t k = near_kf.nearest(p, made).front().index;
      const PoseGraphEdge to_keyframe =
          edge(kf_ids[k], place, local[kf_ids[k]].inverse() * at(p), options.mesh_variance);
      dg.skeleton.edges.push_back(to_keyframe);
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
  for (const auto& [id, pose] : dg.initial) {
    if (!control_points.count(id))
      dg.skeleton.poses.emplace_hint(dg.skeleton.poses.end(), id, pose);
  }
  return dg;
}

}  // namespace hydra_multi
