#pragma once
// dataset.json's description of a simulated dataset (inside sim only): every parameter, the
// sensor profiles, and the recipe (dataset_recipe.h) as JSON.

#include <nlohmann/json.hpp>

#include "hydra_multi/sim/presets.h"

namespace hydra_multi::sim {

nlohmann::ordered_json sensorJson(const SensorProfile& sensor);
nlohmann::ordered_json parametersJson(const SimulationConfig& config);
/// The recipe's fields in dataset.json's order; "robots" holds the team size (dataset.json holds
/// the robots there).
nlohmann::ordered_json recipeJson(const SimulationConfig& config);

}  // namespace hydra_multi::sim
