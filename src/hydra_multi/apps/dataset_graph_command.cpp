// `hydra-multi dataset-graph --dataset DIR --robot R --out GRAPH`: one robot's final graph as the
// robot itself has it (its update stream replayed, in its own odometric frame).

#include <iostream>

#include "hydra_multi/apps/commands.h"
#include "hydra_multi/dsg/graph_summary.h"
#include "hydra_multi/dsg/io/graph_file.h"
#include "hydra_multi/eval/dataset_ground_truth.h"

namespace hydra_multi::apps {

int runDatasetGraph(const DatasetGraphOptions& o) {
  auto dataset = readDatasetGroundTruth(o.dataset);
  if (!dataset) return fail(dataset.error());
  std::optional<RobotId> robot = RobotId::parse(o.robot);
  if (!robot && !o.robot.empty() && o.robot.find_first_not_of("0123456789") == std::string::npos &&
      o.robot.size() < 3) {
    robot = RobotId(static_cast<uint8_t>(std::stoi(o.robot)));
  }
  if (!robot || !dataset.value().streams.count(*robot)) {
    std::string known;
    for (const RobotId r : dataset.value().robots) known += (known.empty() ? "" : ", ") + r.str();
    return fail("no robot '" + o.robot + "' in " + o.dataset + " (robots: " + known + ")");
  }
  auto graph = replayRobotGraph(dataset.value(), *robot);
  if (!graph) return fail(graph.error());
  if (Status s = io::saveSceneGraph(o.out, graph.value()); !s) return fail(s.message());
  const GraphSummary summary = summarize(graph.value());
  std::cout << "robot " << robot->str() << ": " << summary.nodes << " nodes, " << summary.edges
            << " edges, " << summary.mesh_vertices << " mesh vertices -> " << o.out << "\n";
  return 0;
}

}  // namespace hydra_multi::apps
