#pragma once
// Visual texture of a world: points on the rooms' walls, each with a visual word id, and the
// keyframe descriptors a robot's camera makes of them (the robot update's KeyframeDescriptor: a
// sparse bag-of-words vector and 3D keypoints with word ids, in the body frame).
//
// Rooms that share a furniture layout (World::Room::layout) also share their wall texture in the
// room frame, so two identical rooms look the same from corresponding poses: the perceptual
// aliasing that makes most visual loop closures of the paper's Simmons data wrong.

#include <cstdint>
#include <vector>

#include "hydra_multi/dsg/robot_update.h"
#include "hydra_multi/sim/visibility.h"

namespace hydra_multi::sim {

struct TexturedPoint {
  Eigen::Vector3d position = Eigen::Vector3d::Zero();  ///< world frame
  uint32_t word = 0;
  int room = 0;
  int floor = 0;
};

struct TextureOptions {
  double points_per_m2 = 2.0;  ///< on wall surfaces
  uint32_t vocabulary = 1000;  ///< distinct visual words
  double wall_height = 2.5;    ///< textured up to this height above the floor (m)
  uint64_t seed = 1;
};

/// Textured points on the walls of every room: rooms that share a layout share their texture,
/// and a corridor with a texture period (World::Room) repeats its own along its length.
std::vector<TexturedPoint> generateTextures(const World& world, const TextureOptions& options = {});

/// The descriptor of a keyframe: the textured points within the sensor's range and field of view
/// and in line of sight, as keypoints in the body frame, and their word histogram normalized to
/// unit L1 norm.
KeyframeDescriptor describeKeyframe(const std::vector<TexturedPoint>& textures,
                                    const FreeSpace& space, int floor,
                                    const Eigen::Isometry3d& T_world_body, NodeId keyframe,
                                    const SensorModel& sensor = {});

/// 1 - half the L1 distance of two normalized bag-of-words vectors: 1 identical, 0 disjoint.
double bowSimilarity(const std::vector<BowEntry>& a, const std::vector<BowEntry>& b);

}  // namespace hydra_multi::sim
