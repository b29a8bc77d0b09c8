#pragma once
// Loop closures as CSV rows, each checked against the ground truth (evaluation only): `detect
// --loop-closures FILE` writes every detected one, `run` the inter-robot ones with the station's
// verdicts (OUT/loop_closures.csv); `station` writes the measured columns and its verdicts only
// (it never reads ground truth: station_outputs.h).

#include <optional>
#include <ostream>

#include "hydra_multi/apps/station_outputs.h"
#include "hydra_multi/eval/dataset_evaluation.h"
#include "hydra_multi/frontend/loop_closure_detector.h"

namespace hydra_multi::apps {

/// The columns of what the station measured of a loop closure (no truth): ids, stamps, layer,
/// inliers, score, distinctiveness, the relative pose; and one row of them (no newline).
extern const char* const kLoopClosureMeasurementColumns;
void writeLoopClosureMeasurement(std::ostream& csv, const DetectedLoopClosure& closure,
                                 int64_t stamp_a_ns, int64_t stamp_b_ns);

/// The header row; with_verdicts adds the columns alignment_inlier and kept.
void writeLoopClosureCsvHeader(std::ostream& csv, bool with_verdicts);

/// One row: ids, stamps, layer, inliers, score, distinctiveness, the measured relative pose, both
/// keyframes' true positions, the errors against the truth and whether it is correct.
void writeLoopClosureCsvRow(std::ostream& csv, const DetectedLoopClosure& closure,
                            int64_t stamp_a_ns, int64_t stamp_b_ns, const DatasetGroundTruth& truth,
                            const LoopClosureCheck& check,
                            const std::optional<LoopClosureVerdict>& verdict = std::nullopt);

}  // namespace hydra_multi::apps
