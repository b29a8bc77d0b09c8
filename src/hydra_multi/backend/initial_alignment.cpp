#include "hydra_multi/backend/initial_alignment.h"

#include <algorithm>
#include <unordered_map>

namespace hydra_multi {
namespace {

// The weight (`support`, else 1 each) of the loop closures among `edges` that touch a robot
// `moving` marks and whose ends meet within fit_m, each robot in its frame of `frames`.
double fittingSupport(const std::vector<PoseGraphEdge>& edges, const std::vector<double>& support,
                      const std::unordered_map<NodeId, size_t>& robot_of,
                      const std::map<NodeId, Eigen::Isometry3d>& poses,
                      const std::vector<std::optional<Eigen::Isometry3d>>& frames,
                      const std::vector<bool>& moving, double fit_m) {
  double weight = 0.0;
  for (size_t k = 0; k < edges.size(); ++k) {
    const PoseGraphEdge& e = edges[k];
    const size_t from = robot_of.at(e.from), to = robot_of.at(e.to);
    if ((!moving[from] && !moving[to]) || !frames[from] || !frames[to]) continue;
    const Eigen::Vector3d predicted =
        (*frames[from] * poses.at(e.from) * e.T_from_to).translation();
    const Eigen::Vector3d found = (*frames[to] * poses.at(e.to)).translation();
    if ((predicted - found).norm() <= fit_m) weight += support.empty() ? 1.0 : support[k];
  }
  return weight;
}

}  // namespace

const std::map<RobotId, RobotFrameAlignment>& InitialAlignment::update(
    const SceneGraph& frontend, const std::vector<PoseGraphEdge>& inter_robot,
    RobotId preferred_root, const std::map<RobotId, Eigen::Isometry3d>& optimized_first_keyframes,
    const std::vector<double>& support, bool afresh,
    const std::map<std::pair<NodeId, NodeId>, bool>* verdicts) {
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
  struct Candidate {
    size_t index;
    Tried tried;
    bool new_frame;  ///< the estimate moves the start by more than realign_threshold_m
  };
  std::vector<Candidate> candidates;  // aligned robots the estimate would re-align
  std::vector<bool> take(robots.size(), false);
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
      if (options_.realign_against_verdicts && verdicts != nullptr) {
        // The robot's loop closures the estimate holds, as the optimization decided them.
        double decided = 0.0, rejected = 0.0;
        for (size_t k = 0; k < edges.size(); ++k) {
          if (!result.edge_inlier[k] ||
              (robot_of[edges[k].from] != i && robot_of[edges[k].to] != i))
            continue;
          const auto verdict = verdicts->find({edges[k].from, edges[k].to});
          if (verdict == verdicts->end()) continue;
          const double weight = weigh ? edge_support[k] : 1.0;
          decided += weight;
          if (!verdict->second) rejected += weight;
        }
        if (decided > 0.0 && rejected < options_.realign_rejected_share * decided) {
          ++agreed_;
          continue;
        }
      }
      const auto tried = tried_.find(robot);
      if (options_.decline_refuted && tried != tried_.end() &&
          (tried->second.optimized - by_map).norm() <= options_.refuted_within_m &&
          (tried->second.estimate - by_estimate).norm() <= options_.realign_threshold_m) {
        ++declined_;
        continue;
      }
      const Eigen::Vector3d by_kept =
          (known->second.T_global_robot * poses[first->second.second]).translation();
      candidates.push_back({i,
                            {by_estimate, by_map},
                            (by_estimate - by_kept).norm() > options_.realign_threshold_m});
      continue;
    }
    take[i] = true;
  }

  // The candidates the estimate gives new frames are re-aligned together, and only where, in
  // those frames, the inter-robot loop closures of theirs that fit weigh at least
  // realign_fit_share of those that fit in their kept frames, every other robot in its kept frame.
  // A candidate whose frame stays (the optimization moved it away) is re-aligned.
  std::vector<bool> new_frame(robots.size(), false);
  for (const Candidate& c : candidates) new_frame[c.index] = c.new_frame;
  if (options_.realign_fit_share > 0.0 &&
      std::find(new_frame.begin(), new_frame.end(), true) != new_frame.end()) {
    std::vector<std::optional<Eigen::Isometry3d>> kept(robots.size()), moved(robots.size());
    for (size_t i = 0; i < robots.size(); ++i) {
      const auto known = aligned_.find(robots[i]);
      kept[i] = known != aligned_.end() ? std::optional(known->second.T_global_robot)
                                        : result.T_world_robot[i];
      moved[i] = new_frame[i] ? result.T_world_robot[i] : kept[i];
    }
    const auto fits = [&](const std::vector<std::optional<Eigen::Isometry3d>>& frames) {
      return fittingSupport(edges, edge_support, robot_of, poses, frames, new_frame,
                            options_.realign_fit_m);
    };
    if (fits(moved) < options_.realign_fit_share * fits(kept)) {
      const auto unfit = std::remove_if(candidates.begin(), candidates.end(),
                                        [](const Candidate& c) { return c.new_frame; });
      unfit_ += static_cast<size_t>(candidates.end() - unfit);
      candidates.erase(unfit, candidates.end());
    }
  }
  for (const Candidate& c : candidates) {
    ++realignments_;
    tried_[robots[c.index]] = c.tried;
    take[c.index] = true;
  }

  for (size_t i = 0; i < robots.size(); ++i) {
    if (!take[i]) continue;
    RobotFrameAlignment& alignment = aligned_[robots[i]];
    alignment.T_global_robot = *result.T_world_robot[i];
    for (const RobotPairAlignment& pair : result.pairs) {
      if (pair.in_tree && (pair.robot_a == i || pair.robot_b == i) && i != 0)
        alignment.inliers = std::max(alignment.inliers, pair.inliers);
    }
  }
  return aligned_;
}

}  // namespace hydra_multi
