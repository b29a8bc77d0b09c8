#include "hydra_multi/station/station_config.h"

#include <cmath>
#include <fstream>
#include <functional>
#include <limits>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

namespace hydra_multi {
namespace {

using Json = nlohmann::json;
// Sets one option from a JSON value; returns an error text (what was expected) or "".
using Setter = std::function<std::string(const Json&, StationOptions&)>;

Setter number(std::function<void(StationOptions&, double)> set, double min, bool exclusive,
              double max = std::numeric_limits<double>::infinity()) {
  return [set, min, exclusive, max](const Json& v, StationOptions& o) -> std::string {
    if (!v.is_number()) return "expected a number";
    const double x = v.get<double>();
    if (!std::isfinite(x) || (exclusive ? x <= min : x < min) || x > max) {
      return std::string("expected a number ") + (exclusive ? "> " : ">= ") + Json(min).dump() +
             (std::isfinite(max) ? " and <= " + Json(max).dump() : "");
    }
    set(o, x);
    return "";
  };
}

// A robot's label confusion as the label votes assume it (backend/reconciliation.h): at 0.5 or
// more a robot's label would be no evidence, or evidence against itself.
std::string setLabelConfusion(const Json& v, StationOptions& o) {
  if (!v.is_number() || !(v.get<double>() > 0.0 && v.get<double>() < 0.5))
    return "expected a number > 0 and < 0.5";
  o.backend.reconciliation.label_confusion = v.get<double>();
  return "";
}

std::string setThresholdRule(const Json& v, StationOptions& o) {
  using Rule = RoomSegmentationOptions::Rule;
  if (v == "median")
    o.backend.rooms.rule = Rule::kMedian;
  else if (v == "most")
    o.backend.rooms.rule = Rule::kMost;
  else
    return "expected \"median\" or \"most\"";
  return "";
}

Setter count(std::function<void(StationOptions&, int)> set, int min) {
  return [set, min](const Json& v, StationOptions& o) -> std::string {
    if (!v.is_number_integer() || v.get<int64_t>() < min || v.get<int64_t>() > 1000000)
      return "expected an integer >= " + std::to_string(min);
    set(o, static_cast<int>(v.get<int64_t>()));
    return "";
  };
}

Setter flag(std::function<void(StationOptions&, bool)> set) {
  return [set](const Json& v, StationOptions& o) -> std::string {
    if (!v.is_boolean()) return "expected true or false";
    set(o, v.get<bool>());
    return "";
  };
}

const std::map<std::string, std::map<std::string, Setter>>& setters() {
  static const std::map<std::string, std::map<std::string, Setter>> table = {
      {"alignment",
       {{"min_inliers",
         count([](StationOptions& o, int n) { o.backend.alignment.alignment.min_inliers = n; }, 1)},
        {"sigma_translation_m", number(
                                    [](StationOptions& o, double s) {
                                      auto& info =
                                          o.backend.alignment.alignment.averaging.information;
                                      for (int i = 0; i < 3; ++i) info(i, i) = 1.0 / (s * s);
                                    },
                                    0.0, true)},
        {"sigma_rotation_rad", number(
                                   [](StationOptions& o, double s) {
                                     auto& info =
                                         o.backend.alignment.alignment.averaging.information;
                                     for (int i = 3; i < 6; ++i) info(i, i) = 1.0 / (s * s);
                                   },
                                   0.0, true)},
        {"realign_threshold_m",
         number([](StationOptions& o, double x) { o.backend.alignment.realign_threshold_m = x; },
                0.0, true)},
        {"decline_refuted",
         flag([](StationOptions& o, bool b) { o.backend.alignment.decline_refuted = b; })},
        {"refuted_within_m",
         number([](StationOptions& o, double x) { o.backend.alignment.refuted_within_m = x; }, 0.0,
                true)},
        {"realign_fit_share",
         number([](StationOptions& o, double x) { o.backend.alignment.realign_fit_share = x; }, 0.0,
                false, 1.0)},
        {"realign_fit_m",
         number([](StationOptions& o, double x) { o.backend.alignment.realign_fit_m = x; }, 0.0,
                true)},
        {"weigh_support",
         flag([](StationOptions& o, bool b) { o.backend.alignment.weigh_support = b; })},
        {"realign_against_verdicts",
         flag([](StationOptions& o, bool b) { o.backend.alignment.realign_against_verdicts = b; })},
        {"realign_rejected_share",
         number([](StationOptions& o, double x) { o.backend.alignment.realign_rejected_share = x; },
                0.0, false, 1.0)}}},
      {"deformation",
       {{"odometry_variance",
         number([](StationOptions& o, double x) { o.backend.deformation.odometry_variance = x; },
                0.0, true)},
        {"odometry_rotation_variance",
         number([](StationOptions& o,
                   double x) { o.backend.deformation.odometry_rotation_variance = x; },
                0.0, true)},
        {"loop_closure_variance",
         number(
             [](StationOptions& o, double x) { o.backend.deformation.loop_closure_variance = x; },
             0.0, true)},
        {"mesh_variance",
         number([](StationOptions& o, double x) { o.backend.deformation.mesh_variance = x; }, 0.0,
                true)},
        {"link_max_dt_s",
         number([](StationOptions& o, double x) { o.backend.deformation.link_max_dt_s = x; }, 0.0,
                false)},
        {"control_point_voxel_m",
         number([](StationOptions& o, double x) { o.backend.deformation.control_point_voxel = x; },
                0.0, false)},
        {"two_stage", flag([](StationOptions& o, bool b) { o.backend.deformation.two_stage = b; })},
        {"final_iterations",
         count([](StationOptions& o, int n) { o.backend.deformation.final_iterations = n; }, 0)},
        {"readmit_unsolved_with_merges",
         flag([](StationOptions& o, bool b) { o.backend.readmit_unsolved_with_merges = b; })},
        {"readmit_unsolved_share",
         number([](StationOptions& o, double x) { o.backend.readmit_unsolved_share = x; }, 0.0,
                false, 1.0)},
        {"local_deferred_share",
         number([](StationOptions& o, double x) { o.backend.deformation.local_deferred_share = x; },
                0.0, false, 1.0)},
        {"whole_graph_analysis_ahead", flag([](StationOptions& o, bool b) {
           o.backend.deformation.whole_graph_analysis_ahead = b;
         })},
        {"gnc_mu_step",
         number([](StationOptions& o, double x) { o.backend.deformation.solver.gnc.mu_step = x; },
                1.0, true)},
        {"gnc_incremental_mu_step",
         number([](StationOptions& o,
                   double x) { o.backend.deformation.solver.incremental_mu_step = x; },
                1.0, false)},
        {"gnc_inlier_probability", number(
                                       [](StationOptions& o, double x) {
                                         o.backend.deformation.solver.gnc.inlier_probability =
                                             std::min(x, 1.0 - 1e-12);
                                       },
                                       0.0, true)},
        {"gnc_inner_iterations",
         count([](StationOptions& o,
                  int n) { o.backend.deformation.solver.gnc_inner_iterations = n; },
               0)},
        {"reduce_chains",
         flag([](StationOptions& o, bool b) { o.backend.deformation.solver.reduce_chains = b; })},
        {"keep_converged_gnc_solve", flag([](StationOptions& o, bool b) {
           o.backend.deformation.solver.keep_converged_gnc_solve = b;
         })},
        {"linearization_threads",
         count([](StationOptions& o,
                  int n) { o.backend.deformation.solver.solver.linearization_threads = n; },
               1)},
        {"single_precision_from_flops",
         number(
             [](StationOptions& o, double x) {
               o.backend.deformation.solver.solver.single_precision_from_flops = x;
             },
             -1.0, false)},
        {"chain_min_share",
         number(
             [](StationOptions& o, double x) { o.backend.deformation.solver.chain_min_share = x; },
             0.0, false, 1.0)}}},
      {"loop_closures",
       {{"object_ambiguity_ratio",
         number([](StationOptions& o, double x) { o.detector.object_ambiguity_ratio = x; }, 0.0,
                false)},
        {"anchor_objects", flag([](StationOptions& o, bool b) { o.detector.anchor_objects = b; })},
        {"object_rival_distance",
         number([](StationOptions& o, double x) { o.detector.object_rival_distance = x; }, 0.0,
                false)}}},
      {"reconciliation",
       {{"enabled", flag([](StationOptions& o, bool b) { o.backend.reconcile = b; })},
        {"admit_fitting_merges",
         flag([](StationOptions& o, bool b) { o.backend.admit_fitting_merges = b; })},
        {"merge_while_solving",
         flag([](StationOptions& o, bool b) { o.backend.merge_while_solving = b; })},
        {"plan_merges_ahead",
         flag([](StationOptions& o, bool b) { o.backend.plan_merges_ahead = b; })},
        {"icp_threads",
         count([](StationOptions& o, int n) { o.backend.reconciliation.icp_threads = n; }, 1)},
        {"icp_reuse_m",
         number([](StationOptions& o, double x) { o.backend.reconciliation.icp_reuse_m = x; }, 0.0,
                false)},
        {"icp_reuse_rad",
         number([](StationOptions& o, double x) { o.backend.reconciliation.icp_reuse_rad = x; },
                0.0, false)},
        {"place_max_distance",
         number(
             [](StationOptions& o, double x) { o.backend.reconciliation.place_max_distance = x; },
             0.0, false)},
        {"place_max_radius_difference",
         number([](StationOptions& o,
                   double x) { o.backend.reconciliation.place_max_radius_difference = x; },
                0.0, false)},
        {"min_valid_share",
         number([](StationOptions& o, double x) { o.backend.reconciliation.min_valid_share = x; },
                0.0, false)},
        {"merge_variance",
         number([](StationOptions& o, double x) { o.backend.reconciliation.merge_variance = x; },
                0.0, true)},
        {"label_votes",
         flag([](StationOptions& o, bool b) { o.backend.reconciliation.label_votes = b; })},
        {"label_confusion", setLabelConfusion},
        {"label_min_odds",
         number([](StationOptions& o, double x) { o.backend.reconciliation.label_min_odds = x; },
                1.0, false)},
        {"label_vertex_distance_m",
         number([](StationOptions& o,
                   double x) { o.backend.reconciliation.label_vertex_distance_m = x; },
                0.0, true)},
        {"label_min_shared_vertices",
         number([](StationOptions& o,
                   double x) { o.backend.reconciliation.label_min_shared_vertices = x; },
                0.0, true, 1.0)}}},
      {"rooms",
       {{"enabled", flag([](StationOptions& o, bool b) { o.backend.segment_rooms = b; })},
        {"thresholds", count([](StationOptions& o, int n) { o.backend.rooms.thresholds = n; }, 1)},
        {"min_threshold",
         number([](StationOptions& o, double x) { o.backend.rooms.min_threshold = x; }, 0.0, true)},
        {"max_threshold",
         number([](StationOptions& o, double x) { o.backend.rooms.max_threshold = x; }, 0.0, true)},
        {"min_room_places",
         count([](StationOptions& o, int n) { o.backend.rooms.min_room_places = n; }, 1)},
        {"max_door_radius",
         number([](StationOptions& o, double x) { o.backend.rooms.max_door_radius = x; }, 0.0,
                false)},
        {"threshold_rule", setThresholdRule}}},
      {"memory",
       {{"keep_freed_mb", count([](StationOptions& o, int n) { o.keep_freed_mb = n; }, 0)}}}};
  return table;
}

}  // namespace

Status applyStationConfig(const std::string& text, const std::string& where,
                          StationOptions& options) {
  const Json config = Json::parse(text, nullptr, false);
  if (config.is_discarded()) return Error{where + ": not valid JSON"};
  if (!config.is_object()) return Error{where + ": expected a JSON object of sections"};
  StationOptions updated = options;
  for (const auto& [section, values] : config.items()) {
    const auto known = setters().find(section);
    if (known == setters().end()) {
      std::string names;
      for (const auto& [name, unused] : setters()) names += (names.empty() ? "" : ", ") + name;
      return Error{where + ": unknown section \"" + section + "\" (known: " + names + ")"};
    }
    if (!values.is_object()) return Error{where + ": " + section + ": expected an object"};
    for (const auto& [key, value] : values.items()) {
      const auto setter = known->second.find(key);
      if (setter == known->second.end()) {
        std::string names;
        for (const auto& [name, unused] : known->second)
          names += (names.empty() ? "" : ", ") + name;
        return Error{where + ": unknown key " + section + "." + key + " (known: " + names + ")"};
      }
      const std::string problem = setter->second(value, updated);
      if (!problem.empty())
        return Error{where + ": " + section + "." + key + ": " + problem + ", got " + value.dump()};
    }
  }
  if (updated.backend.rooms.min_threshold > updated.backend.rooms.max_threshold)
    return Error{where + ": rooms.min_threshold is above rooms.max_threshold"};
  options = std::move(updated);
  return Status::Ok();
}

Status loadStationConfig(const std::string& path, StationOptions& options) {
  std::ifstream in(path);
  if (!in) return Error{"cannot read the configuration " + path};
  std::ostringstream text;
  text << in.rdbuf();
  return applyStationConfig(text.str(), path, options);
}

Result<std::string> canonicalStationConfig(const std::string& path) {
  if (path.empty()) return std::string("{}");
  StationOptions unused;
  if (Status s = loadStationConfig(path, unused); !s) return Error{s.message()};
  std::ifstream in(path);
  return Json::parse(in, nullptr, false).dump();
}

}  // namespace hydra_multi
