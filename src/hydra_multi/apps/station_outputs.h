#pragma once
// What every station run writes into its output folder, whatever fed it (`run`'s file replay,
// `station`'s network): graph.json, graph.spark.json, mesh.ply (the final backend graph) and
// timing.csv (one row per update, frontend, and per backend round).

#include <string>

#include "hydra_multi/core/result.h"
#include "hydra_multi/station/bandwidth.h"
#include "hydra_multi/station/station.h"

namespace hydra_multi::apps {

Status writeStationOutputs(const std::string& dir, const StationResult& result);

/// What the station made of an inter-robot loop closure in its last round.
struct LoopClosureVerdict {
  bool alignment_inlier = false;  ///< in its robot pair's consensus (initial alignment)
  bool kept = false;              ///< an inlier of GNC in the last backend round
};
LoopClosureVerdict verdictOf(const StationResult& result, const DetectedLoopClosure& closure);
/// A keyframe's stamp as the frontend holds it (-1: unknown).
int64_t keyframeStamp(const StationResult& result, NodeId keyframe);

/// DIR/loop_closures.csv without the ground truth: the inter-robot loop closures as measured,
/// with the station's verdicts (`station`; `run` writes its own with the truth's).
Status writeStationLoopClosures(const std::string& dir, const StationResult& result);

/// Median and maximum, for the summaries: frontend ms per update, backend ms per round while the
/// robots mapped (without the last round when it ran from scratch on the final state: its time is
/// backend_last_ms, 0 when there was none).
struct StationTimes {
  double frontend_ms_p50 = 0.0, frontend_ms_max = 0.0, backend_ms_p50 = 0.0, backend_ms_max = 0.0;
  double peak_memory_mb = 0.0;  ///< the process's peak resident set so far (getrusage)
  double backend_last_ms = 0.0;
};
StationTimes stationTimes(const StationResult& result);

/// DIR/bandwidth.csv and DIR/bandwidth.svg of a ledger's updates; what they add up to per robot.
Result<std::map<RobotId, RobotBandwidth>> writeBandwidth(const std::string& dir,
                                                         const BandwidthLedger& ledger);

}  // namespace hydra_multi::apps
