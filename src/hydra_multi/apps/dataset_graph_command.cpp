// `hydra-multi dataset-graph --dataset DIR --robot R --out GRAPH`: one robot's final graph as the
// station ends with it (its update stream replayed by the station's order rule, in the robot's own
// odometric frame), and what became of its updates.

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
  auto replay = replayRobotGraph(dataset.value(), *robot);
  if (!replay) return fail(replay.error());
  for (const std::string& skipped : replay.value().skipped)
    std::cerr << "skipped " << skipped << std::endl;
  if (Status s = io::saveSceneGraph(o.out, replay.value().graph); !s) return fail(s.message());
  const GraphSummary summary = summarize(replay.value().graph);
  std::cout << "robot " << robot->str() << ": " << summary.nodes << " nodes, " << summary.edges
            << " edges, " << summary.mesh_vertices << " mesh vertices -> " << o.out << "\n"
            << replay.value().summary << "\n";
  return 0;
}

}  // namespace hydra_multi::apps
