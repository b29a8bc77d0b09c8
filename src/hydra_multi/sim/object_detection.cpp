#include "hydra_multi/sim/object_detection.h"

#include <map>
#include <random>

namespace hydra_multi::sim {

uint32_t confusableLabel(uint32_t label) {
  // Look-alike classes of defaultSemanticClasses(): desk/table, shelf/cabinet, wardrobe/shelf,
  // chair/sofa, lamp/plant, monitor/printer.
  static const std::map<uint32_t, uint32_t> kConfusion = {{6, 7},   {7, 6},   {10, 17}, {17, 10},
                                                          {11, 10}, {5, 8},   {8, 5},   {14, 12},
                                                          {12, 14}, {13, 20}, {20, 13}};
  const auto it = kConfusion.find(label);
  return it == kConfusion.end() ? label : it->second;
}

std::vector<DetectedObject> detectObjects(const World& world, const FreeSpace& space, int floor,
                                          const std::vector<StampedPose>& keyframes,
                                          const SensorModel& sensor,
                                          const DetectionOptions& options) {
  return detectObjects(world, space, std::vector<int>(keyframes.size(), floor), keyframes, sensor,
                       options);
}

std::vector<DetectedObject> detectObjects(const World& world, const FreeSpace& space,
                                          const std::vector<int>& floors,
                                          const std::vector<StampedPose>& keyframes,
                                          const SensorModel& sensor,
                                          const DetectionOptions& options) {
  std::map<int, int> views;
  std::map<int, size_t> completed_at;
  for (size_t k = 0; k < keyframes.size() && k < floors.size(); ++k) {
    for (const int id :
         visibleObjects(world, space, floors[k], keyframes[k].T_world_body, sensor)) {
      if (++views[id] == options.min_views) completed_at[id] = k;
    }
  }
  std::vector<DetectedObject> detected;
  for (const auto& [id, k] : completed_at) {
    // One generator per object: its fate does not depend on which other objects were seen.
    std::mt19937_64 rng(options.seed * 1000003u + static_cast<uint64_t>(id));
    std::uniform_real_distribution<double> unit(0.0, 1.0);
    std::normal_distribution<double> gauss(0.0, options.position_sigma);
    const bool missed = unit(rng) < options.miss_probability;
    const bool confused = unit(rng) < options.confusion_probability;
    const Eigen::Vector3d noise(gauss(rng), gauss(rng), gauss(rng));
    if (missed) continue;
    const ObjectInstance& object = world.objects.at(static_cast<size_t>(id));
    DetectedObject d;
    d.true_id = id;
    d.label = confused ? confusableLabel(object.label) : object.label;
    d.centroid = object.T_world_object.translation() + noise;
    // Axis-aligned box of the (yawed) object around the noisy centroid.
    const Eigen::Vector3d half = 0.5 * (object.T_world_object.linear().cwiseAbs() * object.size);
    d.box = {d.centroid - half, d.centroid + half};
    d.first_keyframe = k;
    detected.push_back(d);
  }
  return detected;
}

}  // namespace hydra_multi::sim
