// Reconciliation proposals: which places and objects of two aligned robots look like one node.

#include <gtest/gtest.h>

#include <algorithm>
#include <random>
#include <set>
#include <tuple>

#include "hydra_multi/backend/reconciliation.h"
#include "support/object_shapes.h"

namespace hydra_multi {
namespace {

const RobotId kA(0), kB(1);

void place(SceneGraph& g, RobotId robot, uint64_t index, const Eigen::Vector3d& p, double radius) {
  Node node = makeNode(NodeId::station('p', robot, index), Layer::kPlaces, p);
  node.find<PlaceAttributes>()->distance = radius;
  g.addOrUpdateNode(node);
}

void object(SceneGraph& g, RobotId robot, uint64_t index, const Eigen::Vector3d& p, uint32_t label,
            double half) {
  Node node = makeNode(NodeId::station('O', robot, index), Layer::kObjects, p);
  node.semantic()->label = label;
  node.semantic()->bounding_box = BoundingBox{p.array() - half, p.array() + half};
  g.addOrUpdateNode(node);
}

// Robot b's frame is robot a's moved 10 m along x: b's nodes at x - 10 are at x globally.
TEST(Reconciliation, ProposesOverlappingPlacesAndObjects) {
  SceneGraph g;
  place(g, kA, 0, {1, 1, 1}, 1.0);
  place(g, kB, 0, {1.2 - 10, 1, 1}, 1.1);  // 0.2 m away, similar radius: a candidate
  place(g, kA, 1, {5, 1, 1}, 1.0);
  place(g, kB, 1, {5.3 - 10, 1, 1}, 0.5);  // radii too different
  place(g, kB, 2, {8 - 10, 1, 1}, 1.0);    // too far from anything
  object(g, kA, 0, {3, 3, 0.5}, 6, 0.5);
  object(g, kB, 0, {3.3 - 10, 3.2, 0.5}, 6, 0.5);  // same label, boxes overlap
  object(g, kB, 1, {3.1 - 10, 2.9, 0.5}, 7, 0.5);  // another label
  object(g, kA, 1, {9, 9, 0.5}, 6, 0.3);
  object(g, kB, 2, {9.8 - 10, 9, 0.5}, 6, 0.3);  // same label, boxes apart
  Eigen::Isometry3d T_b = Eigen::Isometry3d::Identity();
  T_b.translation().x() = 10.0;
  const std::map<RobotId, Eigen::Isometry3d> T = {{kA, Eigen::Isometry3d::Identity()}, {kB, T_b}};
  const auto candidates = proposeMerges(g, T);
  ASSERT_EQ(candidates.size(), 2u);
  EXPECT_EQ(candidates[0].layer, Layer::kPlaces);
  EXPECT_EQ(candidates[0].target, NodeId::station('p', kA, 0));
  EXPECT_EQ(candidates[0].source, NodeId::station('p', kB, 0));
  EXPECT_EQ(candidates[1].layer, Layer::kObjects);
  EXPECT_EQ(candidates[1].target, NodeId::station('O', kA, 0));
  EXPECT_EQ(candidates[1].source, NodeId::station('O', kB, 0));
  // A robot that is not aligned proposes nothing.
  EXPECT_TRUE(proposeMerges(g, {{kA, Eigen::Isometry3d::Identity()}}).empty());
  // The factors: zero translation, the rotation between the two robots' frames.
  Eigen::Isometry3d turned = T_b;
  turned.linear() = Eigen::AngleAxisd(0.5, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  const auto factors =
      mergeFactors(candidates, {{kA, Eigen::Isometry3d::Identity()}, {kB, turned}});
  ASSERT_EQ(factors.size(), 2u);
  EXPECT_EQ(factors[0].kind, PoseGraphEdge::Kind::kLoopClosure);
  EXPECT_LT(factors[0].T_from_to.translation().norm(), 1e-12);
  EXPECT_NEAR(Eigen::AngleAxisd(factors[0].T_from_to.linear()).angle(), 0.5, 1e-12);
}

// Three robots' copies of one place and of one object make one group each: both other copies
// merge into robot a's (as pairs, each node in one pair at most, the third copy was left over).
// A group holds one node per robot: robot c's second place beside the first stays out.
TEST(Reconciliation, ThreeRobotsCopiesMergeIntoOne) {
  const RobotId kC(2);
  SceneGraph g;
  place(g, kA, 0, {1, 1, 1}, 1.0);
  place(g, kB, 0, {1.1, 1, 1}, 1.0);
  place(g, kC, 0, {1.2, 1.1, 1}, 1.0);
  place(g, kC, 1, {1.05, 0.95, 1}, 1.0);
  object(g, kB, 0, {3, 3, 0.5}, 6, 0.5);
  object(g, kC, 0, {3.2, 3, 0.5}, 6, 0.5);
  object(g, kA, 0, {3.1, 3.1, 0.5}, 6, 0.5);
  const std::map<RobotId, Eigen::Isometry3d> T = {{kA, Eigen::Isometry3d::Identity()},
                                                  {kB, Eigen::Isometry3d::Identity()},
                                                  {kC, Eigen::Isometry3d::Identity()}};
  const auto candidates = proposeMerges(g, T);
  std::set<std::pair<NodeId, NodeId>> got;
  for (const MergeCandidate& c : candidates) got.insert({c.target, c.source});
  const std::set<std::pair<NodeId, NodeId>> expected = {
      {NodeId::station('p', kA, 0), NodeId::station('p', kB, 0)},
      {NodeId::station('p', kA, 0), NodeId::station('p', kC, 1)},
      {NodeId::station('O', kA, 0), NodeId::station('O', kB, 0)},
      {NodeId::station('O', kA, 0), NodeId::station('O', kC, 0)}};
  EXPECT_EQ(got, expected);

  // One layer alone: the places' candidates first in the full list, then the objects'.
  const auto places = proposeMerges(g, T, {}, nullptr, Layer::kPlaces);
  const auto objects = proposeMerges(g, T, {}, nullptr, Layer::kObjects);
  ASSERT_EQ(places.size() + objects.size(), candidates.size());
  for (size_t i = 0; i < candidates.size(); ++i) {
    const MergeCandidate& one = i < places.size() ? places[i] : objects[i - places.size()];
    EXPECT_EQ(one.layer, i < places.size() ? Layer::kPlaces : Layer::kObjects);
    EXPECT_EQ(one.target, candidates[i].target);
    EXPECT_EQ(one.source, candidates[i].source);
  }
}

// A crowd of four robots' places and objects of three labels, close enough that most nodes have
// several candidates: the groups proposeMerges makes are those of every pair tested by brute force
// (the rules above: different robots, places within 0.3 m and 0.3 m of radius, objects of one label
// with a centre in the other's box, nearest pair joined first, one node per robot per group).
TEST(Reconciliation, TheGroupsAreThoseOfEveryPairTestedByBruteForce) {
  struct Item {
    NodeId id;
    RobotId robot;
    Eigen::Vector3d p;
    double radius = 0.0;  // a place's
    uint32_t label = 0;   // an object's
    double half = 0.0;
  };
  std::mt19937 random(5);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  SceneGraph g;
  std::vector<Item> places, objects;
  std::map<RobotId, Eigen::Isometry3d> T;
  for (int r = 0; r < 4; ++r) {
    const RobotId robot(r);
    T[robot] = Eigen::Isometry3d::Identity();
    for (uint64_t k = 0; k < 60; ++k) {
      const Eigen::Vector3d p(3.0 * unit(random), 3.0 * unit(random), 0.5 * unit(random));
      places.push_back({NodeId::station('p', robot, k), robot, p, 0.5 + 0.4 * unit(random)});
      place(g, robot, k, p, places.back().radius);
    }
    for (uint64_t k = 0; k < 40; ++k) {
      const Eigen::Vector3d p(6.0 * unit(random), 6.0 * unit(random), 0.5);
      const uint32_t label = 1 + static_cast<uint32_t>(3.0 * unit(random));
      objects.push_back(
          {NodeId::station('O', robot, k), robot, p, 0.0, label, 0.2 + 0.6 * unit(random)});
      object(g, robot, k, p, label, objects.back().half);
    }
  }
  // The groups by brute force: every pair, nearest first, into robot-disjoint groups.
  const auto groups = [](const std::vector<Item>& items, auto match) {
    std::vector<std::tuple<double, size_t, size_t>> pairs;
    for (size_t i = 0; i < items.size(); ++i) {
      for (size_t j = i + 1; j < items.size(); ++j) {
        if (items[i].robot != items[j].robot && match(items[i], items[j]))
          pairs.emplace_back((items[i].p - items[j].p).norm(), i, j);
      }
    }
    std::sort(pairs.begin(), pairs.end());
    std::vector<std::set<size_t>> group(items.size());
    std::vector<size_t> of(items.size());
    for (size_t i = 0; i < items.size(); ++i) group[of[i] = i] = {i};
    const auto hasRobotOf = [&](const std::set<size_t>& a, const std::set<size_t>& b) {
      for (const size_t x : a) {
        for (const size_t y : b) {
          if (items[x].robot == items[y].robot) return true;
        }
      }
      return false;
    };
    for (const auto& [d, i, j] : pairs) {
      const size_t a = of[i], b = of[j];
      if (a == b || hasRobotOf(group[a], group[b])) continue;
      for (const size_t m : group[b]) of[m] = a;
      group[a].insert(group[b].begin(), group[b].end());
      group[b].clear();
    }
    std::set<std::pair<NodeId, NodeId>> merges;
    for (const std::set<size_t>& members : group) {
      if (members.size() < 2) continue;
      const size_t target =
          *std::min_element(members.begin(), members.end(),
                            [&](size_t x, size_t y) { return items[x].robot < items[y].robot; });
      for (const size_t m : members) {
        if (m != target) merges.insert({items[target].id, items[m].id});
      }
    }
    return merges;
  };
  std::set<std::pair<NodeId, NodeId>> expected = groups(places, [](const Item& a, const Item& b) {
    return (a.p - b.p).norm() <= 0.3 && std::abs(a.radius - b.radius) <= 0.3;
  });
  const std::set<std::pair<NodeId, NodeId>> object_merges =
      groups(objects, [](const Item& a, const Item& b) {
        const Eigen::Vector3d d = (a.p - b.p).cwiseAbs();
        return a.label == b.label && ((d.array() <= a.half).all() || (d.array() <= b.half).all());
      });
  expected.insert(object_merges.begin(), object_merges.end());
  ASSERT_GT(object_merges.size(), 20u);
  ASSERT_GT(expected.size(), object_merges.size() + 40u);

  std::set<std::pair<NodeId, NodeId>> got;
  for (const MergeCandidate& c : proposeMerges(g, T)) got.insert({c.target, c.source});
  EXPECT_EQ(got, expected);
}

// An object with its vertices (moved by `pose` about its centre) in a robot's graph and mesh.
void meshedObject(SceneGraph& g, Mesh& mesh, RobotId robot, uint64_t index,
                  const Eigen::Isometry3d& pose, const Eigen::Vector3d& size) {
  object(g, robot, index, pose.translation(), 6, 0.5 * size.maxCoeff());
  Node node = g.getNode(NodeId::station('O', robot, index));
  for (const Eigen::Vector3d& p : testing::latticeBoxVertices(size)) {
    node.find<ObjectAttributes>()->mesh_vertices.push_back(mesh.vertices.size());
    MeshVertex v;
    v.position = (pose * p).cast<float>();
    mesh.vertices.push_back(v);
  }
  g.addOrUpdateNode(node);
}

// Object candidates 42 m from the origin, checked by ICP: a copy 0.2 m and 3 degrees off is
// kept with ICP's measurement (the check once took the motion of the origin, 2.4 m, for the
// object's: every such pair was dropped); a copy turned 35 degrees keeps the plain factor, without
// ICP's turn (the robots are aligned: a fit that needs so large a turn is wrong, not a sign of two
// objects).
TEST(Reconciliation, ObjectMergesCheckedByIcpFarFromTheOrigin) {
  const Eigen::Vector3d size(1.2, 0.6, 0.9);
  Eigen::Isometry3d at = Eigen::Isometry3d::Identity();
  at.translation() = Eigen::Vector3d(13.0, 40.0, 0.5);
  const auto turned = [&](double deg, const Eigen::Vector3d& shift) {
    Eigen::Isometry3d T = at;
    T.linear() = Eigen::AngleAxisd(deg * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    T.translation() += shift;
    return T;
  };
  const std::map<RobotId, Eigen::Isometry3d> T = {{kA, Eigen::Isometry3d::Identity()},
                                                  {kB, Eigen::Isometry3d::Identity()}};
  for (const double deg : {3.0, 35.0}) {
    SCOPED_TRACE(deg);
    SceneGraph g;
    Mesh mesh_a, mesh_b;
    meshedObject(g, mesh_a, kA, 0, at, size);
    meshedObject(g, mesh_b, kB, 0, turned(deg, {0.15, -0.13, 0.0}), size);
    const auto candidates = proposeMerges(g, T);
    ASSERT_EQ(candidates.size(), 1u);
    const auto kept = refineObjectMerges(candidates, g, T, {{kA, &mesh_a}, {kB, &mesh_b}});
    ASSERT_EQ(kept.size(), 1u);
    if (deg > 20.0) {
      EXPECT_FALSE(kept[0].T_target_source.has_value());
      continue;
    }
    ASSERT_TRUE(kept[0].T_target_source.has_value());
    // Between the node poses (at the nodes' centres, the robots' rotation): the source's
    // centre is the target's, its vertices turned by deg.
    EXPECT_LT(kept[0].T_target_source->translation().norm(), 0.03);
    EXPECT_NEAR(Eigen::AngleAxisd(kept[0].T_target_source->linear()).angle(), deg * M_PI / 180.0,
                0.01);
  }
}

// Robot b's alignment is 30 degrees off in yaw (about the object) and a solve corrected it: the
// candidate is checked where the solve put b's object. Without the solve's motion the copies
// look 30 degrees apart and the pair keeps only the plain factor; with it ICP measures it, barely
// turned.
TEST(Reconciliation, ObjectMergesCheckedWhereTheSolveMovedThem) {
  const Eigen::Vector3d size(1.2, 0.6, 0.9);
  Eigen::Isometry3d at = Eigen::Isometry3d::Identity();
  at.translation() = Eigen::Vector3d(6.0, 3.0, 0.5);
  Eigen::Isometry3d yaw_error = Eigen::Isometry3d::Identity();
  yaw_error.linear() = Eigen::AngleAxisd(30.0 * M_PI / 180.0, Eigen::Vector3d::UnitZ()).matrix();
  yaw_error = at * yaw_error * at.inverse();  // about the object's centre
  SceneGraph g;
  Mesh mesh_a, mesh_b;
  meshedObject(g, mesh_a, kA, 0, at, size);
  meshedObject(g, mesh_b, kB, 0, at, size);  // robot b's frame is the global one
  const std::map<RobotId, Eigen::Isometry3d> T = {{kA, Eigen::Isometry3d::Identity()},
                                                  {kB, yaw_error}};
  const std::map<RobotId, const Mesh*> meshes = {{kA, &mesh_a}, {kB, &mesh_b}};
  const std::vector<MergeCandidate> candidate = {
      {NodeId::station('O', kA, 0), NodeId::station('O', kB, 0), Layer::kObjects, {}}};
  const std::map<NodeId, Eigen::Isometry3d> moved = {
      {NodeId::station('O', kB, 0), yaw_error.inverse()}};
  const auto unmoved = refineObjectMerges(candidate, g, T, meshes);
  ASSERT_EQ(unmoved.size(), 1u);
  EXPECT_FALSE(unmoved[0].T_target_source.has_value());
  const auto kept = refineObjectMerges(candidate, g, T, meshes, {}, &moved);
  ASSERT_EQ(kept.size(), 1u);
  ASSERT_TRUE(kept[0].T_target_source.has_value());
  EXPECT_LT(kept[0].T_target_source->translation().norm(), 0.02);
  EXPECT_LT(Eigen::AngleAxisd(kept[0].T_target_source->linear()).angle(), 0.01);
}

// ICP's verdict on a pair is kept for the next check: both copies moved together (a common rigid
// motion) take it without ICP, the same measurement, as does one copy moved within icp_reuse_m of
// the other; one copy moved further, or turned against the other, is checked again.
TEST(Reconciliation, IcpVerdictsAreReusedWhileThePairKeepsItsRelativePlacement) {
  const Eigen::Vector3d size(1.2, 0.6, 0.9);
  Eigen::Isometry3d at = Eigen::Isometry3d::Identity();
  at.translation() = Eigen::Vector3d(6.0, 3.0, 0.5);
  SceneGraph g;
  Mesh mesh_a, mesh_b;
  meshedObject(g, mesh_a, kA, 0, at, size);
  Eigen::Isometry3d turned = at;
  turned.linear() = Eigen::AngleAxisd(0.05, Eigen::Vector3d::UnitZ()).matrix();
  meshedObject(g, mesh_b, kB, 0, turned, size);
  const std::map<RobotId, Eigen::Isometry3d> T = {{kA, Eigen::Isometry3d::Identity()},
                                                  {kB, Eigen::Isometry3d::Identity()}};
  const std::map<RobotId, const Mesh*> meshes = {{kA, &mesh_a}, {kB, &mesh_b}};
  const NodeId a = NodeId::station('O', kA, 0), b = NodeId::station('O', kB, 0);
  const std::vector<MergeCandidate> candidate = {{a, b, Layer::kObjects, {}}};
  IcpCache cache;
  const auto first = refineObjectMerges(candidate, g, T, meshes, {}, nullptr, &cache);
  ASSERT_EQ(first.size(), 1u);
  ASSERT_TRUE(first[0].T_target_source.has_value());
  EXPECT_EQ(cache.computed, 1u);
  EXPECT_EQ(cache.reused, 0u);

  Eigen::Isometry3d common = Eigen::Isometry3d::Identity();
  common.linear() = Eigen::AngleAxisd(0.3, Eigen::Vector3d::UnitZ()).matrix();
  common.translation() = Eigen::Vector3d(1.0, -2.0, 0.1);
  const std::map<NodeId, Eigen::Isometry3d> together = {{a, common}, {b, common}};
  const auto again = refineObjectMerges(candidate, g, T, meshes, {}, &together, &cache);
  ASSERT_EQ(again.size(), 1u);
  EXPECT_EQ(cache.reused, 1u);
  EXPECT_EQ(cache.computed, 0u);
  EXPECT_EQ(again[0].T_target_source->matrix(), first[0].T_target_source->matrix());

  // b's copy 5 mm off where ICP checked it: within icp_reuse_m the verdict stands, beyond it ICP
  // runs again.
  Eigen::Isometry3d nudged = Eigen::Isometry3d::Identity();
  nudged.translation() = Eigen::Vector3d(0.0, 0.005, 0.0);
  const std::map<NodeId, Eigen::Isometry3d> nudged_b = {{b, nudged}};
  refineObjectMerges(candidate, g, T, meshes, {}, &nudged_b, &cache);
  EXPECT_EQ(cache.reused, 1u);
  ReconciliationOptions strict;
  strict.icp_reuse_m = 0.004;
  refineObjectMerges(candidate, g, T, meshes, strict, &nudged_b, &cache);
  EXPECT_EQ(cache.computed, 1u);

  Eigen::Isometry3d apart = Eigen::Isometry3d::Identity();
  apart.linear() = Eigen::AngleAxisd(0.4, Eigen::Vector3d::UnitZ()).matrix();
  apart = at * apart * at.inverse();  // b's copy turned about the object by 23 degrees
  const std::map<NodeId, Eigen::Isometry3d> turned_apart = {{b, apart}};
  const auto checked = refineObjectMerges(candidate, g, T, meshes, {}, &turned_apart, &cache);
  EXPECT_EQ(cache.reused, 0u);
  EXPECT_EQ(cache.computed, 1u);
  ASSERT_EQ(checked.size(), 1u);
  EXPECT_FALSE(checked[0].T_target_source.has_value());  // turned past 20 degrees: plain factor
}

// The candidates' ICP on several threads: each pair's verdict and measurement, and the order of
// the kept candidates, are those of one thread (pairs measured, kept as the plain factor, passed
// without ICP).
TEST(Reconciliation, IcpOnSeveralThreadsGivesTheVerdictsOfOne) {
  const Eigen::Vector3d size(1.2, 0.6, 0.9);
  SceneGraph g;
  Mesh mesh_a, mesh_b;
  std::vector<MergeCandidate> candidates;
  const double turns_deg[] = {3.0, 35.0, 0.0, 8.0, 1.0, 60.0, 12.0};
  for (uint64_t i = 0; i < 7; ++i) {
    Eigen::Isometry3d at = Eigen::Isometry3d::Identity();
    at.translation() = Eigen::Vector3d(10.0 * i, 3.0, 0.5);
    Eigen::Isometry3d other = at;
    other.linear() =
        Eigen::AngleAxisd(turns_deg[i] * M_PI / 180.0, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    other.translation() += Eigen::Vector3d(0.02 * i, -0.1, 0.0);
    meshedObject(g, mesh_a, kA, i, at, size);
    meshedObject(g, mesh_b, kB, i, other, size);
    candidates.push_back(
        {NodeId::station('O', kA, i), NodeId::station('O', kB, i), Layer::kObjects, {}});
  }
  candidates.push_back({NodeId::station('P', kA, 0),
                        NodeId::station('P', kB, 0),
                        Layer::kPlaces,
                        {}});  // passes as it is
  const std::map<RobotId, Eigen::Isometry3d> T = {{kA, Eigen::Isometry3d::Identity()},
                                                  {kB, Eigen::Isometry3d::Identity()}};
  const std::map<RobotId, const Mesh*> meshes = {{kA, &mesh_a}, {kB, &mesh_b}};
  ReconciliationOptions one;
  one.icp_threads = 1;
  IcpCache cache_one;
  const auto by_one = refineObjectMerges(candidates, g, T, meshes, one, nullptr, &cache_one);
  EXPECT_EQ(cache_one.computed, 7u);
  size_t measured = 0, plain = 0;
  for (const MergeCandidate& c : by_one) (c.T_target_source ? measured : plain) += 1;
  EXPECT_GE(measured, 3u);
  EXPECT_GE(plain, 3u);  // two turned past 20 degrees, and the place
  for (const int threads : {2, 3}) {
    ReconciliationOptions many;
    many.icp_threads = threads;
    IcpCache cache_many;
    const auto by_many = refineObjectMerges(candidates, g, T, meshes, many, nullptr, &cache_many);
    ASSERT_EQ(by_many.size(), by_one.size()) << threads;
    for (size_t k = 0; k < by_one.size(); ++k) {
      EXPECT_EQ(by_many[k].target, by_one[k].target);
      EXPECT_EQ(by_many[k].source, by_one[k].source);
      ASSERT_EQ(by_many[k].T_target_source.has_value(), by_one[k].T_target_source.has_value());
      if (by_one[k].T_target_source) {
        EXPECT_TRUE(by_many[k].T_target_source->matrix() == by_one[k].T_target_source->matrix());
      }
    }
    EXPECT_EQ(cache_many.computed, cache_one.computed);
    // The cache's entries as one thread's: the next check reuses them all either way.
    const auto again = refineObjectMerges(candidates, g, T, meshes, many, nullptr, &cache_many);
    EXPECT_EQ(cache_many.reused, 7u);
    EXPECT_EQ(again.size(), by_one.size());
  }
}

// An object of the backend graph: its box of `size` at `centre`, its lattice of vertices in the
// graph's mesh (global frame).
void labelledObject(SceneGraph& g, RobotId robot, uint64_t index, const Eigen::Vector3d& centre,
                    const Eigen::Vector3d& size, uint32_t label) {
  Node node = makeNode(NodeId::station('O', robot, index), Layer::kObjects, centre);
  node.semantic()->label = label;
  node.semantic()->bounding_box = BoundingBox{centre - 0.5 * size, centre + 0.5 * size};
  for (const Eigen::Vector3d& p : testing::latticeBoxVertices(size)) {
    node.find<ObjectAttributes>()->mesh_vertices.push_back(g.mesh().vertices.size());
    MeshVertex v;
    v.position = (centre + p).cast<float>();
    g.mesh().vertices.push_back(v);
  }
  g.addOrUpdateNode(node);
}

const uint32_t kChair = 5, kSofa = 8, kTable = 7;
const Eigen::Vector3d kChairSize(0.5, 0.5, 0.9);

// Robot a called a chair a sofa; robots b and c called it a chair, and their copies are merged
// into b's. Two robots against one, at a confusion of 0.1: odds 9 for the chair (the labels as
// common), so a's copy merges into b's.
TEST(LabelVotes, TwoRobotsOutvoteOne) {
  const RobotId kC(2);
  SceneGraph g;
  labelledObject(g, kA, 0, {2.0, 1.0, 0.45}, kChairSize, kSofa);
  labelledObject(g, kB, 0, {2.05, 1.02, 0.45}, kChairSize, kChair);
  const auto disputes = resolveLabelDisputes(g, {{NodeId::station('O', kB, 0), {kB, kC}}});
  ASSERT_EQ(disputes.size(), 1u);
  EXPECT_EQ(disputes[0].winner, NodeId::station('O', kB, 0));
  EXPECT_EQ(disputes[0].loser, NodeId::station('O', kA, 0));
  EXPECT_NEAR(disputes[0].odds, 9.0, 1e-9);
  // Without c's vote it is one robot against one and the labels are as common: no decision.
  EXPECT_TRUE(resolveLabelDisputes(g, {}).empty());
}

// One robot against one: the prior decides, the label of more objects in the team's graph. With
// six chairs and one sofa, (6 + 1) / (1 + 1) = 3.5 >= 3: the sofa is taken for a chair, whichever
// robot called it so; with two sofas, 7 / 3 < 3: both stay.
TEST(LabelVotes, OneAgainstOneTheCommonerLabelWins) {
  for (const bool a_says_chair : {true, false}) {
    SceneGraph g;
    labelledObject(g, kA, 0, {2.0, 1.0, 0.45}, kChairSize, a_says_chair ? kChair : kSofa);
    labelledObject(g, kB, 0, {2.03, 0.98, 0.45}, kChairSize, a_says_chair ? kSofa : kChair);
    for (uint64_t i = 1; i <= 5; ++i)
      labelledObject(g, kA, i, {10.0 * double(i), 8.0, 0.45}, kChairSize, kChair);
    const auto disputes = resolveLabelDisputes(g, {});
    ASSERT_EQ(disputes.size(), 1u);
    const NodeId chair = NodeId::station('O', a_says_chair ? kA : kB, 0);
    const NodeId sofa = NodeId::station('O', a_says_chair ? kB : kA, 0);
    EXPECT_EQ(disputes[0].winner, chair);
    EXPECT_EQ(disputes[0].loser, sofa);
    EXPECT_NEAR(disputes[0].odds, 3.5, 1e-9);
    labelledObject(g, kB, 1, {5.0, -8.0, 0.45}, Eigen::Vector3d(2.0, 0.9, 0.85), kSofa);
    EXPECT_TRUE(resolveLabelDisputes(g, {}).empty());
  }
}

// No dispute without one surface, two robots and enough vertices: a chair pushed under a table
// (the table's box holds its centre, their vertices lie apart), two copies of one robot, a copy of
// too few vertices.
TEST(LabelVotes, OnlyOneSurfaceOfTwoRobots) {
  ReconciliationOptions options;
  options.label_min_odds = 1.0;  // any odds decide: only the geometry and the robots can refuse
  SceneGraph g;
  labelledObject(g, kA, 0, {2.0, 1.0, 0.375}, Eigen::Vector3d(1.2, 0.8, 0.75), kTable);
  labelledObject(g, kB, 0, {2.2, 1.1, 0.45}, kChairSize, kChair);
  EXPECT_TRUE(resolveLabelDisputes(g, {}, options).empty());
  SceneGraph one_robot;
  labelledObject(one_robot, kA, 0, {2.0, 1.0, 0.45}, kChairSize, kSofa);
  labelledObject(one_robot, kA, 1, {2.0, 1.0, 0.45}, kChairSize, kChair);
  EXPECT_TRUE(resolveLabelDisputes(one_robot, {}, options).empty());
  labelledObject(one_robot, kB, 0, {2.0, 1.0, 0.45}, kChairSize, kChair);
  EXPECT_EQ(resolveLabelDisputes(one_robot, {}, options).size(), 1u);
  options.icp_min_vertices = 1000;
  EXPECT_TRUE(resolveLabelDisputes(one_robot, {}, options).empty());
}

}  // namespace
}  // namespace hydra_multi
