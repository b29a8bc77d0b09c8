#include <gtest/gtest.h>

#include <algorithm>

#include "hydra_multi/sim/building_generator.h"
#include "hydra_multi/sim/textures.h"

namespace hydra_multi::sim {
namespace {

// The body pose at the same place of a room's own frame: 1.5 m in from the door, looking away
// from it at the back wall.
Eigen::Isometry3d bodyInRoom(const World& world, const Room& room) {
  const Eigen::Isometry3d T_world_room = world.roomFrame(room);
  Eigen::Isometry3d T_room_body = Eigen::Isometry3d::Identity();
  T_room_body.translation() << 0.0, -0.5 * room.footprint.size().y() + 1.5, 1.0;
  T_room_body.linear() = Eigen::AngleAxisd(0.5 * M_PI, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T_world_room * T_room_body;
}

struct Views {
  double same_side = 0, across = 0;
};

// Similarity of the views from corresponding poses in rooms 1 and 2 (same side of the corridor)
// and rooms 1 and 5 (across it).
Views corresponding(bool identical) {
  BuildingOptions options;
  options.room_kind = RoomKind::kStudentRoom;
  options.rooms_per_side = 4;
  options.identical_rooms = identical;
  const World world = generateBuilding(options).value();
  const FreeSpace space = computeFreeSpace(world);
  const auto textures = generateTextures(world);
  const auto view = [&](int room) {
    return describeKeyframe(textures, space, 0, bodyInRoom(world, world.room(room)),
                            NodeId('a', 0));
  };
  const KeyframeDescriptor a = view(1), b = view(2), c = view(5);
  EXPECT_GT(a.keypoints.size(), 20u);
  return {bowSimilarity(a.bow, b.bow), bowSimilarity(a.bow, c.bow)};
}

// Identical rooms look alike from corresponding poses (aliasing); other rooms do not.
TEST(Textures, IdenticalRoomsAlias) {
  const Views identical = corresponding(true);
  EXPECT_GT(identical.same_side, 0.9);
  EXPECT_GT(identical.across, 0.9);
  const Views distinct = corresponding(false);
  EXPECT_LT(distinct.same_side, 0.3);
  EXPECT_LT(distinct.across, 0.3);
}

// Keypoints are textured points seen from the body: mapped back to the world they land on one.
TEST(Textures, KeypointsAreInTheBodyFrame) {
  BuildingOptions options;
  const World world = generateBuilding(options).value();
  const FreeSpace space = computeFreeSpace(world);
  const auto textures = generateTextures(world);
  const Eigen::Isometry3d T_world_body = bodyInRoom(world, world.room(3));
  const KeyframeDescriptor d = describeKeyframe(textures, space, 0, T_world_body, NodeId('a', 7));
  ASSERT_FALSE(d.keypoints.empty());
  EXPECT_EQ(d.keyframe, NodeId('a', 7));
  for (const Keypoint& k : d.keypoints) {
    const Eigen::Vector3d p_world = T_world_body * k.position.cast<double>();
    double nearest = 1e9;
    for (const TexturedPoint& t : textures) {
      if (t.word == k.word) nearest = std::min(nearest, (t.position - p_world).norm());
    }
    EXPECT_LT(nearest, 1e-5);
    EXPECT_GT(k.position.x(), 0.0f);  // in front of the camera
  }
  double total = 0.0;
  for (const BowEntry& e : d.bow) total += e.weight;
  EXPECT_NEAR(total, 1.0, 1e-5);
}

TEST(Textures, BowSimilarityEnds) {
  const std::vector<BowEntry> a = {{1, 0.5f}, {2, 0.5f}}, b = {{3, 1.0f}};
  EXPECT_NEAR(bowSimilarity(a, a), 1.0, 1e-12);
  EXPECT_NEAR(bowSimilarity(a, b), 0.0, 1e-12);
  EXPECT_NEAR(bowSimilarity(a, {{1, 1.0f}}), 0.5, 1e-12);
}

}  // namespace
}  // namespace hydra_multi::sim
