// Evaluation against a simulated dataset's ground truth: reading it back, scoring graphs whose
// answer is known, combining robot graphs, and clear errors on a broken dataset.

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <unistd.h>

#include "hydra_multi/eval/dataset_evaluation.h"
#include "hydra_multi/sim/dataset.h"

namespace hydra_multi {
namespace {

namespace fs = std::filesystem;

// The tiny dataset, written once for all tests here.
class DatasetEvaluation : public ::testing::Test {
 protected:
  static void SetUpTestSuite() {
    // One folder per process: ctest runs the tests of this suite in parallel processes.
    dir_ = new fs::path(fs::temp_directory_path() /
                        ("hydra_multi_test_eval_dataset_" + std::to_string(getpid())));
    fs::remove_all(*dir_);
    auto dataset = sim::simulateDataset(sim::presetConfig("tiny", 5).value());
    ASSERT_TRUE(dataset.ok()) << dataset.error();
    dataset_ = new sim::SimulatedDataset(std::move(dataset).value());
    ASSERT_TRUE(sim::writeDataset(*dataset_, dir_->string()).ok());
  }
  static void TearDownTestSuite() {
    fs::remove_all(*dir_);
    delete dir_;
    delete dataset_;
  }
  static fs::path* dir_;
  static sim::SimulatedDataset* dataset_;
};
fs::path* DatasetEvaluation::dir_ = nullptr;
sim::SimulatedDataset* DatasetEvaluation::dataset_ = nullptr;

TEST_F(DatasetEvaluation, ReadsTheGroundTruthBack) {
  auto truth = readDatasetGroundTruth(dir_->string());
  ASSERT_TRUE(truth.ok()) << truth.error();
  const DatasetGroundTruth& gt = truth.value();
  const sim::World& world = dataset_->sensed->world;
  ASSERT_EQ(gt.robots.size(), 2u);
  EXPECT_EQ(gt.objects.size(), world.objects.size());
  EXPECT_EQ(gt.room_ids.size(), world.rooms.size());
  EXPECT_EQ(gt.object_threshold_m, 1.0);
  EXPECT_FALSE(gt.gvd.empty());
  for (size_t r = 0; r < 2; ++r) {
    const sim::RobotRun& run = dataset_->runs[r];
    ASSERT_EQ(gt.trajectories.at(run.robot).poses.size(), run.truth.size());
    for (size_t k = 0; k < run.truth.size(); k += 7) {
      const Eigen::Isometry3d* T = gt.poseAt(run.robot, run.truth[k].time_ns);
      ASSERT_NE(T, nullptr);
      EXPECT_LT((T->translation() - run.truth[k].T_world_body.translation()).norm(), 1e-6);
    }
    EXPECT_TRUE(gt.start_poses.at(run.robot).isApprox(run.truth.front().T_world_body, 1e-9));
  }
}

// A graph made of the truth itself, in robot 0's frame, scores perfectly, also when moved as a
// whole (it is fitted to the truth by its keyframes first); objects moved alone by 3 m do not.
TEST_F(DatasetEvaluation, TruthScoresPerfectly) {
  const DatasetGroundTruth gt = readDatasetGroundTruth(dir_->string()).value();
  const Eigen::Isometry3d T_global_world = gt.worldFromGlobal().inverse();
  const auto build = [&](const Eigen::Vector3d& shift, const Eigen::Vector3d& object_shift) {
    SceneGraph graph;
    for (const sim::RobotRun& run : dataset_->runs) {
      for (size_t k = 0; k < run.truth.size(); ++k) {
        Node node = makeNode(NodeId(run.robot.prefix(), k), Layer::kAgents,
                             T_global_world * run.truth[k].T_world_body.translation() + shift);
        node.find<AgentAttributes>()->timestamp_ns = run.truth[k].time_ns;
        graph.addOrUpdateNode(node);
      }
    }
    uint64_t i = 0;
    for (const LabelledPoint& o : gt.objects) {
      Node node = makeNode(NodeId('O', i++), Layer::kObjects,
                           T_global_world * o.position + shift + object_shift);
      node.semantic()->label = o.label;
      graph.addOrUpdateNode(node);
    }
    for (size_t p = 0; p < gt.gvd.size(); p += 50)
      graph.addOrUpdateNode(
          makeNode(NodeId('p', p), Layer::kPlaces, T_global_world * gt.gvd[p] + shift));
    return graph;
  };
  const Eigen::Vector3d none = Eigen::Vector3d::Zero();
  const SceneGraphScore perfect = evaluateSceneGraph(build(none, none), gt);
  EXPECT_TRUE(perfect.aligned_by_trajectory);
  ASSERT_TRUE(perfect.ate_rmse_m.has_value());
  EXPECT_LT(*perfect.ate_rmse_m, 1e-6);
  EXPECT_DOUBLE_EQ(perfect.objects_found_pct.value(), 100.0);
  EXPECT_DOUBLE_EQ(perfect.objects_correct_pct.value(), 100.0);
  EXPECT_LT(perfect.places_position_error_m.value(), 1e-6);
  EXPECT_EQ(perfect.num_objects, gt.objects.size());
  EXPECT_EQ(perfect.num_rooms, 0u);
  EXPECT_FALSE(perfect.rooms_precision.has_value());

  const SceneGraphScore moved = evaluateSceneGraph(build(Eigen::Vector3d(3, 0, 0), none), gt);
  EXPECT_LT(*moved.ate_rmse_m, 1e-6);
  EXPECT_DOUBLE_EQ(moved.objects_found_pct.value(), 100.0);
  EXPECT_LT(moved.places_position_error_m.value(), 1e-6);
  const SceneGraphScore objects_off = evaluateSceneGraph(build(none, Eigen::Vector3d(3, 0, 0)), gt);
  EXPECT_LT(objects_off.objects_found_pct.value(), 30.0);
}

// Rooms: a room node whose places sit in one true room covers only that room's cells.
TEST_F(DatasetEvaluation, RoomsFromTheirPlaces) {
  const DatasetGroundTruth gt = readDatasetGroundTruth(dir_->string()).value();
  const Eigen::Isometry3d T_global_world = gt.worldFromGlobal().inverse();
  const sim::World& world = dataset_->sensed->world;
  SceneGraph graph;
  uint64_t place = 0;
  for (size_t r = 1; r < world.rooms.size(); ++r) {  // every room but the corridor
    const NodeId room('R', r);
    graph.addOrUpdateNode(makeNode(room, Layer::kRooms));
    const Eigen::Vector2d c = world.rooms[r].footprint.center();
    Node node = makeNode(NodeId('p', place++), Layer::kPlaces,
                         T_global_world * Eigen::Vector3d(c.x(), c.y(), 1.0));
    node.find<PlaceAttributes>()->distance = 1.0;
    graph.addOrUpdateNode(node);
    graph.addOrUpdateEdge(room, node.id);
  }
  const SceneGraphScore score = evaluateSceneGraph(graph, gt);
  EXPECT_EQ(score.num_rooms, world.rooms.size() - 1);
  EXPECT_DOUBLE_EQ(score.rooms_precision.value(), 1.0);  // each disc inside one room
  EXPECT_GT(score.rooms_recall.value(), 0.1);
  EXPECT_LT(score.rooms_recall.value(), 0.9);  // the discs do not fill the rooms
}

// Robot graphs with colliding ids combine into one, each node renamed to its robot's station id.
TEST_F(DatasetEvaluation, CombinesRobotGraphs) {
  const DatasetGroundTruth gt = readDatasetGroundTruth(dir_->string()).value();
  std::vector<std::pair<RobotId, SceneGraph>> graphs;
  size_t nodes = 0, vertices = 0;
  for (const RobotId robot : gt.robots) {
    auto replay = replayRobotGraph(gt, robot);
    ASSERT_TRUE(replay.ok()) << replay.error();
    nodes += replay.value().graph.numNodes();
    vertices += replay.value().graph.mesh().vertices.size();
    graphs.emplace_back(robot, std::move(replay.value().graph));
  }
  ASSERT_TRUE(graphs[0].second.hasNode(NodeId('O', 0)) && graphs[1].second.hasNode(NodeId('O', 0)));
  const Eigen::Isometry3d shift(Eigen::Translation3d(10, 0, 0));
  const SceneGraph combined = combineRobotGraphs(graphs, {{gt.robots[1], shift}});
  EXPECT_EQ(combined.numNodes(), nodes);
  EXPECT_EQ(combined.mesh().vertices.size(), vertices);
  const NodeId b0 = NodeId::station('O', gt.robots[1], 0);
  ASSERT_TRUE(combined.hasNode(b0));
  EXPECT_TRUE(combined.getNode(b0).position.isApprox(
      graphs[1].second.getNode(NodeId('O', 0)).position + Eigen::Vector3d(10, 0, 0)));
  for (const uint64_t v : combined.getNode(b0).find<ObjectAttributes>()->mesh_vertices)
    EXPECT_GE(v, graphs[0].second.mesh().vertices.size());
}

// The dataset's difficulty: odometry alone places objects worse than without drift.
TEST_F(DatasetEvaluation, DifficultyFigures) {
  auto difficulty = measureDatasetDifficulty(dir_->string());
  ASSERT_TRUE(difficulty.ok()) << difficulty.error();
  const DatasetDifficulty& d = difficulty.value();
  EXPECT_GT(d.odometry.ate_rmse_m.value(), 0.0);
  EXPECT_GT(d.no_drift.objects_found_pct.value(), 50.0);
  EXPECT_LE(d.odometry.objects_correct_pct.value(), d.no_drift.objects_correct_pct.value() + 1e-9);
  EXPECT_GT(d.top_pairs, 0u);
}

// A broken dataset: errors name the file.
TEST(DatasetErrors, NameTheFile) {
  const fs::path dir = fs::temp_directory_path() /
                       ("hydra_multi_test_broken_dataset_" + std::to_string(getpid()));
  fs::remove_all(dir);
  fs::create_directories(dir);
  auto missing = readDatasetGroundTruth(dir.string());
  ASSERT_FALSE(missing.ok());
  EXPECT_NE(missing.error().find("dataset.json"), std::string::npos);
  auto dataset = sim::simulateDataset(sim::presetConfig("tiny", 1).value());
  ASSERT_TRUE(dataset.ok());
  fs::remove_all(dir);
  ASSERT_TRUE(sim::writeDataset(dataset.value(), dir.string()).ok());
  { std::ofstream(dir / "gt" / "objects.json") << "{\"objects\": [{\"label\": 3}]}"; }
  auto broken = readDatasetGroundTruth(dir.string());
  ASSERT_FALSE(broken.ok());
  EXPECT_NE(broken.error().find("objects.json"), std::string::npos);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace hydra_multi
