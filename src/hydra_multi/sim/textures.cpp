#include "hydra_multi/sim/textures.h"

#include <cmath>
#include <map>
#include <random>
#include <tuple>

namespace hydra_multi::sim {
namespace {

// Texture of one room in its own frame (origin at the footprint's centre, z up from the floor):
// points on the four walls of a w x d room.
std::vector<std::pair<Eigen::Vector3d, uint32_t>> sampleRoomTexture(double w, double d,
                                                                    const TextureOptions& options,
                                                                    std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<uint32_t> word(0, options.vocabulary - 1);
  std::vector<std::pair<Eigen::Vector3d, uint32_t>> points;
  // Walls: (start corner, direction, length).
  const std::vector<std::tuple<Eigen::Vector2d, Eigen::Vector2d, double>> walls = {
      {{-0.5 * w, -0.5 * d}, {1, 0}, w},
      {{0.5 * w, -0.5 * d}, {0, 1}, d},
      {{0.5 * w, 0.5 * d}, {-1, 0}, w},
      {{-0.5 * w, 0.5 * d}, {0, -1}, d}};
  for (const auto& [corner, direction, length] : walls) {
    const int count =
        static_cast<int>(std::round(options.points_per_m2 * length * options.wall_height));
    for (int i = 0; i < count; ++i) {
      const Eigen::Vector2d xy = corner + direction * (unit(rng) * length);
      points.push_back(
          {Eigen::Vector3d(xy.x(), xy.y(), unit(rng) * options.wall_height), word(rng)});
    }
  }
  return points;
}

// A corridor's texture that repeats every `period` metres along x: one tile of its two long
// walls, repeated, and texture of its own on the end walls.
std::vector<std::pair<Eigen::Vector3d, uint32_t>> sampleTiledTexture(double w, double d,
                                                                     double period,
                                                                     const TextureOptions& options,
                                                                     std::mt19937_64& rng) {
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  std::uniform_int_distribution<uint32_t> word(0, options.vocabulary - 1);
  std::vector<std::pair<Eigen::Vector3d, uint32_t>> tile;
  const int count =
      static_cast<int>(std::round(options.points_per_m2 * period * options.wall_height));
  for (const double y : {-0.5 * d, 0.5 * d}) {
    for (int i = 0; i < count; ++i)
      tile.push_back(
          {Eigen::Vector3d(unit(rng) * period, y, unit(rng) * options.wall_height), word(rng)});
  }
  std::vector<std::pair<Eigen::Vector3d, uint32_t>> points;
  for (double x0 = 0.0; x0 < w; x0 += period) {
    for (const auto& [p, wd] : tile) {
      if (x0 + p.x() <= w)
        points.push_back({Eigen::Vector3d(x0 + p.x() - 0.5 * w, p.y(), p.z()), wd});
    }
  }
  const int end_count =
      static_cast<int>(std::round(options.points_per_m2 * d * options.wall_height));
  for (const double x : {-0.5 * w, 0.5 * w}) {
    for (int i = 0; i < end_count; ++i)
      points.push_back(
          {Eigen::Vector3d(x, (unit(rng) - 0.5) * d, unit(rng) * options.wall_height), word(rng)});
  }
  return points;
}

}  // namespace

std::vector<TexturedPoint> generateTextures(const World& world, const TextureOptions& options) {
  std::mt19937_64 rng(options.seed);
  std::map<int, std::vector<std::pair<Eigen::Vector3d, uint32_t>>> shared;  // by layout id
  std::vector<TexturedPoint> textures;
  for (const Room& room : world.rooms) {
    const Eigen::Vector2d size = room.footprint.size();
    // In the room frame, x runs along the corridor and y away from the door (as furniture), so
    // a shared texture repeats the same way in every identical room.
    std::vector<std::pair<Eigen::Vector3d, uint32_t>> local;
    if (room.layout >= 0 && room.kind != RoomKind::kCorridor) {
      auto it = shared.find(room.layout);
      if (it == shared.end()) {
        it = shared.emplace(room.layout, sampleRoomTexture(size.x(), size.y(), options, rng)).first;
      }
      local = it->second;
    } else if (room.texture_period > 0.0) {
      local = sampleTiledTexture(size.x(), size.y(), room.texture_period, options, rng);
    } else {
      local = sampleRoomTexture(size.x(), size.y(), options, rng);
    }
    const Eigen::Isometry3d T_world_room = world.roomFrame(room);
    for (const auto& [p_room, word] : local)
      textures.push_back({T_world_room * p_room, word, room.id, room.floor});
  }
  return textures;
}

KeyframeDescriptor describeKeyframe(const std::vector<TexturedPoint>& textures,
                                    const FreeSpace& space, int floor,
                                    const Eigen::Isometry3d& T_world_body, NodeId keyframe,
                                    const SensorModel& sensor) {
  KeyframeDescriptor descriptor;
  descriptor.keyframe = keyframe;
  if (floor < 0 || static_cast<size_t>(floor) >= space.floors.size()) return descriptor;
  const FloorGrid& grid = space.floors[static_cast<size_t>(floor)];
  const Eigen::Vector2d eye = T_world_body.translation().head<2>();
  const Eigen::Vector2d forward = T_world_body.linear().col(0).head<2>().normalized();
  const double cos_half_fov = std::cos(0.5 * sensor.horizontal_fov_deg * M_PI / 180.0);
  const Eigen::Isometry3d T_body_world = T_world_body.inverse();
  std::map<uint32_t, double> counts;
  for (const TexturedPoint& point : textures) {
    if (point.floor != floor) continue;  // other floors are behind the slabs
    const Eigen::Vector2d to = point.position.head<2>() - eye;
    const double distance = to.norm();
    if (distance > sensor.range || distance < 1e-6 || forward.dot(to) < cos_half_fov * distance) {
      continue;
    }
    // Wall points sit on the wall's face: step a little back towards the eye for the sight line.
    const Eigen::Vector2d near_face =
        point.position.head<2>() - 0.6 * grid.resolution * to / distance;
    if (!lineOfSight(grid, eye, near_face)) continue;
    descriptor.keypoints.push_back({(T_body_world * point.position).cast<float>(), point.word});
    counts[point.word] += 1.0;
  }
  double total = 0.0;
  for (const auto& [word, count] : counts) total += count;
  for (const auto& [word, count] : counts) {
    descriptor.bow.push_back({word, static_cast<float>(count / total)});
  }
  return descriptor;
}

double bowSimilarity(const std::vector<BowEntry>& a, const std::vector<BowEntry>& b) {
  std::map<uint32_t, double> difference;
  for (const BowEntry& e : a) difference[e.word] += e.weight;
  for (const BowEntry& e : b) difference[e.word] -= e.weight;
  double l1 = 0.0;
  for (const auto& [word, d] : difference) l1 += std::abs(d);
  return 1.0 - 0.5 * l1;
}

}  // namespace hydra_multi::sim
