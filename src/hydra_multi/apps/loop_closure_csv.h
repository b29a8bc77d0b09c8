#pragma once
// Loop closures as CSV rows, each checked against the ground truth (evaluation only): `detect
// --loop-closures FILE` writes every detected one, `run` the inter-robot ones with the station's
// verdicts (OUT/loop_closures.csv).

#include <optional>
#include <ostream>

#include "hydra_multi/eval/dataset_evaluation.h"
#include "hydra_multi/frontend/loop_closure_detector.h"

namespace hydra_multi::apps {

/// What the station made of an inter-robot loop closure.
struct LoopClosureVerdict {
  bool alignment_inlier = false;  ///< in its robot pair's consensus (initial alignment)
  bool kept = false;              ///< an inlier of GNC in the last backend round
};

/// The header row; with_verdicts adds the columns alignment_inlier and kept.
void writeLoopClosureCsvHeader(std::ostream& csv, bool with_verdicts);

/// One row: ids, stamps, layer, inliers, score, distinctiveness, the measured relative pose, both
/// keyframes' true positions, the errors against the truth and whether it is correct.
void writeLoopClosureCsvRow(std::ostream& csv, const DetectedLoopClosure& closure,
                            int64_t stamp_a_ns, int64_t stamp_b_ns, const DatasetGroundTruth& truth,
                            const LoopClosureCheck& check,
                            const std::optional<LoopClosureVerdict>& verdict = std::nullopt);

}  // namespace hydra_multi::apps
