#include "hydra_multi/sim/dataset_json.h"

#include <filesystem>

#include "hydra_multi/dsg/io/graph_file.h"
#include "hydra_multi/sim/dataset_recipe.h"

namespace hydra_multi::sim {

using json = nlohmann::ordered_json;

json sensorJson(const SensorProfile& s) {
  json provides = json::array();
  for (uint32_t bit = 1; bit <= kProvidesVisual; bit <<= 1) {
    if (s.providedLayers() & bit) provides.push_back(providedLayerName(bit));
  }
  return {{"kind", s.kind},
          {"semantic", s.semantic},
          {"mesh_range_m", s.mesh_range},
          {"mesh_horizontal_fov_deg", s.mesh_horizontal_fov_deg},
          {"mesh_vertical_fov_deg", s.mesh_vertical_fov_deg},
          {"camera_range_m", s.camera.range},
          {"camera_horizontal_fov_deg", s.camera.horizontal_fov_deg},
          {"provides", provides}};
}

json parametersJson(const SimulationConfig& c) {
  const BuildingOptions& b = c.building;
  const MapperOptions& m = c.mapper;
  return {
      {"building",
       {{"floors", b.floors},
        {"rooms_per_side", b.rooms_per_side},
        {"room_width_m", b.room_width},
        {"room_depth_m", b.room_depth},
        {"corridor_width_m", b.corridor_width},
        {"wall_thickness_m", b.wall_thickness},
        {"floor_height_m", b.floor_height},
        {"room_kind", roomKindName(b.room_kind)},
        {"open_spaces", b.open_spaces},
        {"far_side_depth_m", b.far_side_depth},
        {"kitchen_every", b.kitchen_every},
        {"random_kitchens", b.random_kitchens},
        {"identical_rooms", b.identical_rooms}}},
      {"free_space",
       {{"resolution_m", c.free_space.resolution},
        {"gvd_site_separation_m", c.free_space.gvd_site_separation},
        {"gvd_min_clearance_m", c.free_space.gvd_min_clearance}}},
      {"surfaces", {{"spacing_m", c.surfaces.spacing}, {"door_height_m", c.surfaces.door_height}}},
      {"textures",
       {{"points_per_m2", c.textures.points_per_m2},
        {"vocabulary", c.textures.vocabulary},
        {"wall_height_m", c.textures.wall_height}}},
      {"planner",
       {{"robot_radius_m", c.planner.robot_radius},
        {"preferred_clearance_m", c.planner.preferred_clearance},
        {"clearance_penalty", c.planner.clearance_penalty}}},
      {"trajectory",
       {{"speed_m_s", c.trajectory.speed},
        {"keyframe_spacing_m", c.trajectory.keyframe_spacing},
        {"body_height_m", c.trajectory.body_height},
        {"robot_start_interval_s", c.robot_start_interval_s}}},
      {"odometry",
       {{"translation_sigma_per_sqrt_m", c.odometry.translation_sigma},
        {"yaw_sigma_rad_per_sqrt_m", c.odometry.yaw_sigma},
        {"roll_pitch_sigma_rad_per_sqrt_m", c.odometry.roll_pitch_sigma}}},
      {"loop_closures",
       {{"min_time_gap_s", c.loop_closures.min_time_gap_s},
        {"cooldown_s", c.loop_closures.cooldown_s},
        {"max_distance_m", c.loop_closures.max_distance},
        {"max_yaw_deg", c.loop_closures.max_yaw_deg},
        {"aliasing_acceptance", c.loop_closures.aliasing_acceptance},
        {"gross_error_share", c.loop_closures.gross_error_share},
        {"translation_sigma_m", c.loop_closures.translation_sigma},
        {"rotation_sigma_deg", c.loop_closures.rotation_sigma_deg}}},
      {"mapper",
       {{"update_period_s", m.update_period_s},
        {"snapshot_every", m.snapshot_every},
        {"send_keypoints", m.send_keypoints},
        {"send_own_loop_closures", m.send_own_loop_closures},
        {"mesh_noise_sigma_m", m.mesh_noise_sigma},
        {"control_point_spacing_m", m.control_point_spacing},
        {"keypoint_sigma_base_m", m.keypoint_sigma_base},
        {"keypoint_sigma_per_m2", m.keypoint_sigma_per_m2},
        {"split_probability", m.split_probability},
        {"split_min_extent_m", m.split_min_extent},
        {"split_merge_delay_s", m.split_merge_delay_s},
        {"spurious_probability", m.spurious_probability},
        {"spurious_lifetime_s", m.spurious_lifetime_s},
        {"loop_closure_translation_sigma_m", m.loop_closure_translation_sigma},
        {"loop_closure_rotation_sigma_deg", m.loop_closure_rotation_sigma_deg},
        {"parent_place_radius_m", m.parent_place_radius},
        {"places",
         {{"spacing_m", m.places.spacing},
          {"max_edge_length_m", m.places.max_edge_length},
          {"sensor_range_m", m.places.sensor_range},
          {"height_above_floor_m", m.places.height_above_floor}}},
        {"detection",
         {{"min_views", m.detection.min_views},
          {"miss_probability", m.detection.miss_probability},
          {"confusion_probability", m.detection.confusion_probability},
          {"position_sigma_m", m.detection.position_sigma}}}}}};
}

json recipeJson(const SimulationConfig& c) {
  return {{"preset", c.preset},
          {"seed", c.seed},
          {"scale", c.scale},
          {"team_plan", teamPlanName(c.plan)},
          {"coverage", c.coverage},
          {"return_to_start", c.return_to_start},
          {"object_threshold_m", c.object_threshold_m},
          {"robots", c.robots},
          {"parameters", parametersJson(c)}};
}

std::string datasetRecipe(const SimulationConfig& config) { return recipeJson(config).dump(); }

Result<std::string> readDatasetRecipe(const std::string& dir) {
  const std::string path = (std::filesystem::path(dir) / "dataset.json").string();
  auto text = io::readFile(path);
  if (!text) return Error{text.error()};
  const json header = json::parse(text.value(), nullptr, false);
  if (header.is_discarded() || !header.is_object()) return Error{path + ": not valid JSON"};
  json recipe = json::object();
  const json keys = recipeJson(SimulationConfig{});
  for (const auto& [key, value] : keys.items()) {
    if (!header.contains(key))
      return Error{path + ": no \"" + key + "\" (not a dataset of this version)"};
    recipe[key] =
        key == "robots" && header[key].is_array() ? json(header[key].size()) : header[key];
  }
  return recipe.dump();
}

}  // namespace hydra_multi::sim
