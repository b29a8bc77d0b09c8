#include "hydra_multi/backend/reconciliation.h"

#include <algorithm>
#include <set>
#include <tuple>

#include "hydra_multi/core/nearest_neighbors.h"

namespace hydra_multi {
namespace {

struct Item {
  NodeId id;
  RobotId robot;
  Eigen::Vector3d position;  // global frame
  const Node* node;
};

// Pairs of items of different robots that `match`, nearest first, each item in one pair at most.
template <typename Match>
std::vector<MergeCandidate> pairUp(const std::vector<Item>& items, Layer layer, double reach,
                                   Match match) {
  std::vector<Eigen::Vector3d> positions;
  for (const Item& item : items) positions.push_back(item.position);
  const NearestNeighbors index(positions);
  std::vector<std::tuple<double, size_t, size_t>> pairs;
  for (size_t i = 0; i < items.size(); ++i) {
    for (const auto& near : index.withinRadius(items[i].position, reach)) {
      const size_t j = near.index;
      if (j <= i || items[i].robot == items[j].robot) continue;
      const double d = (items[i].position - items[j].position).norm();
      if (match(items[i], items[j])) pairs.emplace_back(d, i, j);
    }
  }
  std::sort(pairs.begin(), pairs.end());
  std::set<size_t> used;
  std::vector<MergeCandidate> candidates;
  for (const auto& [d, i, j] : pairs) {
    if (used.count(i) || used.count(j)) continue;
    used.insert(i);
    used.insert(j);
    // The robot with the lower index keeps its node.
    const bool i_first = items[i].robot < items[j].robot;
    candidates.push_back(
        {i_first ? items[i].id : items[j].id, i_first ? items[j].id : items[i].id, layer});
  }
  return candidates;
}

}  // namespace

std::vector<MergeCandidate> proposeMerges(
    const SceneGraph& frontend, const std::map<RobotId, Eigen::Isometry3d>& T_global_robot,
    const ReconciliationOptions& options) {
  std::vector<Item> places, objects;
  for (const auto& [robot, T] : T_global_robot) {
    for (const NodeId id : frontend.nodesOfRobot(robot)) {
      const Node& node = frontend.getNode(id);
      if (node.layer() == Layer::kPlaces) places.push_back({id, robot, T * node.position, &node});
      if (node.layer() == Layer::kObjects) objects.push_back({id, robot, T * node.position, &node});
    }
  }
  std::vector<MergeCandidate> candidates =
      pairUp(places, Layer::kPlaces, options.place_max_distance, [&](const Item& a, const Item& b) {
        return std::abs(a.node->find<PlaceAttributes>()->distance -
                        b.node->find<PlaceAttributes>()->distance) <=
               options.place_max_radius_difference;
      });
  // Objects: same label, and either (aligned) box holds the other's centre.
  const auto halfExtents = [&](const Item& item) -> Eigen::Vector3d {
    const auto& box = item.node->semantic()->bounding_box;
    if (!box) return Eigen::Vector3d::Zero();
    const Eigen::Matrix3d R = T_global_robot.at(item.robot).linear();
    return R.cwiseAbs() * (0.5 * (box->max - box->min));
  };
  const auto inside = [](const Eigen::Vector3d& p, const Eigen::Vector3d& centre,
                         const Eigen::Vector3d& half) {
    return ((p - centre).cwiseAbs().array() <= half.array()).all();
  };
  const auto objects_match = [&](const Item& a, const Item& b) {
    if (a.node->semantic()->label != b.node->semantic()->label) return false;
    return inside(b.position, a.position, halfExtents(a)) ||
           inside(a.position, b.position, halfExtents(b));
  };
  for (MergeCandidate c : pairUp(objects, Layer::kObjects, 5.0, objects_match))
    candidates.push_back(c);
  return candidates;
}

std::vector<PoseGraphEdge> mergeFactors(const std::vector<MergeCandidate>& candidates,
                                        const std::map<RobotId, Eigen::Isometry3d>& T_global_robot,
                                        const ReconciliationOptions& options) {
  std::vector<PoseGraphEdge> factors;
  for (const MergeCandidate& c : candidates) {
    const auto ra = c.target.sourceRobot(), rb = c.source.sourceRobot();
    if (!ra || !rb || !T_global_robot.count(*ra) || !T_global_robot.count(*rb)) continue;
    PoseGraphEdge e;
    e.from = c.target;
    e.to = c.source;
    e.kind = PoseGraphEdge::Kind::kLoopClosure;
    e.T_from_to = Eigen::Isometry3d::Identity();
    e.T_from_to.linear() =
        T_global_robot.at(*ra).linear().transpose() * T_global_robot.at(*rb).linear();
    e.information = informationFromVariances(options.merge_variance, options.merge_variance);
    factors.push_back(e);
  }
  return factors;
}

}  // namespace hydra_multi
