// `hydra-multi evaluate --dataset DIR --result GRAPH [--json]`: the paper's metrics of a scene
// graph (in the global frame, robot 0's) against a simulated dataset's ground truth.

#include <iomanip>
#include <iostream>
#include <nlohmann/json.hpp>

#include "hydra_multi/apps/commands.h"
#include "hydra_multi/apps/score_json.h"
#include "hydra_multi/dsg/io/graph_file.h"
#include "hydra_multi/eval/dataset_evaluation.h"

namespace hydra_multi::apps {
namespace {

std::string show(const std::optional<double>& v, const char* unit, int precision = 3) {
  if (!v) return "n/a";
  std::ostringstream out;
  out << std::fixed << std::setprecision(precision) << *v << unit;
  return out.str();
}

}  // namespace

int runEvaluate(const EvaluateOptions& o) {
  auto truth = readDatasetGroundTruth(o.dataset);
  if (!truth) return fail(truth.error());
  auto graph = io::loadSceneGraph(o.result);
  if (!graph) return fail(graph.error());
  const SceneGraphScore s = evaluateSceneGraph(graph.value(), truth.value());
  if (o.json) {
    const nlohmann::ordered_json j = scoreJson(s);
    std::cout << j.dump() << "\n";
    return 0;
  }
  std::cout << o.result << " against " << o.dataset << " (global frame: robot "
            << truth.value().robots.front().str() << "'s)\n"
            << "  ATE rmse          " << show(s.ate_rmse_m, " m") << " over " << s.matched_keyframes
            << " keyframes\n"
            << "  objects found     " << show(s.objects_found_pct, " %", 1) << "\n"
            << "  objects correct   " << show(s.objects_correct_pct, " %", 1) << " of "
            << s.num_objects << " (threshold " << s.object_threshold_m << " m)\n"
            << "  places error      " << show(s.places_position_error_m, " m") << " over "
            << s.num_places << " places\n"
            << "  rooms precision   " << show(s.rooms_precision, "") << "\n"
            << "  rooms recall      " << show(s.rooms_recall, "") << " (" << s.num_rooms
            << " rooms)\n";
  return 0;
}

}  // namespace hydra_multi::apps
