#include "hydra_multi/backend/reconciliation.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <set>
#include <tuple>

#include "hydra_multi/core/nearest_neighbors.h"
#include "hydra_multi/core/parallel.h"
#include "hydra_multi/registration/icp.h"

namespace hydra_multi {
namespace {

// How far apart two objects' centres may be for one's box to hold the other's (no furniture box
// is larger).
constexpr double kObjectReach = 5.0;

struct Item {
  NodeId id;
  RobotId robot;
  Eigen::Vector3d position;  // global frame
  const Node* node;
};

// Groups of items of different robots that `match`, joined nearest pair first, each group
// holding at most one item of each robot: three robots' copies of one place make one group, not
// one pair and a copy left over. Each group merges into its item of the lowest robot index.
// Items whose `kind` differs never match (objects of two labels): each kind is searched in an
// index of its own, which finds the same pairs as one index of all items.
template <typename Kind, typename Match>
std::vector<MergeCandidate> groupUp(const std::vector<Item>& items, Layer layer, double reach,
                                    Kind kind, Match match) {
  std::map<uint32_t, std::vector<size_t>> kinds;
  for (size_t i = 0; i < items.size(); ++i) kinds[kind(items[i])].push_back(i);
  std::vector<std::tuple<double, size_t, size_t>> pairs;
  for (const auto& [k, members] : kinds) {
    std::vector<Eigen::Vector3d> positions;
    positions.reserve(members.size());
    for (const size_t i : members) positions.push_back(items[i].position);
    const NearestNeighbors index(positions);
    for (const size_t i : members) {
      for (const auto& near : index.withinRadius(items[i].position, reach)) {
        const size_t j = members[near.index];
        if (j <= i || items[i].robot == items[j].robot) continue;
        const double d = (items[i].position - items[j].position).norm();
        if (match(items[i], items[j])) pairs.emplace_back(d, i, j);
      }
    }
  }
  std::sort(pairs.begin(), pairs.end());
  // Union-find over the items; each root knows its group's robots (empty for an item no pair
  // has named yet, which is its own root).
  std::vector<size_t> parent(items.size());
  for (size_t i = 0; i < items.size(); ++i) parent[i] = i;
  std::vector<std::set<RobotId>> robots(items.size());
  const auto root = [&parent](size_t i) {
    while (parent[i] != i) i = parent[i] = parent[parent[i]];
    return i;
  };
  for (const auto& [d, i, j] : pairs) {
    const size_t a = root(i), b = root(j);
    if (robots[a].empty()) robots[a] = {items[a].robot};
    if (robots[b].empty()) robots[b] = {items[b].robot};
    if (a == b) continue;
    if (std::any_of(robots[b].begin(), robots[b].end(),
                    [&](RobotId r) { return robots[a].count(r) != 0; }))
      continue;
    parent[b] = a;
    robots[a].insert(robots[b].begin(), robots[b].end());
  }
  // Each group's members, in item order; the member of the lowest robot index is the target.
  std::map<size_t, std::vector<size_t>> groups;
  for (size_t i = 0; i < items.size(); ++i) {
    if (parent[i] != i || !robots[i].empty()) groups[root(i)].push_back(i);
  }
  std::vector<MergeCandidate> candidates;
  for (const auto& [group, members] : groups) {
    if (members.size() < 2) continue;
    const size_t target =
        *std::min_element(members.begin(), members.end(),
                          [&](size_t a, size_t b) { return items[a].robot < items[b].robot; });
    for (const size_t m : members) {
      if (m != target) candidates.push_back({items[target].id, items[m].id, layer, {}});
    }
  }
  return candidates;
}

}  // namespace

Eigen::Vector3d globalPosition(NodeId id, const Eigen::Vector3d& aligned,
                               const std::map<NodeId, Eigen::Vector3d>* optimized) {
  if (optimized == nullptr) return aligned;
  const auto it = optimized->find(id);
  return it == optimized->end() ? aligned : it->second;
}

std::vector<MergeCandidate> proposeMerges(
    const SceneGraph& frontend, const std::map<RobotId, Eigen::Isometry3d>& T_global_robot,
    const ReconciliationOptions& options, const std::map<NodeId, Eigen::Vector3d>* optimized,
    std::optional<Layer> only) {
  std::vector<Item> places, objects;
  const bool want_places = !only || *only == Layer::kPlaces;
  const bool want_objects = !only || *only == Layer::kObjects;
  for (const auto& [robot, T] : T_global_robot) {
    for (const Node* robot_node : frontend.robotNodes(robot)) {
      const Node& node = *robot_node;
      const bool place = node.layer() == Layer::kPlaces, object = node.layer() == Layer::kObjects;
      if (!(place && want_places) && !(object && want_objects)) continue;
      const NodeId id = node.id;
      const Eigen::Vector3d p = globalPosition(id, T * node.position, optimized);
      (place ? places : objects).push_back({id, robot, p, &node});
    }
  }
  const auto one_kind = [](const Item&) { return 0u; };
  std::vector<MergeCandidate> candidates =
      groupUp(places, Layer::kPlaces, options.place_max_distance, one_kind,
              [&](const Item& a, const Item& b) {
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
  const auto label = [](const Item& item) { return item.node->semantic()->label; };
  for (MergeCandidate c : groupUp(objects, Layer::kObjects, kObjectReach, label, objects_match))
    candidates.push_back(c);
  return candidates;
}

std::vector<MergeCandidate> refineObjectMerges(
    std::vector<MergeCandidate> candidates, const SceneGraph& frontend,
    const std::map<RobotId, Eigen::Isometry3d>& T_global_robot,
    const std::map<RobotId, const Mesh*>& meshes, const ReconciliationOptions& options,
    const std::map<NodeId, Eigen::Isometry3d>* moved, IcpCache* cache) {
  if (!options.object_icp) return candidates;
  // An object's vertices and its node pose (at its centre, turned as its robot's frame), global
  // frame, moved as the solve moved it; `key` sums its vertices in its robot's frame.
  const auto object = [&](NodeId id, std::vector<Eigen::Vector3d>& points, Eigen::Isometry3d& pose,
                          double& key) {
    const Node* node = frontend.findNode(id);
    const auto robot = id.sourceRobot();
    if (!node || !robot || !T_global_robot.count(*robot)) return false;
    Eigen::Isometry3d M = Eigen::Isometry3d::Identity();
    if (moved != nullptr) {
      if (const auto it = moved->find(id); it != moved->end()) M = it->second;
    }
    const Eigen::Isometry3d T = M * T_global_robot.at(*robot);
    pose = T;
    pose.translation() = T * node->position;
    key = node->position.sum();
    const auto mesh = meshes.find(*robot);
    const ObjectAttributes* attributes = node->find<ObjectAttributes>();
    if (mesh == meshes.end() || mesh->second == nullptr || attributes == nullptr) return true;
    for (const uint64_t v : attributes->mesh_vertices) {
      if (v >= mesh->second->vertices.size()) continue;
      const Eigen::Vector3d p = mesh->second->vertices[v].position.cast<double>();
      points.push_back(T * p);
      key += p.sum() * 1e-3 + 1.0;
    }
    return true;
  };
  // The candidates in order: passed as they are (no ICP), their cached verdict reused, or an ICP
  // to run (`fits`, on icp_threads threads; each fit depends on its pair alone).
  struct Fit {
    std::vector<Eigen::Vector3d> target, source;
    Eigen::Isometry3d X_target, X_source;
    IcpCache::Entry entry;
  };
  std::vector<Fit> fits;
  std::vector<const IcpCache::Entry*> reuse(candidates.size(), nullptr);
  std::vector<long> fit_of(candidates.size(), -1);
  for (size_t i = 0; i < candidates.size(); ++i) {
    const MergeCandidate& c = candidates[i];
    Fit fit{{}, {}, Eigen::Isometry3d::Identity(), Eigen::Isometry3d::Identity(), {}};
    double target_key = 0.0, source_key = 0.0;
    if (c.layer != Layer::kObjects || !object(c.target, fit.target, fit.X_target, target_key) ||
        !object(c.source, fit.source, fit.X_source, source_key) ||
        fit.target.size() < options.icp_min_vertices ||
        fit.source.size() < options.icp_min_vertices)
      continue;
    // Not kept, or kept as the plain factor, unless ICP measures it.
    fit.entry = {target_key, source_key, fit.X_target.inverse() * fit.X_source, false,
                 c.T_target_source};
    if (cache != nullptr) {
      const auto it = cache->entries.find({c.target, c.source});
      const IcpCache::Entry* last = it == cache->entries.end() ? nullptr : &it->second;
      if (last != nullptr && last->target_key == target_key && last->source_key == source_key) {
        const Eigen::Isometry3d delta = last->relative.inverse() * fit.entry.relative;
        if (delta.translation().norm() < options.icp_reuse_m &&
            Eigen::AngleAxisd(delta.linear()).angle() < options.icp_reuse_rad) {
          reuse[i] = last;
          continue;
        }
      }
    }
    fit_of[i] = static_cast<long>(fits.size());
    fits.push_back(std::move(fit));
  }
  // A fit's verdict: kept, with the ICP measurement as T_target_source, or not.
  const auto verdict = [&options](Fit& fit) {
    const auto found = icp(fit.source, fit.target);
    if (!found) return;
    // How far ICP moves the source object and how much it turns it (T's translation alone is
    // the motion of the global origin: metres for a slight turn of an object far from it).
    Eigen::Vector3d centroid = Eigen::Vector3d::Zero();
    for (const Eigen::Vector3d& p : fit.source) centroid += p;
    centroid /= static_cast<double>(fit.source.size());
    const Eigen::Isometry3d& T = found.value().T_target_source;
    const double shift = (T * centroid - centroid).norm();
    const double turn_deg = Eigen::AngleAxisd(T.linear()).angle() * 180.0 / M_PI;
    if (shift > options.icp_max_shift_m) return;
    // A wrong fit (the robots are aligned), not a sign of two objects: the plain factor.
    fit.entry.kept = true;
    if (turn_deg > options.icp_max_rotation_deg) return;
    if (double(found.value().inliers.size()) <
            options.icp_min_paired_share * double(fit.source.size()) ||
        found.value().rmse > options.icp_max_rmse_m) {
      fit.entry.kept = false;
      return;
    }
    fit.entry.T_target_source = fit.X_target.inverse() * T * fit.X_source;
  };
  const size_t threads =
      std::max<size_t>(1, std::min<size_t>(static_cast<size_t>(options.icp_threads), fits.size()));
  runOnThreads(threads, [&](size_t t) {
    for (size_t f = t; f < fits.size(); f += threads) verdict(fits[f]);
  });

  std::map<std::pair<NodeId, NodeId>, IcpCache::Entry> checked;
  size_t reused = 0;
  std::vector<MergeCandidate> kept;
  for (size_t i = 0; i < candidates.size(); ++i) {
    MergeCandidate& c = candidates[i];
    const IcpCache::Entry* entry = reuse[i];
    if (entry != nullptr) {
      ++reused;
    } else if (fit_of[i] >= 0) {
      entry = &fits[static_cast<size_t>(fit_of[i])].entry;
    } else {
      kept.push_back(std::move(c));
      continue;
    }
    checked[{c.target, c.source}] = *entry;
    if (!entry->kept) continue;
    c.T_target_source = entry->T_target_source;
    kept.push_back(std::move(c));
  }
  if (cache != nullptr) {
    cache->entries = std::move(checked);
    cache->reused = reused;
    cache->computed = cache->entries.size() - reused;
  }
  return kept;
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
    if (c.T_target_source) e.T_from_to = *c.T_target_source;
    // A place has no orientation, so its merge factor holds the positions only; an object's holds
    // its rotation too where ICP measured it.
    e.information = informationFromVariances(
        options.merge_variance,
        c.T_target_source ? options.merge_variance : options.unmeasured_rotation_variance);
    factors.push_back(e);
  }
  return factors;
}

namespace {

struct Voted {
  NodeId id;
  uint32_t label = 0;
  Eigen::Vector3d position;
  const BoundingBox* box = nullptr;
  std::vector<Eigen::Vector3d> vertices;
  std::set<RobotId> robots;
};

// A share label_min_shared_vertices of the smaller vertex set lies within
// label_vertex_distance_m of the other's: one surface.
bool shareTheirSurface(const Voted& a, const Voted& b, const ReconciliationOptions& options) {
  const Voted& small = a.vertices.size() <= b.vertices.size() ? a : b;
  const Voted& large = &small == &a ? b : a;
  const NearestNeighbors index(large.vertices);
  size_t shared = 0;
  for (const Eigen::Vector3d& v : small.vertices) {
    const auto nearest = index.nearest(v);
    shared += !nearest.empty() &&
              (large.vertices[nearest.front().index] - v).norm() <= options.label_vertex_distance_m;
  }
  return double(shared) >= options.label_min_shared_vertices * double(small.vertices.size());
}

}  // namespace

std::vector<LabelDispute> resolveLabelDisputes(const SceneGraph& graph,
                                               const std::map<NodeId, std::set<RobotId>>& voters,
                                               const ReconciliationOptions& options) {
  std::vector<Voted> objects;
  std::map<uint32_t, size_t> label_count;
  for (const auto& [id, node] : graph.nodes()) {
    const ObjectAttributes* object = node.find<ObjectAttributes>();
    if (object == nullptr) continue;
    ++label_count[object->semantic.label];
    const auto robot = id.sourceRobot();
    if (!object->semantic.bounding_box || !robot) continue;
    Voted v{id, object->semantic.label, node.position, &*object->semantic.bounding_box, {}, {}};
    for (const uint64_t i : object->mesh_vertices) {
      if (i < graph.mesh().vertices.size())
        v.vertices.push_back(graph.mesh().vertices[i].position.cast<double>());
    }
    if (v.vertices.size() < options.icp_min_vertices) continue;
    const auto given = voters.find(id);
    v.robots = given == voters.end() ? std::set<RobotId>{*robot} : given->second;
    objects.push_back(std::move(v));
  }
  std::vector<Eigen::Vector3d> positions;
  for (const Voted& v : objects) positions.push_back(v.position);
  const NearestNeighbors index(positions);
  const double vote = std::log((1.0 - options.label_confusion) / options.label_confusion);
  // log odds of a's label over b's
  const auto logOdds = [&](const Voted& a, const Voted& b) {
    return std::log(double(label_count[a.label] + 1) / double(label_count[b.label] + 1)) +
           (double(a.robots.size()) - double(b.robots.size())) * vote;
  };
  std::vector<std::tuple<double, size_t, size_t>> disputes;  // distance, winner, loser
  for (size_t i = 0; i < objects.size(); ++i) {
    const Voted& a = objects[i];
    for (const auto& near : index.withinRadius(a.position, kObjectReach)) {
      const size_t j = near.index;
      const Voted& b = objects[j];
      if (j <= i || a.label == b.label) continue;
      if (std::any_of(a.robots.begin(), a.robots.end(),
                      [&](RobotId r) { return b.robots.count(r) != 0; }))
        continue;
      if (!a.box->contains(b.position) && !b.box->contains(a.position)) continue;
      const double odds = logOdds(a, b);
      if (std::abs(odds) < std::log(options.label_min_odds)) continue;
      if (!shareTheirSurface(a, b, options)) continue;
      disputes.emplace_back((a.position - b.position).norm(), odds > 0 ? i : j, odds > 0 ? j : i);
    }
  }
  std::sort(disputes.begin(), disputes.end());
  std::vector<LabelDispute> resolved;
  std::set<size_t> taken;
  for (const auto& [distance, winner, loser] : disputes) {
    if (taken.count(winner) || taken.count(loser)) continue;
    taken.insert({winner, loser});
    resolved.push_back({objects[winner].id, objects[loser].id,
                        std::exp(logOdds(objects[winner], objects[loser]))});
  }
  return resolved;
}

}  // namespace hydra_multi
