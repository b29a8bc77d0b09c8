#include "hydra_multi/apps/station_outputs.h"

#include <filesystem>
#include <fstream>

#include "hydra_multi/dsg/io/graph_file.h"
#include "hydra_multi/eval/trajectory_error.h"

namespace hydra_multi::apps {

Status writeStationOutputs(const std::string& dir, const StationResult& result) {
  namespace fs = std::filesystem;
  const fs::path out(dir);
  for (const char* name : {"graph.json", "graph.spark.json", "mesh.ply"}) {
    if (Status s = io::saveSceneGraph((out / name).string(), result.graph); !s) return s;
  }
  std::ofstream timing(out / "timing.csv");
  timing << "kind,index,robot,sequence,robot_time_s,ms,handoff_ms,loop_closures,nodes,poses,"
            "factors\n";
  for (size_t i = 0; i < result.updates.size(); ++i) {
    const UpdateTiming& u = result.updates[i];
    timing << "update," << i << "," << u.robot.str() << "," << u.sequence << "," << u.time_ns * 1e-9
           << "," << u.frontend_ms << "," << u.handoff_ms << "," << u.loop_closures << ",,,\n";
  }
  for (const RoundTiming& r : result.rounds) {
    timing << "backend," << r.round << ",,," << r.after_update << "," << r.report.time_s * 1e3
           << ",," << r.report.inter_robot_inliers << "," << r.report.nodes << ","
           << r.report.variables << "," << r.report.factors << "\n";
  }
  if (!timing) return Error{"cannot write " + (out / "timing.csv").string()};
  return Status::Ok();
}

StationTimes stationTimes(const StationResult& result) {
  std::vector<double> frontend_ms, backend_ms;
  for (const UpdateTiming& u : result.updates) frontend_ms.push_back(u.frontend_ms);
  for (const RoundTiming& r : result.rounds) backend_ms.push_back(r.report.time_s * 1e3);
  const ErrorStatistics frontend = errorStatistics(frontend_ms);
  const ErrorStatistics backend = errorStatistics(backend_ms);
  return {frontend.median, frontend.max, backend.median, backend.max};
}

}  // namespace hydra_multi::apps
