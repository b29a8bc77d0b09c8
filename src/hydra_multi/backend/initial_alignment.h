#pragma once
// InitialAlignment (paper III-B, eq. 1-2): the frames of the robots relative to robot 0's (the
// global frame), from the inter-robot loop closures and the robots' odometric keyframe poses, by
// robust pose averaging per robot pair (at least k = 5 inliers) and a spanning tree over the
// robots that prefers the pairs with more inliers (optim/multi_robot_alignment.h).
//
// Departure from the paper: the consensus is weighed. Each loop closure counts with the support
// the station gives it (frontend/loop_closure_detector.h, interRobotSupport: how much more
// distinctive its match is than a typical one), not 1. In look-alike rooms the wrong loop
// closures agree with each other and outnumber the right ones; the few matches that hold a
// distinctive place (a kitchen among student rooms) decide (docs/DECISIONS.md: "The alignment's
// consensus weighed by support").
//
// Online, a robot once aligned keeps its alignment: it is replaced only when this round's
// estimate, from every loop closure so far, disagrees with the backend's optimized result by more
// than realign_threshold_m (the pose of the robot's first keyframe after optimization against the
// one the estimate gives), the optimization has not already refuted that estimate
// (decline_refuted), and, where the estimate is a new frame, the new frames fit as much of the
// robots' inter-robot loop closures (by support) as the kept ones (realign_fit_share), and, with
// realign_against_verdicts, the optimization rejected enough of the loop closures the estimate
// rests on. A robot not aligned yet stays in its own frame and takes no part in merging. A round
// afresh (the station's last) takes every robot's estimate from this round's loop closures, so its
// alignments do not depend on when earlier rounds ran; a robot this round cannot align keeps the
// alignment it had.
//
// The global frame is the root's: the robot the caller prefers (the station: robot a, or the
// lowest robot it has data of). It stays where it was first put; when a lower robot is preferred
// later (robot a joining late, its first update lost), the frame moves to that robot's once it is
// aligned with the current root, and every alignment is re-expressed in it; never before, so no
// robot drops out of the map while the new root is not connected yet.

#include <map>
#include <optional>
#include <vector>

#include "hydra_multi/dsg/scene_graph.h"
#include "hydra_multi/optim/multi_robot_alignment.h"

namespace hydra_multi {

struct InitialAlignmentOptions {
  /// Sigma of eq. (2): 0.5 m and 0.05 rad, tighter than for g2o files (optim's default 1 m,
  /// 0.1 rad) because wrong loop closures between look-alike rooms are only a room's width off.
  MultiRobotAlignmentOptions alignment = [] {
    MultiRobotAlignmentOptions options;
    options.averaging.information.setZero();
    options.averaging.information.diagonal() << 4.0, 4.0, 4.0, 400.0, 400.0, 400.0;
    options.averaging.consensus = true;
    return options;
  }();
  double realign_threshold_m = 10.0;
  /// An estimate refuted: the optimization, started from it, put the robot's start back within
  /// refuted_within_m of where it had it before the re-alignment. While the optimized start is
  /// there, the robot is not re-aligned to an estimate within realign_threshold_m of that one.
  bool decline_refuted = true;
  double refuted_within_m = 1.0;
  /// Estimates that fit the robots' loop closures worse than their kept frames: the robots whose
  /// estimated frames move their starts by more than realign_threshold_m from their kept frames
  /// are re-aligned together, and only where, in the estimated frames, their inter-robot loop
  /// closures that fit (ends within realign_fit_m, the keyframes as the robots recorded them)
  /// weigh at least this share of those that fit in their kept frames, every other robot in its
  /// kept frame; each weighs its support in the consensus (weigh_support), else 1. The spanning
  /// tree composes an estimate through other pairs, whose consensus can hold look-alikes; this
  /// checks it against all of the robots' loop closures. 0: not checked.
  double realign_fit_share = 1.0;
  double realign_fit_m = 2.0;
  /// Weigh each loop closure in its pair's consensus by the support the caller gives (the
  /// station: how distinctive its match is, frontend/loop_closure_detector.h); false: by count,
  /// as the paper.
  bool weigh_support = true;
  /// Take every round's estimate (no optimized result to check it against: the baselines
  /// without joint optimization).
  bool always_realign = false;
  /// Re-align only a robot the map disagrees with: where the caller gives the optimization's
  /// verdicts on the inter-robot loop closures and it decided some of the robot's loop closures
  /// that the estimate holds as inliers, the robot is re-aligned only if it rejected at least
  /// realign_rejected_share of them (by support, as weigh_support). Over long paths a start
  /// placed by a frame fitted where the loop closures are can lie tens of metres from a map that
  /// keeps every one of them (odometric drift). false: the distance alone.
  bool realign_against_verdicts = true;
  double realign_rejected_share = 0.5;
};

struct RobotFrameAlignment {
  Eigen::Isometry3d T_global_robot = Eigen::Isometry3d::Identity();
  size_t inliers = 0;  ///< of the tree edge that aligned it (0 for the root)
  int rounds_aligned = 0;
};

class InitialAlignment {
 public:
  explicit InitialAlignment(InitialAlignmentOptions options = {}) : options_(options) {}

  /// One round. `frontend`: the graph of every robot's keyframes in station ids, each robot in its
  /// own frame; `inter_robot`: loop closures between keyframes of different robots (T_from_to);
  /// `root`: the robot whose frame should be global (see above). `optimized_first_keyframes`,
  /// when given, holds the backend's optimized global pose of each aligned robot's first
  /// keyframe, for the re-alignment rule. `support`, when given, holds one weight per inter-robot
  /// loop closure for the consensus (weigh_support). `afresh`: take every estimate (see above).
  /// `verdicts`, when given: the optimization's last verdict on each inter-robot loop closure
  /// ((from, to) -> kept), for realign_against_verdicts. Returns the robots aligned after this
  /// round.
  const std::map<RobotId, RobotFrameAlignment>& update(
      const SceneGraph& frontend, const std::vector<PoseGraphEdge>& inter_robot, RobotId root,
      const std::map<RobotId, Eigen::Isometry3d>& optimized_first_keyframes = {},
      const std::vector<double>& support = {}, bool afresh = false,
      const std::map<std::pair<NodeId, NodeId>, bool>* verdicts = nullptr);

  const std::map<RobotId, RobotFrameAlignment>& aligned() const { return aligned_; }
  bool isAligned(RobotId robot) const { return aligned_.count(robot) != 0; }
  /// The robot whose frame is the global frame now (none before the first round).
  std::optional<RobotId> root() const { return root_; }
  /// Per pair, the last round's averaging: loop closures and inliers.
  const std::vector<RobotPairAlignment>& pairs() const { return pairs_; }
  size_t realignments() const { return realignments_; }
  /// Re-alignments not made: the estimate was one the optimization had refuted (decline_refuted).
  size_t realignmentsDeclined() const { return declined_; }
  /// Re-alignments not made: the estimated frame fit less of the loop closures (realign_fit_share).
  size_t realignmentsUnfit() const { return unfit_; }
  /// Re-alignments not made: the optimization kept the robot's loop closures that the estimate
  /// holds (realign_against_verdicts).
  size_t realignmentsAgreed() const { return agreed_; }
  /// Times the global frame moved to a preferred root that joined late.
  size_t rootChanges() const { return root_changes_; }
  /// Per inter-robot loop closure (from, to) of the last round: an inlier of its pair's average.
  const std::map<std::pair<NodeId, NodeId>, bool>& edgeInliers() const { return edge_inliers_; }

 private:
  InitialAlignmentOptions options_;
  std::optional<RobotId> root_;
  std::map<RobotId, RobotFrameAlignment> aligned_;
  std::vector<RobotPairAlignment> pairs_;
  size_t realignments_ = 0;
  size_t declined_ = 0;
  size_t unfit_ = 0;
  size_t agreed_ = 0;
  /// Per robot re-aligned, its start by the estimate it took and as optimized before.
  struct Tried {
    Eigen::Vector3d estimate, optimized;
  };
  std::map<RobotId, Tried> tried_;
  size_t root_changes_ = 0;
  std::map<std::pair<NodeId, NodeId>, bool> edge_inliers_;
  /// Each robot pair's consensus tests, kept from round to round (ConsensusCache).
  std::map<std::pair<size_t, size_t>, ConsensusCache> consensus_;
};

}  // namespace hydra_multi
