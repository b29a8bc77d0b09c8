#pragma once
// What a simulated dataset is made from: the fields of dataset.json that decide its bytes (preset,
// seed, scale, team plan, coverage, return to start, object threshold, team size and every
// parameter), as canonical JSON. Equal recipes, same build: the same dataset. `trials` reuses a
// dataset, and a run made on it, only when its recipe is the one asked for.

#include <string>

#include "hydra_multi/core/result.h"
#include "hydra_multi/sim/presets.h"

namespace hydra_multi::sim {

std::string datasetRecipe(const SimulationConfig& config);
/// The recipe recorded in DIR/dataset.json; an error naming the file if it has none.
Result<std::string> readDatasetRecipe(const std::string& dir);

}  // namespace hydra_multi::sim
