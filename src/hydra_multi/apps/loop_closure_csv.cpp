#include "hydra_multi/apps/loop_closure_csv.h"

#include <cmath>
#include <iomanip>

namespace hydra_multi::apps {

const char* const kLoopClosureMeasurementColumns =
    "robot_a,keyframe_a,stamp_a_s,robot_b,keyframe_b,stamp_b_s,source,inliers,score,"
    "distinctiveness,x,y,z,yaw_deg";

void writeLoopClosureMeasurement(std::ostream& csv, const DetectedLoopClosure& c,
                                 int64_t stamp_a_ns, int64_t stamp_b_ns) {
  const Eigen::Vector3d t = c.T_a_b.translation();
  const double yaw = std::atan2(c.T_a_b.linear()(1, 0), c.T_a_b.linear()(0, 0)) * 180.0 / M_PI;
  csv << c.robot_a.str() << "," << c.keyframe_a.str() << "," << stamp_a_ns * 1e-9 << ","
      << c.robot_b.str() << "," << c.keyframe_b.str() << "," << stamp_b_ns * 1e-9 << ","
      << loopClosureSourceName(c.source) << "," << c.inliers << "," << c.score << ","
      << c.distinctiveness << "," << t.x() << "," << t.y() << "," << t.z() << "," << yaw;
}

void writeLoopClosureCsvHeader(std::ostream& csv, bool with_verdicts) {
  csv << kLoopClosureMeasurementColumns
      << ",true_xa,true_ya,true_za,true_xb,true_yb,true_zb,translation_error_m,"
         "rotation_error_deg,correct"
      << (with_verdicts ? ",alignment_inlier,kept" : "") << "\n";
  csv << std::setprecision(9);
}

void writeLoopClosureCsvRow(std::ostream& csv, const DetectedLoopClosure& c, int64_t stamp_a_ns,
                            int64_t stamp_b_ns, const DatasetGroundTruth& truth,
                            const LoopClosureCheck& check,
                            const std::optional<LoopClosureVerdict>& verdict) {
  writeLoopClosureMeasurement(csv, c, stamp_a_ns, stamp_b_ns);
  for (const auto& [robot, stamp] : {std::pair{c.robot_a, stamp_a_ns}, {c.robot_b, stamp_b_ns}}) {
    const Eigen::Isometry3d* pose = truth.poseAt(robot, stamp);
    for (int k = 0; k < 3; ++k) {
      csv << ",";
      if (pose != nullptr) csv << pose->translation()(k);
    }
  }
  csv << ",";
  if (check.known) csv << check.translation_error_m;
  csv << ",";
  if (check.known) csv << check.rotation_error_deg;
  csv << "," << (check.correct ? 1 : 0);
  if (verdict) csv << "," << verdict->alignment_inlier << "," << verdict->kept;
  csv << "\n";
}

}  // namespace hydra_multi::apps
