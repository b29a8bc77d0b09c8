// One backend round end to end on the tiny team: frontend, loop closures, alignment, deformation
// graph, rooms; the result scored against the ground truth.

#include <gtest/gtest.h>
#include <unistd.h>

#include <filesystem>

#include "hydra_multi/backend/backend.h"
#include "hydra_multi/eval/dataset_evaluation.h"
#include "hydra_multi/frontend/loop_closure_detector.h"
#include "hydra_multi/sim/dataset.h"
#include "hydra_multi/station/station.h"

namespace hydra_multi {
namespace {

TEST(Backend, RoundOnTinyTeam) {
  namespace fs = std::filesystem;
  const fs::path dir =
      fs::temp_directory_path() / ("hydra_multi_test_backend_" + std::to_string(getpid()));
  fs::remove_all(dir);
  auto dataset = sim::simulateDataset(sim::presetConfig("tiny", 1).value());
  ASSERT_TRUE(dataset.ok());
  ASSERT_TRUE(sim::writeDataset(dataset.value(), dir.string()).ok());
  std::vector<RobotUpdate> updates;
  for (const auto& stream : dataset.value().streams)
    updates.insert(updates.end(), stream.begin(), stream.end());
  std::stable_sort(updates.begin(), updates.end(), [](const RobotUpdate& a, const RobotUpdate& b) {
    return a.time_ns < b.time_ns;
  });
  SceneGraphProcessor processor;
  LoopClosureDetector detector;
  for (const RobotUpdate& u : updates) {
    const UpdateReport report = processor.process(u);
    detector.update(processor, report.new_keyframes);
  }
  detector.flush(processor);
  const std::vector<PoseGraphEdge> inter = interRobotEdges(detector.loopClosures());
  std::vector<BackendRobot> robots;
  for (const RobotId r : processor.robots()) {
    const RobotFrontendState* s = processor.robot(r);
    robots.push_back({r, &s->pose_graph, &s->control_points, &s->control_point_edges, &s->mesh});
  }
  BackendOptions options;
  options.rooms.min_room_places = 5;  // tiny's rooms hold about 15 places each
  Backend backend(options);
  const BackendRoundReport report = backend.round(processor.graph(), robots, inter, RobotId(0));
  EXPECT_EQ(report.robots_aligned, 2u);
  EXPECT_GT(report.inter_robot_inliers, inter.size() / 2);
  EXPECT_GE(report.rooms, 1u);
  // The robots saw the same rooms: places and objects of both are merged.
  EXPECT_GT(report.merges_proposed, 10u);
  EXPECT_GT(report.merges_accepted, report.merges_proposed / 2);
  EXPECT_EQ(report.merges_undone, 0u);
  EXPECT_GT(backend.graph().mesh().vertices.size(), 5000u);

  const DatasetGroundTruth truth = readDatasetGroundTruth(dir.string()).value();
  const SceneGraphScore score = evaluateSceneGraph(backend.graph(), truth);
  EXPECT_EQ(score.matched_keyframes,
            dataset.value().runs[0].truth.size() + dataset.value().runs[1].truth.size());
  EXPECT_LT(score.ate_rmse_m.value(), 0.3);
  EXPECT_GT(score.objects_found_pct.value(), 70.0);
  EXPECT_GT(score.objects_correct_pct.value(), 70.0);
  EXPECT_GT(score.rooms_precision.value(), 0.2);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hydra_multi
