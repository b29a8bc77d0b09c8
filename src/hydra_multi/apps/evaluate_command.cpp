// `hydra-multi evaluate --dataset DIR --result GRAPH [--json] [--objects F] [--keyframes F]`: the
// paper's metrics of a scene graph (in the global frame, robot 0's) against a simulated dataset's
// ground truth; optionally every object's verdict and every keyframe's error as CSV.

#include <fstream>
#include <iomanip>
#include <iostream>
#include <map>
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

Status writeObjectsCsv(const std::string& path, const SceneGraph& graph,
                       const SceneGraphScore& score, const DatasetGroundTruth& truth) {
  std::ofstream out(path);
  if (!out) return Error{"cannot write " + path};
  out << "node,label,name,x,y,z,verdict,true_object,true_label,distance_m\n"
      << std::setprecision(6);
  for (const ScoredObject& o : score.objects) {
    const SemanticAttributes* semantic = graph.getNode(o.id).semantic();
    out << o.id.str() << "," << o.label << "," << (semantic ? semantic->name : "") << ","
        << o.position_world.x() << "," << o.position_world.y() << "," << o.position_world.z() << ","
        << toString(o.verdict.kind) << ",";
    if (o.verdict.true_index >= 0)
      out << o.verdict.true_index << ","
          << truth.objects.at(static_cast<size_t>(o.verdict.true_index)).label << ","
          << o.verdict.distance_m;
    else
      out << ",,";
    out << "\n";
  }
  if (!out) return Error{"cannot write " + path};
  return Status::Ok();
}

Status writeKeyframesCsv(const std::string& path, const SceneGraphScore& score) {
  std::ofstream out(path);
  if (!out) return Error{"cannot write " + path};
  out << "node,stamp_s,x,y,z,true_x,true_y,true_z,error_m\n" << std::setprecision(6);
  for (const ScoredKeyframe& k : score.keyframes) {
    const Eigen::Vector3d& p = k.position_world;
    const Eigen::Vector3d& t = k.true_position;
    out << k.id.str() << "," << 1e-9 * static_cast<double>(k.stamp_ns) << "," << p.x() << ","
        << p.y() << "," << p.z() << "," << t.x() << "," << t.y() << "," << t.z() << ","
        << (p - t).norm() << "\n";
  }
  if (!out) return Error{"cannot write " + path};
  return Status::Ok();
}

}  // namespace

int runEvaluate(const EvaluateOptions& o) {
  auto truth = readDatasetGroundTruth(o.dataset);
  if (!truth) return fail(truth.error());
  std::map<std::string, size_t> unread;
  auto graph = io::loadSceneGraph(o.result, &unread);
  if (!graph) return fail(graph.error());
  if (!unread.empty())
    std::cerr << "hydra-multi: note: " << io::describeUnread(o.result, unread) << "\n";
  const SceneGraphScore s = evaluateSceneGraph(graph.value(), truth.value());
  if (!o.objects_csv.empty()) {
    if (Status written = writeObjectsCsv(o.objects_csv, graph.value(), s, truth.value()); !written)
      return fail(written.message());
  }
  if (!o.keyframes_csv.empty()) {
    if (Status written = writeKeyframesCsv(o.keyframes_csv, s); !written)
      return fail(written.message());
  }
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
            << "    of which        " << s.objects_correct << " correct (" << s.objects_duplicates
            << " duplicates), " << s.objects_wrong_label << " wrong label, " << s.objects_misplaced
            << " misplaced\n"
            << "  places error      " << show(s.places_position_error_m, " m") << " over "
            << s.num_places << " places\n"
            << "  rooms precision   " << show(s.rooms_precision, "") << "\n"
            << "  rooms recall      " << show(s.rooms_recall, "") << " (" << s.num_rooms
            << " rooms)\n";
  return 0;
}

}  // namespace hydra_multi::apps
