#include <gtest/gtest.h>

#include <map>
#include <set>

#include "hydra_multi/sim/building_generator.h"
#include "hydra_multi/sim/exploration.h"
#include "hydra_multi/sim/object_detection.h"

namespace hydra_multi::sim {
namespace {

struct Tour {
  World world;
  FreeSpace space;
  std::vector<StampedPose> keyframes;
};

Tour touredRoom1() {
  BuildingOptions options;
  options.rooms_per_side = 4;
  Tour run{generateBuilding(options).value(), {}, {}};
  run.space = computeFreeSpace(run.world);
  const FloorGrid& g = run.space.floors[0];
  const auto tour = planRoomTour(run.world, g, roomStandpoint(g, 0).value(), {1});
  EXPECT_TRUE(tour.ok()) << tour.error();
  run.keyframes = sampleTrajectory(tour.value(), 0.0, 0);
  return run;
}

// Without misses, confusion or noise, the detections are exactly the objects seen from two
// keyframes or more, with their true labels and centroids; a robot never sees into room 3.
TEST(ObjectDetection, DetectsWhatWasSeen) {
  const Tour run = touredRoom1();
  DetectionOptions perfect;
  perfect.miss_probability = perfect.confusion_probability = perfect.position_sigma = 0.0;
  const auto detected = detectObjects(run.world, run.space, 0, run.keyframes, {}, perfect);
  std::map<int, int> views;
  for (const StampedPose& k : run.keyframes) {
    for (const int id : visibleObjects(run.world, run.space, 0, k.T_world_body)) ++views[id];
  }
  std::set<int> expected;
  for (const auto& [id, n] : views) {
    if (n >= 2) expected.insert(id);
  }
  std::set<int> got;
  for (const DetectedObject& d : detected) {
    got.insert(d.true_id);
    const ObjectInstance& truth = run.world.objects.at(static_cast<size_t>(d.true_id));
    EXPECT_EQ(d.label, truth.label);
    EXPECT_LT((d.centroid - truth.T_world_object.translation()).norm(), 1e-12);
    EXPECT_TRUE(d.box.contains(d.centroid));
    EXPECT_NE(run.world.objects[static_cast<size_t>(d.true_id)].room, 3);
  }
  EXPECT_EQ(got, expected);
  EXPECT_GE(got.size(), 3u);
}

// Misses and confusions at their extremes, and the same mistakes for the same seed.
TEST(ObjectDetection, MissesConfusionsAndSeeds) {
  const Tour run = touredRoom1();
  DetectionOptions all_missed;
  all_missed.miss_probability = 1.0;
  EXPECT_TRUE(detectObjects(run.world, run.space, 0, run.keyframes, {}, all_missed).empty());

  DetectionOptions confused;
  confused.miss_probability = 0.0;
  confused.confusion_probability = 1.0;
  for (const DetectedObject& d :
       detectObjects(run.world, run.space, 0, run.keyframes, {}, confused)) {
    EXPECT_EQ(d.label, confusableLabel(run.world.objects.at(static_cast<size_t>(d.true_id)).label));
  }
  EXPECT_EQ(confusableLabel(6), 7u);    // desk looks like a table
  EXPECT_EQ(confusableLabel(15), 15u);  // a refrigerator looks like nothing else

  DetectionOptions noisy;
  noisy.miss_probability = 0.5;
  const auto a = detectObjects(run.world, run.space, 0, run.keyframes, {}, noisy);
  const auto b = detectObjects(run.world, run.space, 0, run.keyframes, {}, noisy);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_EQ(a[i].true_id, b[i].true_id);
    EXPECT_EQ(a[i].centroid, b[i].centroid);
  }
}

}  // namespace
}  // namespace hydra_multi::sim
