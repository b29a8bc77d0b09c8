// Loop-closure detection on a simulated team: the two robots of `tiny` overlap, and the detector
// finds loop closures between them that the ground truth confirms.

#include <gtest/gtest.h>

#include <algorithm>

#include "hydra_multi/frontend/loop_closure_detector.h"
#include "hydra_multi/sim/dataset.h"

namespace hydra_multi {
namespace {

TEST(LoopClosureDetector, FindsTrueInterRobotClosuresOnTiny) {
  auto dataset = sim::simulateDataset(sim::presetConfig("tiny", 1).value());
  ASSERT_TRUE(dataset.ok());
  const sim::SimulatedDataset& d = dataset.value();
  // Arrival order: by time, as the station's replay does.
  std::vector<RobotUpdate> updates;
  for (const auto& stream : d.streams) updates.insert(updates.end(), stream.begin(), stream.end());
  std::stable_sort(updates.begin(), updates.end(), [](const RobotUpdate& a, const RobotUpdate& b) {
    return a.time_ns < b.time_ns;
  });
  SceneGraphProcessor processor;
  LoopClosureDetector detector;
  size_t found_online = 0;
  for (const RobotUpdate& u : updates) {
    const UpdateReport report = processor.process(u);
    ASSERT_EQ(report.outcome, UpdateOutcome::kApplied) << report.message;
    found_online += detector.update(processor, report.new_keyframes).size();
  }
  detector.flush(processor);
  EXPECT_GT(found_online, 0u);  // found while the robots were still sending
  EXPECT_EQ(detector.keyframesPending(), 0u);
  size_t inter = 0, correct = 0;
  for (const DetectedLoopClosure& c : detector.loopClosures()) {
    // The truth: keyframe index k of robot r is d.runs[r].truth[k].
    const auto truthOf = [&](RobotId robot, NodeId station) {
      return d.runs[robot.index()].truth[station.index()].T_world_body;
    };
    const Eigen::Isometry3d T_true =
        truthOf(c.robot_a, c.keyframe_a).inverse() * truthOf(c.robot_b, c.keyframe_b);
    const Eigen::Isometry3d error = T_true.inverse() * c.T_a_b;
    const bool ok = error.translation().norm() < 1.0 &&
                    Eigen::AngleAxisd(error.linear()).angle() < 10.0 * M_PI / 180.0;
    EXPECT_GE(c.inliers, 5u);
    EXPECT_GT(c.information(0, 0), 0.0);
    if (c.interRobot()) {
      ++inter;
      correct += ok;
    } else {
      // Same-robot closures only between keyframes far apart in time.
      const int64_t ta = d.runs[c.robot_a.index()].truth[c.keyframe_a.index()].time_ns;
      const int64_t tb = d.runs[c.robot_b.index()].truth[c.keyframe_b.index()].time_ns;
      EXPECT_GE(std::llabs(ta - tb), 30'000'000'000);
    }
  }
  EXPECT_GE(inter, 10u);
  EXPECT_GE(double(correct), 0.8 * double(inter));
  // Every verified match holds some information; the support per inter-robot closure is what
  // lies beyond its layer's typical match, so some have none and some have more.
  const std::vector<double> support = interRobotSupport(detector.loopClosures());
  ASSERT_EQ(support.size(), inter);
  for (const DetectedLoopClosure& c : detector.loopClosures()) EXPECT_GT(c.distinctiveness, 0.0);
  EXPECT_GT(std::count(support.begin(), support.end(), 0.0), 0);
  EXPECT_GT(*std::max_element(support.begin(), support.end()), 0.0);
}

struct ObjectClosureCounts {
  size_t found = 0, correct = 0;  ///< correct: within 1 m and 10 degrees of the truth
  size_t turned = 0;              ///< at the right place (within 3 m) but turned by over 5 degrees
};

// Replays a simulated team through a processor and a detector with `options` and checks its
// inter-robot object loop closures against the truth.
ObjectClosureCounts interRobotObjectClosures(const sim::SimulatedDataset& d,
                                             const LoopClosureOptions& options) {
  std::vector<RobotUpdate> updates;
  for (const auto& stream : d.streams) updates.insert(updates.end(), stream.begin(), stream.end());
  std::stable_sort(updates.begin(), updates.end(), [](const RobotUpdate& a, const RobotUpdate& b) {
    return a.time_ns < b.time_ns;
  });
  SceneGraphProcessor processor;
  LoopClosureDetector detector(options);
  for (const RobotUpdate& u : updates)
    detector.update(processor, processor.process(u).new_keyframes);
  detector.flush(processor);
  ObjectClosureCounts counts;
  for (const DetectedLoopClosure& c : detector.loopClosures()) {
    if (!c.interRobot() || c.source != DetectedLoopClosure::Source::kObjects) continue;
    const auto truthOf = [&](RobotId robot, NodeId station) {
      return d.runs[robot.index()].truth[station.index()].T_world_body;
    };
    const Eigen::Isometry3d error =
        (truthOf(c.robot_a, c.keyframe_a).inverse() * truthOf(c.robot_b, c.keyframe_b)).inverse() *
        c.T_a_b;
    const double meters = error.translation().norm();
    const double degrees = Eigen::AngleAxisd(error.linear()).angle() * 180.0 / M_PI;
    ++counts.found;
    counts.correct += meters < 1.0 && degrees < 10.0;
    counts.turned += meters < 3.0 && degrees > 5.0;
  }
  return counts;
}

// A robot's objects keep the drift of the moment it mapped them; on dorm-2 seed 1 robot a drifts
// 2.8 % and passes its rooms twice. An object loop closure tied to the keyframes that described
// it can then be turned by the drift between the passes (the wrong loop closures GNC kept there);
// tied to the keyframes that mapped the registered objects, none at the right place is.
TEST(LoopClosureDetector, ObjectClosuresJoinTheKeyframesThatMappedTheObjects) {
  auto dataset = sim::simulateDataset(sim::presetConfig("dorm-2", 1).value());
  ASSERT_TRUE(dataset.ok());
  LoopClosureOptions options;
  options.anchor_objects = false;
  const ObjectClosureCounts described = interRobotObjectClosures(dataset.value(), options);
  options.anchor_objects = true;
  const ObjectClosureCounts mapped = interRobotObjectClosures(dataset.value(), options);
  ASSERT_GT(described.found, 0u);
  ASSERT_GT(mapped.found, 0u);
  EXPECT_GT(described.turned, 0u);
  EXPECT_EQ(mapped.turned, 0u);
  EXPECT_GE(mapped.correct, described.correct);
}

DetectedLoopClosure closure(uint8_t robot_a, uint8_t robot_b, DetectedLoopClosure::Source source,
                            size_t inliers, double distinctiveness) {
  DetectedLoopClosure c;
  c.robot_a = RobotId(robot_a);
  c.robot_b = RobotId(robot_b);
  c.source = source;
  c.inliers = inliers;
  c.distinctiveness = distinctiveness;
  return c;
}

// Support: distinctiveness beyond the median per inlier of the closure's own layer, times its
// inliers; never below zero; intra-robot closures neither count in the median nor get a support.
TEST(LoopClosureDetector, InterRobotSupportIsDistinctivenessBeyondTheTypicalMatch) {
  using S = DetectedLoopClosure::Source;
  const std::vector<DetectedLoopClosure> closures = {
      closure(0, 1, S::kObjects, 10, 20.0),  // 2.0 per inlier
      closure(0, 1, S::kObjects, 5, 15.0),   // 3.0; the median of 2, 3 and 1 is 2
      closure(0, 0, S::kObjects, 5, 500.0),  // intra-robot: skipped
      closure(1, 0, S::kObjects, 4, 4.0),    // 1.0
      closure(0, 1, S::kVisual, 20, 30.0),   // 1.5 per inlier, the only visual one
  };
  const std::vector<double> support = interRobotSupport(closures);
  ASSERT_EQ(support.size(), 4u);
  EXPECT_DOUBLE_EQ(support[0], 0.0);          // 20 - 2 * 10
  EXPECT_DOUBLE_EQ(support[1], 15.0 - 10.0);  // 15 - 2 * 5
  EXPECT_DOUBLE_EQ(support[2], 0.0);          // 4 - 2 * 4 < 0
  EXPECT_DOUBLE_EQ(support[3], 0.0);          // the median itself
  EXPECT_TRUE(interRobotSupport({}).empty());
}

}  // namespace
}  // namespace hydra_multi
