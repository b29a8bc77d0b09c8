#pragma once
// The scene-graph metrics as the JSON keys of `evaluate --json` (shared by `run`'s metrics.json).

#include <nlohmann/json.hpp>

#include "hydra_multi/eval/dataset_evaluation.h"

namespace hydra_multi::apps {

/// ate_rmse_m, objects_found_pct, objects_correct_pct, object_threshold_m,
/// places_position_error_m, rooms_precision, rooms_recall, num_objects, num_places, num_rooms
/// (null where a metric had nothing to measure).
nlohmann::ordered_json scoreJson(const SceneGraphScore& score);

}  // namespace hydra_multi::apps
