#include "hydra_multi/backend/initial_alignment.h"

namespace hydra_multi {

const std::map<RobotId, RobotFrameAlignment>& InitialAlignment::update(
    const SceneGraph& frontend, const std::vector<PoseGraphEdge>& inter_robot,
    RobotId preferred_root, const std::map<RobotId, Eigen::Isometry3d>& optimized_first_keyframes,
    const std::vector<double>& support, bool afresh) {
  if (!root_) root_ = preferred_root;
  const RobotId root = *root_;
  // Robots in a dense order, the root first.
  std::vector<RobotId> robots = {root};
  for (const RobotId r : frontend.robots()) {
    if (r != root) robots.push_back(r);
  }
  std::map<RobotId, size_t> index;
  for (size_t i = 0; i < robots.size(); ++i) index[robots[i]] = i;
  std::map<NodeId, Eigen::Isometry3d> poses;
  std::unordered_map<NodeId, size_t> robot_of;
  std::map<RobotId, std::pair<int64_t, NodeId>> first_keyframe;
  for (const NodeId id : frontend.nodesInLayer(Layer::kAgents)) {
    const Node& node = frontend.getNode(id);
    const auto robot = node.robot();
    if (!robot || !index.count(*robot)) continue;
    poses[id] = nodePose(node);
    robot_of[id] = index[*robot];
    const int64_t t = node.find<AgentAttributes>()->timestamp_ns;
    const auto it = first_keyframe.find(*robot);
    if (it == first_keyframe.end() || t < it->second.first) first_keyframe[*robot] = {t, id};
  }
  std::vector<PoseGraphEdge> edges;
  std::vector<double> edge_support;
  const bool weigh = options_.weigh_support && support.size() == inter_robot.size();
  for (size_t k = 0; k < inter_robot.size(); ++k) {
    const PoseGraphEdge& e = inter_robot[k];
    if (poses.count(e.from) && poses.count(e.to) && robot_of[e.from] != robot_of[e.to]) {
      edges.push_back(e);
      if (weigh) edge_support.push_back(support[k]);
    }
  }
  MultiRobotAlignment result = alignRobotFrames(robots.size(), poses, robot_of, edges, 0,
                                                options_.alignment, edge_support, &consensus_);
  // The preferred root aligned with the current one: the global frame moves to it, and every
  // frame kept or estimated, and the optimized poses compared below, are re-expressed there.
  std::map<RobotId, Eigen::Isometry3d> optimized = optimized_first_keyframes;
  if (preferred_root != root && index.count(preferred_root) &&
      result.T_world_robot[index[preferred_root]]) {
    const Eigen::Isometry3d T_new_old = result.T_world_robot[index[preferred_root]]->inverse();
    for (auto& T : result.T_world_robot)
      if (T) T = T_new_old * *T;
    for (auto& [robot, alignment] : aligned_)
      alignment.T_global_robot = T_new_old * alignment.T_global_robot;
    for (auto& [robot, T] : optimized) T = T_new_old * T;
    for (auto& [robot, tried] : tried_) {
      tried.estimate = T_new_old * tried.estimate;
      tried.optimized = T_new_old * tried.optimized;
    }
    root_ = preferred_root;
    ++root_changes_;
  }
  pairs_ = result.pairs;
  edge_inliers_.clear();
  for (size_t k = 0; k < edges.size(); ++k)
    edge_inliers_[{edges[k].from, edges[k].to}] = result.edge_inlier[k];

  // Keep an alignment unless this round's estimate (from every loop closure so far) puts the
  // robot's start far from where the optimized result has it. (Comparing the kept alignment
  // instead would never catch a wrong early one: the optimization starts from it and stays there,
  // GNC rejecting the loop closures that contradict it.)
  if (afresh) tried_.clear();
  for (size_t i = 0; i < robots.size(); ++i) {
    const RobotId robot = robots[i];
    if (!result.T_world_robot[i]) continue;
    auto known = aligned_.find(robot);
    if (known != aligned_.end() && !options_.always_realign && !afresh) {
      ++known->second.rounds_aligned;
      const auto optimized_first = optimized.find(robot);
      const auto first = first_keyframe.find(robot);
      if (optimized_first == optimized.end() || first == first_keyframe.end()) continue;
      const Eigen::Vector3d by_estimate =
          (*result.T_world_robot[i] * poses[first->second.second]).translation();
      const Eigen::Vector3d by_map = optimized_first->second.translation();
      if ((by_estimate - by_map).norm() <= options_.realign_threshold_m) continue;
      const auto tried = tried_.find(robot);
      if (options_.decline_refuted && tried != tried_.end() &&
          (tried->second.optimized - by_map).norm() <= options_.refuted_within_m &&
          (tried->second.estimate - by_estimate).norm() <= options_.realign_threshold_m) {
        ++declined_;
        continue;
      }
      ++realignments_;
      tried_[robot] = {by_estimate, by_map};
    }
    RobotFrameAlignment& alignment = aligned_[robot];
    alignment.T_global_robot = *result.T_world_robot[i];
    for (const RobotPairAlignment& pair : result.pairs) {
      if (pair.in_tree && (pair.robot_a == i || pair.robot_b == i) && i != 0)
        alignment.inliers = std::max(alignment.inliers, pair.inliers);
    }
  }
  return aligned_;
}

}  // namespace hydra_multi
