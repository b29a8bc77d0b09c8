#include <gtest/gtest.h>

#include "hydra_multi/eval/scene_metrics.h"

namespace hydra_multi {
namespace {

// Hand-made: two chairs and a table are true; the estimate has one chair 0.5 m off, one chair 3 m
// off, a table labelled as a chair, and a sofa. At 1 m: found 1/3, correct 1/4.
TEST(SceneMetrics, ObjectsFoundAndCorrect) {
  const uint32_t chair = 5, table = 7, sofa = 9;
  const std::vector<LabelledPoint> truth = {
      {chair, {0, 0, 0}}, {chair, {10, 0, 0}}, {table, {5, 5, 0}}};
  const std::vector<LabelledPoint> estimated = {
      {chair, {0.5, 0, 0}}, {chair, {13, 0, 0}}, {chair, {5, 5, 0}}, {sofa, {20, 0, 0}}};
  const ObjectMetrics at1 = objectMetrics(estimated, truth, 1.0);
  EXPECT_NEAR(*at1.found_pct, 100.0 / 3.0, 1e-12);
  EXPECT_NEAR(*at1.correct_pct, 25.0, 1e-12);
  // At 3 m the second chair counts too: found 2/3, correct 2/4.
  const ObjectMetrics at3 = objectMetrics(estimated, truth, 3.0);
  EXPECT_NEAR(*at3.found_pct, 200.0 / 3.0, 1e-12);
  EXPECT_NEAR(*at3.correct_pct, 50.0, 1e-12);
  EXPECT_FALSE(objectMetrics({}, truth, 1.0).correct_pct.has_value());
  EXPECT_EQ(*objectMetrics({}, truth, 1.0).found_pct, 0.0);
  EXPECT_FALSE(objectMetrics(estimated, {}, 1.0).found_pct.has_value());
}

// The same estimate, object by object at 1 m, plus a second copy of the first chair: the first
// chair correct, its copy a duplicate (still counted correct by the paper's share), the chair 3 m
// off misplaced, the table labelled chair a wrong label, the sofa misplaced.
TEST(SceneMetrics, ObjectVerdicts) {
  const uint32_t chair = 5, table = 7, sofa = 9;
  const std::vector<LabelledPoint> truth = {
      {chair, {0, 0, 0}}, {chair, {10, 0, 0}}, {table, {5, 5, 0}}};
  const std::vector<LabelledPoint> estimated = {{chair, {0.5, 0, 0}},
                                                {chair, {13, 0, 0}},
                                                {chair, {5, 5, 0.2}},
                                                {sofa, {20, 0, 0}},
                                                {chair, {-0.3, 0, 0}}};
  const ObjectMetrics m = objectMetrics(estimated, truth, 1.0);
  EXPECT_EQ(m.correct, 2u);
  EXPECT_EQ(m.duplicates, 1u);
  EXPECT_EQ(m.wrong_label, 1u);
  EXPECT_EQ(m.misplaced, 2u);
  EXPECT_NEAR(*m.correct_pct, 40.0, 1e-12);  // duplicates count as correct
  using Kind = ObjectVerdict::Kind;
  ASSERT_EQ(m.verdicts.size(), estimated.size());
  EXPECT_EQ(m.verdicts[0].kind, Kind::kCorrect);
  EXPECT_EQ(m.verdicts[0].true_index, 0);
  EXPECT_NEAR(m.verdicts[0].distance_m, 0.5, 1e-12);
  EXPECT_EQ(m.verdicts[1].kind, Kind::kMisplaced);
  EXPECT_EQ(m.verdicts[1].true_index, -1);
  EXPECT_EQ(m.verdicts[2].kind, Kind::kWrongLabel);
  EXPECT_EQ(m.verdicts[2].true_index, 2);
  EXPECT_NEAR(m.verdicts[2].distance_m, 0.2, 1e-12);
  EXPECT_EQ(m.verdicts[3].kind, Kind::kMisplaced);
  EXPECT_EQ(m.verdicts[4].kind, Kind::kDuplicate);
  EXPECT_EQ(m.verdicts[4].true_index, 0);
  EXPECT_STREQ(toString(Kind::kWrongLabel), "wrong_label");
}

// Places at known distances from a line of GVD voxels.
TEST(SceneMetrics, PlacesPositionError) {
  std::vector<Eigen::Vector3d> gvd;
  for (int i = 0; i <= 10; ++i) gvd.emplace_back(i, 0, 0);
  const std::vector<Eigen::Vector3d> places = {{2, 0.3, 0}, {5, 0, 0.1}, {12, 0, 0}};
  EXPECT_NEAR(*placesPositionError(places, gvd), (0.3 + 0.1 + 2.0) / 3.0, 1e-12);
  EXPECT_FALSE(placesPositionError({}, gvd).has_value());
  EXPECT_FALSE(placesPositionError(places, {}).has_value());
}

// Two true rooms of 10 voxels; the estimate splits the first in 6 + 4 and swallows the second
// with 5 voxels of the first's: precision (1 + 1 + 10/15) / 3, recall (6/10 + 10/10) / 2.
TEST(SceneMetrics, RoomsPrecisionRecall) {
  std::vector<Eigen::Vector3i> room_a, room_b;
  for (int i = 0; i < 10; ++i) {
    room_a.emplace_back(i, 0, 0);
    room_b.emplace_back(i, 5, 0);
  }
  const std::vector<Eigen::Vector3i> part1(room_a.begin(), room_a.begin() + 6);
  const std::vector<Eigen::Vector3i> part2(room_a.begin() + 6, room_a.end());
  std::vector<Eigen::Vector3i> merged = room_b;
  merged.insert(merged.end(), room_a.begin(), room_a.begin() + 5);
  const RoomMetrics m = roomMetrics({part1, part2, merged}, {room_a, room_b});
  EXPECT_NEAR(*m.precision, (1.0 + 1.0 + 10.0 / 15.0) / 3.0, 1e-12);
  EXPECT_NEAR(*m.recall, (6.0 / 10.0 + 1.0) / 2.0, 1e-12);
  const RoomMetrics perfect = roomMetrics({room_b, room_a}, {room_a, room_b});
  EXPECT_DOUBLE_EQ(*perfect.precision, 1.0);
  EXPECT_DOUBLE_EQ(*perfect.recall, 1.0);
  EXPECT_FALSE(roomMetrics({}, {room_a}).precision.has_value());
}

TEST(SceneMetrics, VoxelKeysFloor) {
  EXPECT_EQ(voxelKey({0.25, -0.25, 1.0}, 0.5), Eigen::Vector3i(0, -1, 2));
}

}  // namespace
}  // namespace hydra_multi
