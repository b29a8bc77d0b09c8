// Reconciliation proposals: which places and objects of two aligned robots look like one node.

#include <gtest/gtest.h>

#include "hydra_multi/backend/reconciliation.h"

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
  place(g, kB, 0, {1.2 - 10, 1, 1}, 1.1);   // 0.2 m away, similar radius: a candidate
  place(g, kA, 1, {5, 1, 1}, 1.0);
  place(g, kB, 1, {5.3 - 10, 1, 1}, 0.5);   // radii too different
  place(g, kB, 2, {8 - 10, 1, 1}, 1.0);     // too far from anything
  object(g, kA, 0, {3, 3, 0.5}, 6, 0.5);
  object(g, kB, 0, {3.3 - 10, 3.2, 0.5}, 6, 0.5);  // same label, boxes overlap
  object(g, kB, 1, {3.1 - 10, 2.9, 0.5}, 7, 0.5);  // another label
  object(g, kA, 1, {9, 9, 0.5}, 6, 0.3);
  object(g, kB, 2, {9.8 - 10, 9, 0.5}, 6, 0.3);     // same label, boxes apart
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
  const auto factors = mergeFactors(candidates, {{kA, Eigen::Isometry3d::Identity()}, {kB, turned}});
  ASSERT_EQ(factors.size(), 2u);
  EXPECT_EQ(factors[0].kind, PoseGraphEdge::Kind::kLoopClosure);
  EXPECT_LT(factors[0].T_from_to.translation().norm(), 1e-12);
  EXPECT_NEAR(Eigen::AngleAxisd(factors[0].T_from_to.linear()).angle(), 0.5, 1e-12);
}

}  // namespace
}  // namespace hydra_multi
