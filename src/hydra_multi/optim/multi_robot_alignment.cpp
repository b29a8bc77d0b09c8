#include "hydra_multi/optim/multi_robot_alignment.h"

#include <algorithm>
#include <deque>
#include <numeric>
#include <optional>
#include <set>

#include "hydra_multi/core/parallel.h"

namespace hydra_multi {

size_t MultiRobotAlignment::numAligned() const {
  return static_cast<size_t>(std::count_if(T_world_robot.begin(), T_world_robot.end(),
                                           [](const auto& T) { return T.has_value(); }));
}

MultiRobotAlignment alignRobotFrames(
    size_t num_robots, const std::map<NodeId, Eigen::Isometry3d>& local_poses,
    const std::unordered_map<NodeId, size_t>& robot_of,
    const std::vector<PoseGraphEdge>& inter_robot_edges, size_t root,
    const MultiRobotAlignmentOptions& options, const std::vector<double>& edge_support,
    std::map<std::pair<size_t, size_t>, ConsensusCache>* consensus) {
  MultiRobotAlignment result;
  result.T_world_robot.resize(num_robots);
  result.edge_inlier.assign(inter_robot_edges.size(), false);

  // eq. (1): one estimate of T_a_b per loop closure, grouped by pair (a < b).
  struct PairEstimates {
    std::vector<Eigen::Isometry3d> estimates;
    std::vector<size_t> edges;
    std::vector<double> support;
  };
  std::map<std::pair<size_t, size_t>, PairEstimates> by_pair;
  for (size_t k = 0; k < inter_robot_edges.size(); ++k) {
    const PoseGraphEdge& e = inter_robot_edges[k];
    const auto from = robot_of.find(e.from), to = robot_of.find(e.to);
    const auto T_from = local_poses.find(e.from), T_to = local_poses.find(e.to);
    if (from == robot_of.end() || to == robot_of.end() || T_from == local_poses.end() ||
        T_to == local_poses.end() || from->second == to->second) {
      continue;
    }
    // T_A_B = T_A_from * Z_from_to * T_B_to^-1, with A the robot of `from`.
    Eigen::Isometry3d T_A_B = T_from->second * e.T_from_to * T_to->second.inverse();
    size_t a = from->second, b = to->second;
    if (a > b) {
      std::swap(a, b);
      T_A_B = T_A_B.inverse();
    }
    PairEstimates& pair = by_pair[{a, b}];
    pair.estimates.push_back(T_A_B);
    pair.edges.push_back(k);
    pair.support.push_back(k < edge_support.size() ? edge_support[k] : 1.0);
  }
  // eq. (2) per pair, the pairs with the most estimates first, shared out over the threads in
  // turn; each pair's consensus cache made before (the map is not touched on the threads).
  std::vector<const PairEstimates*> pairs;
  std::vector<ConsensusCache*> caches;
  for (const auto& [key, pair] : by_pair) {
    pairs.push_back(&pair);
    caches.push_back(consensus != nullptr ? &(*consensus)[key] : nullptr);
  }
  std::vector<size_t> largest_first(pairs.size());
  std::iota(largest_first.begin(), largest_first.end(), size_t{0});
  std::stable_sort(largest_first.begin(), largest_first.end(), [&pairs](size_t x, size_t y) {
    return pairs[x]->estimates.size() > pairs[y]->estimates.size();
  });
  std::vector<std::optional<Result<PoseAverage>>> averages(pairs.size());
  const size_t threads = std::max<size_t>(1, std::min(options.threads, pairs.size()));
  runOnThreads(threads, [&](size_t t) {
    for (size_t i = t; i < largest_first.size(); i += threads) {
      const size_t p = largest_first[i];
      averages[p] =
          robustPoseAverage(pairs[p]->estimates, options.averaging, pairs[p]->support, caches[p]);
    }
  });
  size_t index = 0;
  for (const auto& [key, pair] : by_pair) {
    const Result<PoseAverage>& average = *averages[index++];
    if (!average) continue;
    RobotPairAlignment alignment;
    alignment.robot_a = key.first;
    alignment.robot_b = key.second;
    alignment.T_a_b = average.value().T;
    alignment.loop_closures = pair.estimates.size();
    std::set<std::pair<NodeId, NodeId>> keyframe_pairs;  // of the inliers
    for (size_t i = 0; i < pair.edges.size(); ++i) {
      result.edge_inlier[pair.edges[i]] = average.value().inliers[i];
      const PoseGraphEdge& e = inter_robot_edges[pair.edges[i]];
      if (average.value().inliers[i]) keyframe_pairs.insert(std::minmax(e.from, e.to));
    }
    alignment.inliers = keyframe_pairs.size();
    result.pairs.push_back(alignment);
  }
  // Maximum spanning tree by inlier count (Kruskal), over pairs with at least k inliers.
  std::vector<size_t> order(result.pairs.size());
  for (size_t i = 0; i < order.size(); ++i) order[i] = i;
  std::sort(order.begin(), order.end(),
            [&](size_t x, size_t y) { return result.pairs[x].inliers > result.pairs[y].inliers; });
  std::vector<size_t> component(num_robots);
  for (size_t r = 0; r < num_robots; ++r) component[r] = r;
  const auto find = [&](size_t r) {
    while (component[r] != r) r = component[r] = component[component[r]];
    return r;
  };
  for (const size_t p : order) {
    RobotPairAlignment& pair = result.pairs[p];
    if (pair.inliers < options.min_inliers) continue;
    const size_t ra = find(pair.robot_a), rb = find(pair.robot_b);
    if (ra == rb) continue;
    component[ra] = rb;
    pair.in_tree = true;
  }
  // Chain along the tree from the root.
  if (root < num_robots) {
    result.T_world_robot[root] = Eigen::Isometry3d::Identity();
    std::deque<size_t> queue = {root};
    while (!queue.empty()) {
      const size_t current = queue.front();
      queue.pop_front();
      for (const RobotPairAlignment& pair : result.pairs) {
        if (!pair.in_tree) continue;
        if (pair.robot_a == current && !result.T_world_robot[pair.robot_b]) {
          result.T_world_robot[pair.robot_b] = *result.T_world_robot[current] * pair.T_a_b;
          queue.push_back(pair.robot_b);
        } else if (pair.robot_b == current && !result.T_world_robot[pair.robot_a]) {
          result.T_world_robot[pair.robot_a] =
              *result.T_world_robot[current] * pair.T_a_b.inverse();
          queue.push_back(pair.robot_a);
        }
      }
    }
  }
  return result;
}

}  // namespace hydra_multi
