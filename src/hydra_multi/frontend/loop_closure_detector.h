#pragma once
// LoopClosureDetector: hierarchical loop-closure detection over the frontend graph (paper III-A,
// Hydra's detector; DESIGN.md "Loop closure detection").
//
// A keyframe is described (descriptors.h) once the robot has moved on from it (its time is
// descriptor_delay_s behind the robot's latest), so that its neighbourhood has been mapped; then
// it is matched against every described keyframe of the other robots, and against its own robot's
// keyframes at least min_time_separation_s older:
//   top-down   places prune the candidates (score >= place_min_score); among those, objects
//              (score >= object_min_score) and bag of words (score >= bow_min_score) rank them;
//   bottom-up  the first geometric verification that succeeds wins: objects, if the best object
//              candidate scores >= object_register_score, by TLS registration of same-label
//              object pairs with max-clique pruning (at least 5 inliers), unless a rival
//              registration at another pose holds nearly as many (ambiguous); otherwise visual
//              keypoints of the best bag-of-words candidates, matched by word id, by RANSAC with
//              at least visual_min_inliers inliers.
// An inter-robot object match joins the keyframes that mapped the registered objects (each
// robot's keyframe nearest their median mapping time), since the objects keep that moment's drift.
// A loop closure holds both keyframes (station ids), the relative pose T_a_b of keyframe b in
// keyframe a's body frame, an information matrix per verifying layer, the inlier count and the
// score, and its distinctiveness (how rare the matched labels or words are, for the alignment's
// weighed consensus). Robots without objects (a lidar robot) are matched by places and bag of
// words only.

#include <map>
#include <set>
#include <unordered_map>
#include <vector>

#include "hydra_multi/frontend/descriptors.h"
#include "hydra_multi/frontend/scene_graph_processor.h"
#include "hydra_multi/registration/ransac.h"
#include "hydra_multi/registration/tls_registration.h"

namespace hydra_multi {

struct LoopClosureOptions {
  DescriptorOptions descriptors;
  double descriptor_delay_s = 10.0;
  double min_time_separation_s = 30.0;  ///< same-robot candidates
  double place_min_score = 0.5;
  double object_min_score = 0.3;
  double object_register_score = 0.8;
  double bow_min_score = 0.3;
  size_t visual_candidates = 2;  ///< best bag-of-words candidates verified per keyframe
  size_t visual_min_inliers = 12;
  TlsRegistrationOptions objects{0.3, 5, 20000};
  /// An object registration with a rival is ambiguous and no loop closure: with the best
  /// registration's inlier pairs set aside, a second one of at least this share of its inliers at
  /// a pose more than object_rival_distance away (a corridor's row of look-alike rooms, shifted by
  /// one room). 0: no check.
  double object_ambiguity_ratio = 0.8;
  double object_rival_distance = 1.0;  ///< m
  /// An inter-robot object loop closure joins, on each side, the keyframe nearest the median
  /// time its registered objects were mapped, not the keyframe that described them: a robot's
  /// objects keep the drift of the moment it first saw them, and a robot passing again has
  /// drifted on.
  bool anchor_objects = true;
  /// A loop closure means both keyframes saw the same place: a verified transform that puts
  /// them further apart than this is not one (m).
  double max_keyframe_distance = 6.0;
  RansacOptions visual{0.15, 300, 0.999, 12, 1};
  /// Information of a verified loop closure: sigmas (m, rad) per layer.
  double object_translation_sigma = 0.3, object_rotation_sigma = 0.05;
  double visual_translation_sigma = 0.1, visual_rotation_sigma = 0.02;
  bool detect_intra_robot = true;
};

struct DetectedLoopClosure {
  enum class Source { kObjects, kVisual };
  RobotId robot_a, robot_b;
  NodeId keyframe_a, keyframe_b;  ///< station ids; a is the earlier-described (candidate)
  Eigen::Isometry3d T_a_b = Eigen::Isometry3d::Identity();
  Matrix6d information = Matrix6d::Identity();
  Source source = Source::kVisual;
  size_t inliers = 0;
  double score = 0.0;  ///< of the layer that ranked the pair
  /// How rare what matched is: the sum over the inlier correspondences of log(N / n), n of N
  /// objects sharing the pair's label (objects) or of N described keyframes holding the pair's
  /// word (visual). Look-alike rooms match on common labels and words; a match that holds a
  /// kitchen's fridge or its words is worth more.
  double distinctiveness = 0.0;
  bool interRobot() const { return robot_a != robot_b; }
};
const char* loopClosureSourceName(DetectedLoopClosure::Source source);

/// What each inter-robot closure of `closures` (in order, the others skipped) is worth to the
/// alignment's consensus: its distinctiveness beyond that of a typical match of its layer,
/// max(0, d - m * inliers) with m the median distinctiveness per inlier over the layer's
/// inter-robot closures. In look-alike rooms the typical match is between two look-alikes, on
/// common labels and words; what is left marks the matches of the few places that differ.
std::vector<double> interRobotSupport(const std::vector<DetectedLoopClosure>& closures);

class LoopClosureDetector {
 public:
  explicit LoopClosureDetector(LoopClosureOptions options = {});

  /// Queues the new keyframes of an applied update, then describes and matches those that are
  /// ready (descriptor_delay_s behind their robot). Returns the loop closures found by this call.
  std::vector<DetectedLoopClosure> update(const SceneGraphProcessor& processor,
                                          const std::vector<NodeId>& new_keyframes);
  /// The same for every keyframe not yet described (at the end of a run).
  std::vector<DetectedLoopClosure> flush(const SceneGraphProcessor& processor);

  const std::vector<DetectedLoopClosure>& loopClosures() const { return found_; }
  size_t keyframesDescribed() const { return described_.size(); }
  size_t keyframesPending() const { return pending_.size(); }

 private:
  struct Entry {
    KeyframeDescriptors d;
    RobotId robot;
    int64_t time_ns = 0;
    std::vector<double> place_bins;  ///< d.place_radii, every bin (zeros too)
  };
  std::vector<DetectedLoopClosure> run(const SceneGraphProcessor& processor, bool all);
  std::optional<DetectedLoopClosure> match(const SceneGraphProcessor& processor,
                                           const Entry& query);
  std::optional<DetectedLoopClosure> verifyObjects(const SceneGraphProcessor& processor,
                                                   const Entry& query, const Entry& candidate);
  /// Whether the object registration `best` of these correspondences has a rival (options).
  bool ambiguous(const std::vector<Eigen::Vector3d>& source,
                 const std::vector<Eigen::Vector3d>& target, const RegistrationResult& best) const;
  std::optional<DetectedLoopClosure> verifyVisual(const SceneGraphProcessor& processor,
                                                  const Entry& query, const Entry& candidate);

  LoopClosureOptions options_;
  std::vector<Entry> described_;
  std::vector<NodeId> pending_;                ///< keyframes not described yet, in arrival order
  std::map<uint32_t, size_t> word_keyframes_;  ///< described keyframes holding each word
  /// Per bag-of-words word, the described keyframes holding it (index in described_, weight):
  /// a query's bag-of-words score against each of them without passing over the others.
  std::unordered_map<uint32_t, std::vector<std::pair<uint32_t, double>>> word_postings_;
  /// The same per object label: a query's objects score against every described keyframe.
  std::unordered_map<uint32_t, std::vector<std::pair<uint32_t, double>>> label_postings_;
  std::vector<DetectedLoopClosure> found_;
};

}  // namespace hydra_multi
