#pragma once
// The station's configuration file (`hydra-multi run --config FILE`): a JSON object whose sections
// set the station's parameters over its defaults (DESIGN.md's, but where a header says why not).
// Every key is optional; an unknown key, a wrong type or a value out of range is an error that
// names the file and the key.
//
//   {
//     "loop_closures":  {"object_ambiguity_ratio": 0.8, "object_rival_distance": 1.0,
//                        "anchor_objects": true},
//     "alignment":      {"min_inliers": 5, "sigma_translation_m": 0.5, "sigma_rotation_rad": 0.05,
//                        "realign_threshold_m": 10.0, "decline_refuted": true,
//                        "refuted_within_m": 1.0, "weigh_support": true,
//                        "realign_against_verdicts": true, "realign_rejected_share": 0.5},
//     "deformation":    {"odometry_variance": 0.01, "loop_closure_variance": 0.05,
//                        "mesh_variance": 0.01, "odometry_rotation_variance": 0.0001,
//                        "link_max_dt_s": 10.0, "two_stage": true, "final_iterations": 10,
//                        "gnc_mu_step": 1.4, "gnc_inlier_probability": 0.99,
//                        "gnc_inner_iterations": 3},
//     "reconciliation": {"enabled": true, "place_max_distance": 0.3,
//                        "place_max_radius_difference": 0.3, "min_valid_share": 0.5,
//                        "merge_variance": 0.05, "label_votes": false, "label_confusion": 0.1,
//                        "label_min_odds": 3.0, "label_vertex_distance_m": 0.1,
//                        "label_min_shared_vertices": 0.5},
//     "rooms":          {"enabled": true, "thresholds": 12, "min_threshold": 0.43,
//                        "max_threshold": 1.2, "min_room_places": 5,
//                        "threshold_rule": "most", "max_door_radius": 0.55}
//   }

#include <string>

#include "hydra_multi/core/result.h"
#include "hydra_multi/station/station.h"

namespace hydra_multi {

/// Applies the configuration in `text` (JSON) to `options`; `where` names its source in errors.
/// On error `options` is unchanged.
Status applyStationConfig(const std::string& text, const std::string& where,
                          StationOptions& options);

/// Reads FILE and applies it to `options` (applyStationConfig).
Status loadStationConfig(const std::string& path, StationOptions& options);

/// The settings of the configuration file at `path` as canonical JSON (keys sorted, no spaces;
/// "{}" for an empty path, the defaults): what a run records in OUT/config.json and what `trials`
/// compares before it reuses a run. Errors as loadStationConfig's.
Result<std::string> canonicalStationConfig(const std::string& path);

}  // namespace hydra_multi
