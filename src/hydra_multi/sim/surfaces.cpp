#include "hydra_multi/sim/surfaces.h"

#include <algorithm>
#include <cmath>

namespace hydra_multi::sim {
namespace {

constexpr uint32_t kWall = 1, kFloor = 2, kCeiling = 3;
constexpr uint32_t kNone = UINT32_MAX;

// Adds a grid of vertices spanning origin + s * u + t * v for s in [0, |u|], t in [0, |v|] (u, v
// the patch's edge vectors); `keep` may drop vertices (door openings). Triangles join the grid
// cells whose four corners were kept.
template <typename Keep>
void addPatch(WorldMesh& mesh, const Eigen::Vector3d& origin, const Eigen::Vector3d& u,
              const Eigen::Vector3d& v, double spacing, SurfaceVertex prototype, Keep keep) {
  const int nu = std::max(1, static_cast<int>(std::ceil(u.norm() / spacing)));
  const int nv = std::max(1, static_cast<int>(std::ceil(v.norm() / spacing)));
  std::vector<uint32_t> index((nu + 1) * (nv + 1), kNone);
  for (int j = 0; j <= nv; ++j) {
    for (int i = 0; i <= nu; ++i) {
      const Eigen::Vector3d p = origin + u * (double(i) / nu) + v * (double(j) / nv);
      if (!keep(p)) continue;
      prototype.position = p;
      index[j * (nu + 1) + i] = static_cast<uint32_t>(mesh.vertices.size());
      mesh.vertices.push_back(prototype);
    }
  }
  for (int j = 0; j < nv; ++j) {
    for (int i = 0; i < nu; ++i) {
      const uint32_t a = index[j * (nu + 1) + i], b = index[j * (nu + 1) + i + 1];
      const uint32_t c = index[(j + 1) * (nu + 1) + i + 1], d = index[(j + 1) * (nu + 1) + i];
      if (a == kNone || b == kNone || c == kNone || d == kNone) continue;
      mesh.faces.push_back({a, b, c});
      mesh.faces.push_back({a, c, d});
    }
  }
}

}  // namespace

WorldMesh generateSurfaces(const World& world, const SurfaceOptions& options) {
  WorldMesh mesh;
  const double s = options.spacing;
  const auto all = [](const Eigen::Vector3d&) { return true; };
  for (const Room& room : world.rooms) {
    const Floor& floor = world.floors.at(static_cast<size_t>(room.floor));
    const Rect& f = room.footprint;
    const double z = floor.z, h = floor.height;
    const Eigen::Vector3d lo(f.min.x(), f.min.y(), z);
    const Eigen::Vector3d dx(f.size().x(), 0, 0), dy(0, f.size().y(), 0), up(0, 0, h);
    SurfaceVertex structure;
    structure.floor = room.floor;
    structure.room = room.id;
    structure.label = kFloor;
    addPatch(mesh, lo, dx, dy, s, structure, all);
    structure.label = kCeiling;
    addPatch(mesh, lo + up, dx, dy, s, structure, all);
    // Walls: the four sides of the footprint, without the door openings in them.
    structure.label = kWall;
    const auto notDoor = [&](const Eigen::Vector3d& p) {
      if (p.z() > z + options.door_height) return true;
      for (const Door& door : world.doors) {
        if (door.floor != room.floor || (door.room_a != room.id && door.room_b != room.id))
          continue;
        if (std::abs(p.x() - door.center.x()) < 0.5 * door.width &&
            std::abs(p.y() - door.center.y()) < 0.5)
          return false;
      }
      return true;
    };
    const Eigen::Vector3d corners[4] = {lo, lo + dx, lo + dx + dy, lo + dy};
    for (int k = 0; k < 4; ++k) {
      addPatch(mesh, corners[k], corners[(k + 1) % 4] - corners[k], up, s, structure, notDoor);
    }
  }
  for (const ObjectInstance& object : world.objects) {
    SurfaceVertex prototype;
    prototype.label = object.label;
    prototype.room = object.room;
    prototype.floor = world.room(object.room).floor;
    prototype.object = object.id;
    // Top and four sides of the box, in the object frame (centred, z from -size/2).
    const Eigen::Vector3d e = object.size, half = 0.5 * e;
    const Eigen::Matrix3d R = object.T_world_object.linear();
    const Eigen::Vector3d t = object.T_world_object.translation();
    const auto world_point = [&](const Eigen::Vector3d& p) { return Eigen::Vector3d(R * p + t); };
    const Eigen::Vector3d ex = R * Eigen::Vector3d(e.x(), 0, 0),
                          ey = R * Eigen::Vector3d(0, e.y(), 0),
                          ez = R * Eigen::Vector3d(0, 0, e.z());
    const Eigen::Vector3d base = world_point(-half);
    addPatch(mesh, base + ez, ex, ey, s, prototype, all);  // top
    addPatch(mesh, base, ex, ez, s, prototype, all);
    addPatch(mesh, base + ey, ex, ez, s, prototype, all);
    addPatch(mesh, base, ey, ez, s, prototype, all);
    addPatch(mesh, base + ex, ey, ez, s, prototype, all);
  }
  return mesh;
}

}  // namespace hydra_multi::sim
