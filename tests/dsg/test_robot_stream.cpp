// RobotStreamState: a robot's updates folded into one snapshot; what does not fold is an error
// naming the update, and changes nothing.

#include <gtest/gtest.h>

#include "hydra_multi/dsg/robot_stream.h"

namespace hydra_multi {
namespace {

const RobotId kA(0);

Node keyframe(uint64_t index) {
  Node node = makeNode(NodeId('a', index), Layer::kAgents, Eigen::Vector3d(double(index), 0, 0));
  node.find<AgentAttributes>()->timestamp_ns = static_cast<int64_t>(index);
  return node;
}

// Update `sequence`: keyframe `sequence`, odometry from the one before, a control point on it and
// its descriptor; one mesh vertex.
RobotUpdate step(uint64_t sequence) {
  RobotUpdate u;
  u.robot = kA;
  u.sequence = sequence;
  u.time_ns = static_cast<int64_t>(sequence) * 10;
  u.is_snapshot = sequence == 0;
  u.graph.nodes.push_back(keyframe(sequence));
  if (sequence > 0) {
    u.graph.edges.push_back({NodeId('a', sequence - 1), NodeId('a', sequence), {}});
    u.pose_graph.push_back({NodeId('a', sequence - 1), NodeId('a', sequence)});
    u.deformation.edges.push_back({sequence - 1, sequence});
  }
  u.deformation.points.push_back(
      {sequence, Eigen::Vector3d::Zero(), u.time_ns, NodeId('a', sequence)});
  u.descriptors.push_back({NodeId('a', sequence), {{7, 1.0f}}, {}});
  u.graph.mesh.vertex_start = sequence;
  MeshVertex v;
  v.robot = kA;
  v.position.x() = double(sequence);
  u.graph.mesh.vertices.push_back(v);
  u.graph.mesh.face_start = 0;
  return u;
}

TEST(RobotStreamState, FoldsUpdatesIntoOneSnapshot) {
  RobotStreamState state;
  for (uint64_t s = 0; s < 4; ++s) ASSERT_TRUE(state.add(step(s)).ok());
  // Update 4 deletes keyframe 1: its edges, control point and descriptor go with it.
  RobotUpdate removal = step(4);
  removal.graph.removed_nodes.push_back(NodeId('a', 1));
  ASSERT_TRUE(state.add(removal).ok()) << state.add(removal).message();
  EXPECT_EQ(state.updatesAdded(), 5u);
  const RobotUpdate snapshot = state.snapshot();
  EXPECT_TRUE(snapshot.is_snapshot);
  EXPECT_EQ(snapshot.sequence, 4u);
  EXPECT_EQ(snapshot.time_ns, 40);
  EXPECT_EQ(snapshot.graph.nodes.size(), 4u);
  EXPECT_EQ(snapshot.graph.mesh.vertex_start, 0u);
  EXPECT_EQ(snapshot.graph.mesh.vertices.size(), 5u);
  EXPECT_EQ(snapshot.graph.edges.size(), 2u);  // 2-3 and 3-4
  ASSERT_EQ(snapshot.pose_graph.size(), 2u);
  EXPECT_EQ(snapshot.pose_graph.front().from, NodeId('a', 2));
  EXPECT_EQ(snapshot.deformation.points.size(), 4u);
  EXPECT_EQ(snapshot.deformation.edges, (std::vector<ControlPointEdge>{{2, 3}, {3, 4}}));
  ASSERT_EQ(snapshot.descriptors.size(), 4u);
  EXPECT_EQ(snapshot.descriptors[1].keyframe, NodeId('a', 2));
  EXPECT_TRUE(validateRobotUpdate(snapshot).ok());
  // A snapshot starts over; the one just made folds into itself.
  RobotStreamState again;
  ASSERT_TRUE(again.add(snapshot).ok());
  EXPECT_EQ(again.snapshot(), snapshot);
}

TEST(RobotStreamState, WhatDoesNotFoldIsAnErrorAndChangesNothing) {
  RobotStreamState state;
  const Status first = state.add(step(1));
  ASSERT_FALSE(first.ok());
  EXPECT_NE(first.message().find("update 1 of robot a: the first update of a stream must be a "
                                 "snapshot"),
            std::string::npos)
      << first.message();
  ASSERT_TRUE(state.add(step(0)).ok());
  const RobotUpdate before = state.snapshot();
  const Status gap = state.add(step(2));
  ASSERT_FALSE(gap.ok());
  EXPECT_NE(gap.message().find("expected sequence 1"), std::string::npos) << gap.message();
  RobotUpdate dangling = step(1);
  dangling.graph.edges.push_back({NodeId('a', 1), NodeId('a', 42), {}});
  const Status bad = state.add(dangling);
  ASSERT_FALSE(bad.ok());
  EXPECT_NE(bad.message().find("update 1 of robot a"), std::string::npos) << bad.message();
  RobotUpdate nan = step(1);
  nan.graph.mesh.vertices.front().position.z() = std::nan("");
  EXPECT_FALSE(state.add(nan).ok());
  EXPECT_EQ(state.snapshot(), before);
  EXPECT_EQ(state.updatesAdded(), 1u);
}

}  // namespace
}  // namespace hydra_multi
