#include "hydra_multi/apps/station_outputs.h"

#include <sys/resource.h>

#include <filesystem>
#include <fstream>
#include <iomanip>

#include "hydra_multi/apps/loop_closure_csv.h"
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
            "factors,alignment_ms,build_ms,gnc_ms,whole_graph_ms,graph_ms,rooms_ms,from_scratch,"
            "queue_ms,robots_afresh,solve_ms,factorization_ms,analysis_ms,lm_iterations,freed_mb,"
            "freed_handed_back,loop_closure_solve_ms,candidates_ms\n";
  for (size_t i = 0; i < result.updates.size(); ++i) {
    const UpdateTiming& u = result.updates[i];
    timing << "update," << i << "," << u.robot.str() << "," << u.sequence << "," << u.time_ns * 1e-9
           << "," << u.frontend_ms << "," << u.handoff_ms << "," << u.loop_closures << ",,,,,,,,,,,"
           << u.queue_ms << ",,,,,,,,,\n";
  }
  for (const RoundTiming& r : result.rounds) {
    const BackendRoundReport& b = r.report;
    timing << "backend," << r.round << ",,," << r.after_update << "," << b.time_s * 1e3 << ",,"
           << b.inter_robot_inliers << "," << b.nodes << "," << b.variables << "," << b.factors
           << "," << b.alignment_s * 1e3 << "," << b.build_s * 1e3 << "," << b.gnc_s * 1e3 << ","
           << b.whole_graph_s * 1e3 << "," << b.graph_s * 1e3 << "," << b.rooms_s * 1e3 << ","
           << (b.from_scratch ? 1 : 0) << ",," << b.robots_afresh << ","
           << b.solver_time.solve_s * 1e3 << "," << b.solver_time.factorization_s * 1e3 << ","
           << b.solver_time.analysis_s * 1e3 << "," << b.solver_time.iterations << ","
           << r.freed.bytes / double(1 << 20) << "," << (r.freed.handed_back ? 1 : 0) << ","
           << b.loop_closure_solve_s * 1e3 << "," << b.candidates_s * 1e3 << "\n";
  }
  if (!timing) return Error{"cannot write " + (out / "timing.csv").string()};
  return Status::Ok();
}

LoopClosureVerdict verdictOf(const StationResult& result, const DetectedLoopClosure& c) {
  const auto averaged = result.alignment_inliers.find({c.keyframe_a, c.keyframe_b});
  const auto kept = result.inter_robot_inliers.find({c.keyframe_a, c.keyframe_b});
  LoopClosureVerdict verdict;
  verdict.alignment_inlier = averaged != result.alignment_inliers.end() && averaged->second;
  verdict.kept = kept != result.inter_robot_inliers.end() && kept->second;
  return verdict;
}

int64_t keyframeStamp(const StationResult& result, NodeId keyframe) {
  const auto it = result.keyframe_stamps.find(keyframe);
  return it == result.keyframe_stamps.end() ? -1 : it->second;
}

Status writeStationLoopClosures(const std::string& dir, const StationResult& result) {
  const std::string path = (std::filesystem::path(dir) / "loop_closures.csv").string();
  std::ofstream csv(path);
  csv << kLoopClosureMeasurementColumns << ",alignment_inlier,kept\n" << std::setprecision(9);
  for (const DetectedLoopClosure& c : result.loop_closures) {
    if (!c.interRobot()) continue;
    writeLoopClosureMeasurement(csv, c, keyframeStamp(result, c.keyframe_a),
                                keyframeStamp(result, c.keyframe_b));
    const LoopClosureVerdict verdict = verdictOf(result, c);
    csv << "," << verdict.alignment_inlier << "," << verdict.kept << "\n";
  }
  if (!csv) return Error{"cannot write " + path};
  return Status::Ok();
}

Result<std::map<RobotId, RobotBandwidth>> writeBandwidth(const std::string& dir,
                                                         const BandwidthLedger& ledger) {
  const std::vector<UpdateBandwidth> rows = ledger.rows();
  const std::filesystem::path out(dir);
  std::ofstream(out / "bandwidth.csv") << bandwidthCsv(rows);
  std::ofstream svg(out / "bandwidth.svg");
  svg << bandwidthSvg(rows);
  if (!svg) return Error{"cannot write " + (out / "bandwidth.svg").string()};
  return bandwidthTotals(rows);
}

StationTimes stationTimes(const StationResult& result) {
  std::vector<double> frontend_ms, backend_ms;
  for (const UpdateTiming& u : result.updates) frontend_ms.push_back(u.frontend_ms);
  // The rounds while the robots mapped; the last one, from scratch on the final state, apart.
  const size_t online = result.rounds.size() > 1 && result.rounds.back().report.from_scratch
                            ? result.rounds.size() - 1
                            : result.rounds.size();
  for (size_t k = 0; k < online; ++k) backend_ms.push_back(result.rounds[k].report.time_s * 1e3);
  const ErrorStatistics frontend = errorStatistics(frontend_ms);
  const ErrorStatistics backend = errorStatistics(backend_ms);
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  StationTimes times{frontend.median, frontend.max, backend.median, backend.max,
                     double(usage.ru_maxrss) / 1024.0};
  if (online < result.rounds.size())
    times.backend_last_ms = result.rounds.back().report.time_s * 1e3;
  return times;
}

}  // namespace hydra_multi::apps
