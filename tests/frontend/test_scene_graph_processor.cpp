// The station's scene-graph processor: id remapping, deletions, robots joining late, replayed,
// out-of-order, gapped and corrupt updates; the graph is never left half-changed.

#include <gtest/gtest.h>

#include <algorithm>
#include <cstdlib>
#include <limits>
#include <map>
#include <optional>
#include <string>

#include "hydra_multi/dsg/graph_delta.h"
#include "hydra_multi/dsg/io/binary_format.h"
#include "hydra_multi/dsg/robot_stream.h"
#include "hydra_multi/frontend/scene_graph_processor.h"
#include "hydra_multi/sim/dataset.h"

namespace hydra_multi {
namespace {

const RobotId kA(0), kB(1), kC(2);

Node object(uint64_t index, const Eigen::Vector3d& p, uint32_t label = 5) {
  Node node = makeNode(NodeId('O', index), Layer::kObjects, p);
  node.semantic()->label = label;
  return node;
}

Node keyframe(RobotId robot, uint64_t index, const Eigen::Vector3d& p) {
  Node node = makeNode(NodeId(robot.prefix(), index), Layer::kAgents, p);
  node.find<AgentAttributes>()->timestamp_ns = static_cast<int64_t>(index) * 1000000000;
  return node;
}

// Update `sequence` of `robot` adding keyframe `sequence` and object `sequence`, the keyframe
// linked to the previous one.
RobotUpdate step(RobotId robot, uint64_t sequence) {
  RobotUpdate u;
  u.robot = robot;
  u.sequence = sequence;
  u.time_ns = static_cast<int64_t>(sequence) * 1000000000;
  u.is_snapshot = sequence == 0;
  u.graph.nodes.push_back(keyframe(robot, sequence, Eigen::Vector3d(double(sequence), 0, 0)));
  u.graph.nodes.push_back(object(sequence, Eigen::Vector3d(double(sequence), 1, 0)));
  if (sequence > 0) {
    u.graph.edges.push_back(
        {NodeId(robot.prefix(), sequence - 1), NodeId(robot.prefix(), sequence), {}});
    PoseGraphEdge odometry;
    odometry.from = NodeId(robot.prefix(), sequence - 1);
    odometry.to = NodeId(robot.prefix(), sequence);
    u.pose_graph.push_back(odometry);
  }
  u.graph.mesh.vertex_start = sequence;  // one mesh vertex per update
  MeshVertex v;
  v.robot = robot;
  u.graph.mesh.vertices.push_back(v);
  u.graph.mesh.face_start = 0;
  return u;
}

TEST(SceneGraphProcessor, RemapsIdsPerRobot) {
  SceneGraphProcessor processor;
  ASSERT_EQ(processor.process(step(kA, 0)).outcome, UpdateOutcome::kApplied);
  ASSERT_EQ(processor.process(step(kB, 0)).outcome, UpdateOutcome::kApplied);
  const SceneGraph& g = processor.graph();
  const NodeId a0 = NodeId::station('O', kA, 0), b0 = NodeId::station('O', kB, 0);
  EXPECT_TRUE(g.hasNode(a0));
  EXPECT_TRUE(g.hasNode(b0));
  EXPECT_EQ(g.numNodes(), 4u);
  EXPECT_EQ(SceneGraphProcessor::toRobotSide(b0)->first, kB);
  EXPECT_EQ(SceneGraphProcessor::toRobotSide(b0)->second, NodeId('O', 0));
  EXPECT_EQ(processor.frameOf(b0), kB);
  EXPECT_EQ(g.getNode(NodeId::station('b', kB, 0)).robot(), kB);
  EXPECT_EQ(processor.robot(kA)->mesh.vertices.size(), 1u);
  // A robot may not send another robot's keyframes.
  RobotUpdate foreign = step(kA, 1);
  foreign.graph.nodes.push_back(keyframe(kB, 7, Eigen::Vector3d::Zero()));
  const UpdateReport report = processor.process(foreign);
  EXPECT_EQ(report.outcome, UpdateOutcome::kRejected);
  EXPECT_NE(report.message.find("does not carry robot a's prefix"), std::string::npos);
  EXPECT_EQ(g.numNodes(), 4u);
}

TEST(SceneGraphProcessor, DeletionsAndLateRobots) {
  SceneGraphProcessor processor;
  for (uint64_t s = 0; s < 3; ++s) processor.process(step(kA, s));
  RobotUpdate remove = step(kA, 3);
  remove.graph.removed_nodes.push_back(NodeId('O', 1));
  const UpdateReport report = processor.process(remove);
  ASSERT_EQ(report.outcome, UpdateOutcome::kApplied) << report.message;
  EXPECT_FALSE(processor.graph().hasNode(NodeId::station('O', kA, 1)));
  EXPECT_EQ(report.nodes_removed, 1u);
  EXPECT_EQ(report.new_keyframes, std::vector<NodeId>{NodeId::station('a', kA, 3)});
  // Robot c joins late; robot a goes on.
  EXPECT_EQ(processor.process(step(kC, 0)).outcome, UpdateOutcome::kApplied);
  EXPECT_EQ(processor.process(step(kA, 4)).outcome, UpdateOutcome::kApplied);
  EXPECT_EQ(processor.robots(), (std::vector<RobotId>{kA, kC}));
  EXPECT_EQ(processor.robot(kA)->pose_graph.size(), 4u);
  EXPECT_EQ(processor.order(kA)->nextSequence(), 5u);
}

// A replayed update is recognised and ignored; the same number with other content is refused.
TEST(SceneGraphProcessor, ReplayedUpdates) {
  SceneGraphProcessor processor;
  processor.process(step(kA, 0));
  processor.process(step(kA, 1));
  const SceneGraph before = processor.graph();
  EXPECT_EQ(processor.process(step(kA, 1)).outcome, UpdateOutcome::kDuplicate);
  RobotUpdate other = step(kA, 1);
  other.graph.nodes[1].position.x() += 1.0;
  const UpdateReport conflicting = processor.process(other);
  EXPECT_EQ(conflicting.outcome, UpdateOutcome::kRejected);
  EXPECT_NE(conflicting.message.find("differs"), std::string::npos);
  EXPECT_EQ(processor.graph(), before);
}

// Updates that overtake a missing one wait for it; the result is the in-order graph.
TEST(SceneGraphProcessor, OutOfOrderUpdates) {
  SceneGraphProcessor in_order, shuffled;
  for (uint64_t s = 0; s < 5; ++s) in_order.process(step(kA, s));
  shuffled.process(step(kA, 0));
  EXPECT_EQ(shuffled.process(step(kA, 3)).outcome, UpdateOutcome::kBuffered);
  EXPECT_EQ(shuffled.process(step(kA, 2)).outcome, UpdateOutcome::kBuffered);
  EXPECT_EQ(shuffled.process(step(kA, 4)).outcome, UpdateOutcome::kBuffered);
  EXPECT_EQ(shuffled.order(kA)->heldBack(), 3u);
  const UpdateReport report = shuffled.process(step(kA, 1));
  EXPECT_EQ(shuffled.order(kA)->heldBack(), 0u);
  EXPECT_EQ(report.outcome, UpdateOutcome::kApplied);
  EXPECT_EQ(report.applied, (std::vector<uint64_t>{1, 2, 3, 4}));
  EXPECT_EQ(shuffled.graph(), in_order.graph());
  EXPECT_EQ(shuffled.robot(kA)->mesh, in_order.robot(kA)->mesh);
  // The counters: two applied on arrival, three buffered and applied later.
  const UpdateCounts counts = shuffled.counts();
  EXPECT_EQ(counts.applied, 2u);
  EXPECT_EQ(counts.buffered, 3u);
  EXPECT_EQ(counts.applied_from_buffer, 3u);
  EXPECT_EQ(counts.rejected + counts.waiting + counts.duplicates, 0u);
}

// A gap longer than the reorder buffer makes the robot wait for a snapshot, which recovers it.
TEST(SceneGraphProcessor, GapWaitsForSnapshot) {
  ProcessorOptions options;
  options.reorder_buffer = 2;
  std::vector<std::string> log;
  SceneGraphProcessor processor(options, [&](const std::string& line) { log.push_back(line); });
  processor.process(step(kA, 0));
  processor.process(step(kA, 2));
  processor.process(step(kA, 3));
  EXPECT_EQ(processor.process(step(kA, 4)).outcome, UpdateOutcome::kWaiting);
  EXPECT_TRUE(processor.order(kA)->waitingForSnapshot());
  EXPECT_EQ(processor.process(step(kA, 5)).outcome, UpdateOutcome::kWaiting);
  EXPECT_EQ(processor.counts().waiting, 2u);
  EXPECT_EQ(processor.counts().applied_from_buffer, 0u);  // 2 and 3 were dropped with the wait
  ASSERT_FALSE(log.empty());
  EXPECT_NE(log.back().find("robot a update 5"), std::string::npos);
  // The snapshot: the robot's whole graph at sequence 6.
  RobotUpdate snapshot;
  snapshot.robot = kA;
  snapshot.sequence = 6;
  snapshot.is_snapshot = true;
  snapshot.graph.nodes = {keyframe(kA, 0, Eigen::Vector3d::Zero()),
                          object(9, Eigen::Vector3d::Ones())};
  const UpdateReport report = processor.process(snapshot);
  ASSERT_EQ(report.outcome, UpdateOutcome::kApplied) << report.message;
  EXPECT_FALSE(processor.order(kA)->waitingForSnapshot());
  EXPECT_EQ(processor.graph().numNodes(), 2u);  // replaced, not added
  EXPECT_TRUE(processor.graph().hasNode(NodeId::station('O', kA, 9)));
  EXPECT_TRUE(processor.robot(kA)->mesh.vertices.empty());
  // And deltas on top of the snapshot apply again.
  RobotUpdate next = step(kA, 7);
  next.graph.edges = {{NodeId('a', 0), NodeId('a', 7), {}}};
  next.pose_graph.front().from = NodeId('a', 0);
  next.graph.mesh.vertex_start = 0;
  const UpdateReport after = processor.process(next);
  EXPECT_EQ(after.outcome, UpdateOutcome::kApplied) << after.message;
}

// A corrupt update in the middle of a real robot stream is refused whole: the graph is what the
// updates before it made, and it stays intact.
TEST(SceneGraphProcessor, CorruptUpdateInARealStream) {
  auto dataset = sim::simulateDataset(sim::presetConfig("tiny", 2).value());
  ASSERT_TRUE(dataset.ok());
  const std::vector<RobotUpdate>& stream = dataset.value().streams[0];
  ASSERT_GT(stream.size(), 10u);
  const size_t middle = stream.size() / 2;
  SceneGraphProcessor reference, processor;
  for (size_t i = 0; i < middle; ++i) {
    ASSERT_EQ(reference.process(stream[i]).outcome, UpdateOutcome::kApplied);
    ASSERT_EQ(processor.process(stream[i]).outcome, UpdateOutcome::kApplied);
  }
  const auto corruptions = std::vector<std::function<void(RobotUpdate&)>>{
      [](RobotUpdate& u) { u.graph.nodes.back().position.x() = std::nan(""); },
      [](RobotUpdate& u) {
        u.graph.mesh.faces.push_back({0, 1, 99999999});
      },
      [](RobotUpdate& u) { u.graph.removed_nodes.push_back(NodeId('O', 777)); },
      [](RobotUpdate& u) { u.graph.mesh.vertex_start += 5; },
      [](RobotUpdate& u) {
        u.descriptors.push_back(u.descriptors.front());
        u.descriptors.back().keyframe = NodeId('a', 99999);
      },
  };
  for (const auto& corrupt : corruptions) {
    SceneGraphProcessor copy = processor;
    RobotUpdate bad = stream[middle];
    corrupt(bad);
    const UpdateReport report = copy.process(bad);
    EXPECT_EQ(report.outcome, UpdateOutcome::kRejected);
    // The message names the robot and the update.
    EXPECT_NE(report.message.find("robot a"), std::string::npos) << report.message;
    EXPECT_NE(report.message.find("update " + std::to_string(middle)), std::string::npos)
        << report.message;
    EXPECT_EQ(copy.graph(), reference.graph());
    EXPECT_EQ(copy.robot(RobotId(0))->mesh, reference.robot(RobotId(0))->mesh);
    // The robot's later deltas cannot apply without the refused one: it waits for a snapshot.
    EXPECT_NE(copy.process(stream[middle + 1]).outcome, UpdateOutcome::kApplied);
    EXPECT_EQ(copy.graph(), reference.graph());
  }
}

// The changes the processor applied, taken now and then and applied in order to a copy of its graph
// and robots' states as they were at the first take, give its graph and states: through two robots'
// interleaved streams with a reordered pair, a refused update, the wait for a snapshot and the
// snapshot itself.
TEST(SceneGraphProcessor, ItsDeltasKeepACopyOfItsGraph) {
  auto dataset = sim::simulateDataset(sim::presetConfig("tiny", 2).value());
  ASSERT_TRUE(dataset.ok());
  const auto& streams = dataset.value().streams;
  ASSERT_EQ(streams.size(), 2u);
  ASSERT_GT(streams[0].size(), 8u);
  SceneGraphProcessor processor;
  SceneGraph copy;
  std::vector<RobotUpdate> arrivals;
  for (size_t i = 0; i < std::max(streams[0].size(), streams[1].size()); ++i) {
    for (const auto& stream : streams) {
      if (i < stream.size()) arrivals.push_back(stream[i]);
    }
  }
  std::swap(arrivals[6], arrivals[8]);                          // robot a's updates 3 and 4 swapped
  arrivals[12].graph.nodes.back().position.x() = std::nan("");  // refused: robot a waits
  RobotStreamState sent;  // robot a's, for the snapshot that recovers it
  for (const RobotUpdate& u : streams[0]) ASSERT_TRUE(sent.add(u).ok());
  // Deltas kept from the second arrival on: the copy starts from the graph then.
  processor.process(arrivals[0]);
  copy = processor.graph();
  std::map<RobotId, RobotFrontendState> states;
  for (const RobotId r : processor.robots()) states[r] = *processor.robot(r);
  processor.keepDeltas();
  // The robots' states but the descriptors (the detector's).
  const auto expectSameStates = [&] {
    for (const RobotId r : processor.robots()) {
      const RobotFrontendState& a = *processor.robot(r);
      const RobotFrontendState& b = states[r];
      EXPECT_EQ(a.mesh, b.mesh) << r.str();
      EXPECT_EQ(a.pose_graph, b.pose_graph) << r.str();
      EXPECT_EQ(a.control_points, b.control_points) << r.str();
      EXPECT_EQ(a.control_point_edges, b.control_point_edges) << r.str();
      EXPECT_EQ(a.last_time_ns, b.last_time_ns) << r.str();
      EXPECT_EQ(a.provided_layers, b.provided_layers) << r.str();
    }
  };
  size_t taken = 0, outcomes_refused = 0;
  for (size_t i = 1; i < arrivals.size(); ++i) {
    const UpdateReport report = processor.process(arrivals[i]);
    outcomes_refused += report.outcome != UpdateOutcome::kApplied;
    if (i % 5 == 0 || i + 1 == arrivals.size()) {
      for (const AppliedDelta& delta : processor.takeDeltas()) {
        ASSERT_TRUE(applyDelta(copy, delta.graph).ok());
        applyStateDelta(states[delta.robot.robot], delta.robot);
        ++taken;
      }
      EXPECT_EQ(copy, processor.graph()) << "after arrival " << i;
      expectSameStates();
    }
  }
  const UpdateReport recovered = processor.process(sent.snapshot());
  ASSERT_EQ(recovered.outcome, UpdateOutcome::kApplied) << recovered.message;
  for (const AppliedDelta& delta : processor.takeDeltas()) {
    ASSERT_TRUE(applyDelta(copy, delta.graph).ok());
    applyStateDelta(states[delta.robot.robot], delta.robot);
  }
  EXPECT_EQ(copy, processor.graph());
  expectSameStates();
  EXPECT_GT(outcomes_refused, 1u);  // the refused update, and robot a's after it
  EXPECT_GT(taken, arrivals.size() / 2);
  EXPECT_TRUE(processor.takeDeltas().empty());
}

// The objects per label and a robot's keyframe nearest a time, by a pass over the graph.
std::map<uint32_t, size_t> objectsPerLabelByPass(const SceneGraph& graph) {
  std::map<uint32_t, size_t> count;
  for (const NodeId id : graph.nodesInLayer(Layer::kObjects))
    ++count[graph.getNode(id).semantic()->label];
  return count;
}

std::optional<NodeId> keyframeNearestByPass(const SceneGraph& graph, RobotId robot,
                                            int64_t time_ns) {
  std::optional<NodeId> best;
  int64_t best_gap = std::numeric_limits<int64_t>::max();
  for (const NodeId id : graph.nodesOfRobot(robot, Layer::kAgents)) {  // in id order
    const int64_t gap =
        std::llabs(graph.getNode(id).find<AgentAttributes>()->timestamp_ns - time_ns);
    if (gap < best_gap) {
      best_gap = gap;
      best = id;
    }
  }
  return best;
}

void expectIndexesFollowTheGraph(const SceneGraphProcessor& processor, const std::string& when) {
  const SceneGraph& graph = processor.graph();
  EXPECT_EQ(processor.objectsPerLabel(), objectsPerLabelByPass(graph)) << when;
  // Times from a second before the first stamp to a second after the last, 300 of them, and every
  // stamp itself.
  std::vector<int64_t> times;
  for (const NodeId id : graph.nodesInLayer(Layer::kAgents))
    times.push_back(graph.getNode(id).find<AgentAttributes>()->timestamp_ns);
  if (times.empty()) return;
  const auto [low, high] = std::minmax_element(times.begin(), times.end());
  const int64_t first = *low - 1000000000, span = *high - *low + 2000000000;
  for (int k = 0; k <= 300; ++k) times.push_back(first + span / 300 * k);
  for (const RobotId robot : {kA, kB, kC}) {
    for (const int64_t t : times) {
      ASSERT_EQ(processor.keyframeNearest(robot, t), keyframeNearestByPass(graph, robot, t))
          << when << ", robot " << robot.str() << ", t " << t;
    }
  }
}

// The objects per label and the keyframes by time follow the graph through real updates, swapped
// and refused ones, a snapshot, removals, a label that changes and a keyframe re-stamped; of two
// keyframes as near a time, the one with the smaller id.
TEST(SceneGraphProcessor, ItsIndexesFollowTheGraph) {
  auto dataset = sim::simulateDataset(sim::presetConfig("tiny", 2).value());
  ASSERT_TRUE(dataset.ok());
  const auto& streams = dataset.value().streams;
  std::vector<RobotUpdate> arrivals;
  for (size_t i = 0; i < std::max(streams[0].size(), streams[1].size()); ++i) {
    for (const auto& stream : streams) {
      if (i < stream.size()) arrivals.push_back(stream[i]);
    }
  }
  std::swap(arrivals[6], arrivals[8]);
  arrivals[12].graph.nodes.back().position.x() = std::nan("");  // refused: robot a waits
  RobotStreamState sent;
  for (const RobotUpdate& u : streams[0]) ASSERT_TRUE(sent.add(u).ok());
  SceneGraphProcessor processor;
  for (size_t i = 0; i < arrivals.size(); ++i) {
    processor.process(arrivals[i]);
    expectIndexesFollowTheGraph(processor, "after arrival " + std::to_string(i));
  }
  ASSERT_GT(processor.objectsPerLabel().size(), 1u);
  ASSERT_EQ(processor.process(sent.snapshot()).outcome, UpdateOutcome::kApplied);
  expectIndexesFollowTheGraph(processor, "after the snapshot");

  // Robot c: keyframes 0 and 2 s apart from 1 (ties), an object relabelled, one removed, a
  // keyframe re-stamped.
  SceneGraphProcessor own;
  for (uint64_t s = 0; s < 4; ++s)
    ASSERT_EQ(own.process(step(kC, s)).outcome, UpdateOutcome::kApplied);
  RobotUpdate change = step(kC, 4);
  change.graph.nodes.push_back(object(1, Eigen::Vector3d(1, 1, 0), 9));
  change.graph.removed_nodes.push_back(NodeId('O', 2));
  Node restamped = keyframe(kC, 3, Eigen::Vector3d(3, 0, 0));
  restamped.find<AgentAttributes>()->timestamp_ns = 1000000000;  // as keyframe 1's
  change.graph.nodes.push_back(restamped);
  ASSERT_EQ(own.process(change).outcome, UpdateOutcome::kApplied);
  expectIndexesFollowTheGraph(own, "after the changes");
  EXPECT_EQ(own.objectsPerLabel(), (std::map<uint32_t, size_t>{{5, 3}, {9, 1}}));
  // 1 s: keyframes 1 and 3 (re-stamped), the smaller id; 3 s: keyframes 2 and 4 a second away.
  EXPECT_EQ(own.keyframeNearest(kC, 1000000000), NodeId::station('c', kC, 1));
  EXPECT_EQ(own.keyframeNearest(kC, 3000000000), NodeId::station('c', kC, 2));
  EXPECT_EQ(own.keyframeNearest(kA, 0), std::nullopt);
}

void expectSameRobotState(const SceneGraphProcessor& a, const SceneGraphProcessor& b,
                          RobotId robot) {
  EXPECT_EQ(a.graph(), b.graph());
  const RobotFrontendState& x = *a.robot(robot);
  const RobotFrontendState& y = *b.robot(robot);
  EXPECT_EQ(a.order(robot)->nextSequence(), b.order(robot)->nextSequence());
  EXPECT_EQ(a.order(robot)->waitingForSnapshot(), b.order(robot)->waitingForSnapshot());
  EXPECT_EQ(x.mesh, y.mesh);
  EXPECT_EQ(x.pose_graph, y.pose_graph);
  EXPECT_EQ(x.control_points, y.control_points);
  EXPECT_EQ(x.control_point_edges, y.control_point_edges);
  EXPECT_EQ(x.descriptors, y.descriptors);
}

// The snapshot of a real stream so far (dsg/robot_stream.h), applied in place of an update,
// leaves the station as the update did; after a lost update the robot waits, and the next
// snapshot brings it back to the state of the whole stream.
TEST(SceneGraphProcessor, SnapshotOfTheStreamSoFarRecoversALostUpdate) {
  auto dataset = sim::simulateDataset(sim::presetConfig("tiny", 2).value());
  ASSERT_TRUE(dataset.ok());
  const std::vector<RobotUpdate>& stream = dataset.value().streams[0];
  ASSERT_GT(stream.size(), 10u);
  const RobotId robot = stream.front().robot;
  SceneGraphProcessor reference, lossy;
  RobotStreamState sent;
  const size_t lost = stream.size() / 2, resent = lost + 3;
  for (size_t i = 0; i < stream.size(); ++i) {
    ASSERT_TRUE(sent.add(stream[i]).ok());
    ASSERT_EQ(reference.process(stream[i]).outcome, UpdateOutcome::kApplied);
    if (i % 4 == 2) {  // the snapshot instead of update i, on a copy
      SceneGraphProcessor by_snapshot;
      for (size_t j = 0; j < i; ++j) by_snapshot.process(stream[j]);
      const UpdateReport report = by_snapshot.process(sent.snapshot());
      ASSERT_EQ(report.outcome, UpdateOutcome::kApplied) << report.message;
      expectSameRobotState(by_snapshot, reference, robot);
    }
    if (i == lost) continue;
    const UpdateReport report = lossy.process(i == resent ? sent.snapshot() : stream[i]);
    if (i > lost && i < resent) {
      EXPECT_EQ(report.outcome, UpdateOutcome::kBuffered);
    } else if (i >= resent) {
      EXPECT_EQ(report.outcome, UpdateOutcome::kApplied) << report.message;
    }
  }
  EXPECT_EQ(lossy.order(robot)->heldBack(), 0u);
  expectSameRobotState(lossy, reference, robot);
  EXPECT_EQ(sent.snapshot().sequence, stream.back().sequence);
}

// A stream replayed outside the station (dsg/robot_stream.h: dataset-graph, info, the
// evaluation) applies the same updates as the station and counts them alike, through a lost
// update, a reordered pair, a duplicate, a snapshot that supersedes buffered deltas and a refused
// update; what it ends with is the station's graph of that robot, in robot-side ids.
TEST(SceneGraphProcessor, AStreamReplayAppliesWhatTheStationApplies) {
  sim::SimulationConfig config = sim::presetConfig("tiny", 3).value();
  config.mapper.snapshot_every = 5;
  auto dataset = sim::simulateDataset(config);
  ASSERT_TRUE(dataset.ok());
  const std::vector<RobotUpdate>& stream = dataset.value().streams[1];
  ASSERT_GT(stream.size(), 12u);
  const RobotId robot = stream.front().robot;
  std::vector<RobotUpdate> arrivals;
  for (size_t i = 0; i < stream.size(); ++i) {
    if (i == 2) continue;  // lost: 3 and 4 wait, the snapshot at 5 supersedes them
    if (i == 7) {          // 8 before 7, then 7 again
      arrivals.push_back(stream[8]);
      arrivals.push_back(stream[7]);
      arrivals.push_back(stream[7]);
      ++i;
      continue;
    }
    arrivals.push_back(stream[i]);
  }
  RobotUpdate foreign = stream[10];
  foreign.graph.nodes.front().position.x() = std::nan("");
  arrivals.insert(arrivals.begin() + 9, foreign);  // malformed: refused by both
  SceneGraphProcessor station;
  RobotStreamReplay replay(robot, io::robotUpdateDigest);
  for (const RobotUpdate& u : arrivals) {
    const UpdateOutcome at_station = station.process(u).outcome;
    EXPECT_EQ(replay.add(u).outcome, at_station) << "update " << u.sequence;
  }
  const UpdateCounts& a = station.order(robot)->counts();
  const UpdateCounts& b = replay.order().counts();
  EXPECT_EQ(describeStream(robot, station.order(robot), 1),
            describeStream(robot, &replay.order(), 1));
  EXPECT_EQ(a.applied_from_buffer, b.applied_from_buffer);
  EXPECT_EQ(a.superseded, 2u);
  EXPECT_EQ(a.duplicates, 1u);
  EXPECT_EQ(a.rejected, 1u);
  std::set<NodeId> at_station, replayed;
  for (const NodeId id : station.graph().nodesOfRobot(robot))
    at_station.insert(SceneGraphProcessor::toRobotSide(id)->second);
  for (const auto& [id, node] : replay.graph().nodes()) replayed.insert(id);
  EXPECT_EQ(at_station, replayed);
  EXPECT_EQ(replay.graph().mesh().vertices.size(), station.robot(robot)->mesh.vertices.size());
}

// Robot b's state in `hostile` is what it is in `reference` (which had only robot b's stream):
// every node of b, its mesh, pose graph, deformation graph and descriptors.
void expectRobotUntouched(const SceneGraphProcessor& hostile, const SceneGraphProcessor& reference,
                          RobotId robot) {
  size_t nodes = 0;
  for (const auto& [id, node] : hostile.graph().nodes()) {
    if (SceneGraphProcessor::toRobotSide(id)->first != robot) continue;
    ++nodes;
    ASSERT_TRUE(reference.graph().hasNode(id)) << id.str();
    EXPECT_TRUE(node == reference.graph().getNode(id)) << id.str();
  }
  EXPECT_EQ(nodes, reference.graph().numNodes());
  const RobotFrontendState& x = *hostile.robot(robot);
  const RobotFrontendState& y = *reference.robot(robot);
  EXPECT_EQ(x.mesh, y.mesh);
  EXPECT_EQ(x.pose_graph, y.pose_graph);
  EXPECT_EQ(x.control_points, y.control_points);
  EXPECT_EQ(x.descriptors, y.descriptors);
}

// A hostile robot cannot make parent links form a cycle: a node's parent is the one neighbour of
// a higher layer, and a new parent edge replaces the old one. Edges object -> place -> room ->
// object leave the object one parent (the room), and every chain of parents goes up and ends.
// Robot b, mapping meanwhile, is untouched.
TEST(SceneGraphProcessor, ParentLinksCannotFormACycle) {
  const auto dataset = sim::simulateDataset(sim::presetConfig("tiny", 1).value());
  ASSERT_TRUE(dataset.ok());
  const std::vector<RobotUpdate>& b = dataset.value().streams[1];
  SceneGraphProcessor hostile, reference;
  RobotUpdate u = step(kA, 0);
  const NodeId place('p', 1), place2('p', 2), room('R', 1), object('O', 0);
  u.graph.nodes.push_back(makeNode(place, Layer::kPlaces, Eigen::Vector3d(0, 1, 0)));
  u.graph.nodes.push_back(makeNode(place2, Layer::kPlaces, Eigen::Vector3d(0, 2, 0)));
  u.graph.nodes.push_back(makeNode(room, Layer::kRooms, Eigen::Vector3d(0, 1, 1)));
  for (const auto& [x, y] : std::vector<std::pair<NodeId, NodeId>>{
           {object, place}, {place, room}, {room, object}, {place, place2}, {place2, place}})
    u.graph.edges.push_back({x, y, {}});
  for (size_t k = 0; k < b.size(); ++k) {
    if (k == b.size() / 2) {
      const UpdateReport report = hostile.process(u);
      EXPECT_EQ(report.outcome, UpdateOutcome::kApplied) << report.message;
    }
    ASSERT_EQ(hostile.process(b[k]).outcome, reference.process(b[k]).outcome);
  }
  const SceneGraph& g = hostile.graph();
  EXPECT_EQ(g.parent(NodeId::station('O', kA, 0)), NodeId::station('R', kA, 1));
  EXPECT_EQ(g.parent(NodeId::station('p', kA, 1)), NodeId::station('R', kA, 1));
  for (const auto& [id, node] : g.nodes()) {
    int steps = 0;
    for (std::optional<NodeId> at = id, up = g.parent(id); up; at = up, up = g.parent(*up)) {
      EXPECT_GT(layerLevel(g.getNode(*up).layer()), layerLevel(g.getNode(*at).layer()));
      ASSERT_LE(++steps, 4) << id.str();
    }
  }
  expectRobotUntouched(hostile, reference, kB);
}

// A robot that sends another robot's ids: its keyframes with the other's prefix are refused whole
// (logged with the robot and the update); its objects and places with the same ids as the other's
// are its own (station ids X@robot), and the other robot's map is untouched.
TEST(SceneGraphProcessor, IdsThatCollideWithAnotherRobots) {
  const auto dataset = sim::simulateDataset(sim::presetConfig("tiny", 1).value());
  ASSERT_TRUE(dataset.ok());
  const std::vector<RobotUpdate>& b = dataset.value().streams[1];
  std::vector<std::string> log;
  SceneGraphProcessor hostile({}, [&log](const std::string& line) { log.push_back(line); });
  SceneGraphProcessor reference;
  for (size_t k = 0; k < b.size(); ++k) {
    ASSERT_EQ(hostile.process(b[k]).outcome, reference.process(b[k]).outcome);
    if (k == 0) {
      RobotUpdate impostor = b[0];  // robot b's first update, sent as robot a's
      impostor.robot = kA;
      const UpdateReport report = hostile.process(impostor);
      EXPECT_EQ(report.outcome, UpdateOutcome::kRejected);
      EXPECT_NE(report.message.find("does not carry robot a's prefix"), std::string::npos)
          << report.message;
      // Robot a's own first update, its objects numbered as robot b's.
      RobotUpdate own = step(kA, 0);
      own.graph.nodes.clear();
      own.graph.nodes.push_back(keyframe(kA, 0, Eigen::Vector3d::Zero()));
      for (const Node& n : b[0].graph.nodes) {
        if (n.layer() == Layer::kObjects || n.layer() == Layer::kPlaces) {
          Node copy = n;
          copy.position += Eigen::Vector3d(100, 0, 0);
          own.graph.nodes.push_back(copy);
        }
      }
      own.graph.edges.clear();
      EXPECT_EQ(hostile.process(own).outcome, UpdateOutcome::kApplied);
    }
  }
  EXPECT_FALSE(log.empty());
  for (const Node& n : b[0].graph.nodes) {
    if (n.layer() != Layer::kObjects && n.layer() != Layer::kPlaces) continue;
    EXPECT_TRUE(hostile.graph().hasNode(*SceneGraphProcessor::toStation(kA, n.id)));
  }
  expectRobotUntouched(hostile, reference, kB);
}

}  // namespace
}  // namespace hydra_multi
