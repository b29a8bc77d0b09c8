// The deformation graph: drifted robots pulled onto the truth by inter-robot loop closures, with
// wrong ones rejected by GNC; ties only between what a robot made about the same time.

#include <gtest/gtest.h>

#include <cstdio>
#include <memory>
#include <random>
#include <set>
#include <string>

#include "hydra_multi/backend/deformation_graph.h"
#include "hydra_multi/backend/optimized_map.h"
#include "hydra_multi/core/se3.h"

namespace hydra_multi {
namespace {

Eigen::Isometry3d circle(double angle, double radius = 10.0) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.translation() << radius * std::cos(angle), radius * std::sin(angle), 0.0;
  T.linear() = Eigen::AngleAxisd(angle + M_PI / 2, Eigen::Vector3d::UnitZ()).toRotationMatrix();
  return T;
}

struct Robot {
  RobotId id;
  std::vector<Eigen::Isometry3d> truth;  // global frame
  std::vector<Eigen::Isometry3d> odom;   // own frame, drifting
  std::vector<PoseGraphEdge> pose_graph;
  std::vector<ControlPoint> control_points;
  std::vector<ControlPointEdge> control_point_edges;
};

// Robot r drives 60 keyframes around a circle from its own start, with a yaw drift; one control
// point 1 m beside each keyframe, chained.
Robot drive(RobotId id, double start_angle, double yaw_drift, SceneGraph& frontend) {
  Robot r;
  r.id = id;
  for (int k = 0; k < 60; ++k) r.truth.push_back(circle(start_angle + 2 * M_PI * k / 60.0));
  r.odom.push_back(Eigen::Isometry3d::Identity());
  for (size_t k = 1; k < r.truth.size(); ++k) {
    Vector6d xi = Vector6d::Zero();
    xi[5] = yaw_drift;
    r.odom.push_back(r.odom.back() * (r.truth[k - 1].inverse() * r.truth[k]) * expSE3(xi));
  }
  for (size_t k = 0; k < r.truth.size(); ++k) {
    const NodeId kf = NodeId::station(id.prefix(), id, k);
    Node node = makeNode(kf, Layer::kAgents, r.odom[k].translation());
    node.find<AgentAttributes>()->orientation = Eigen::Quaterniond(r.odom[k].linear());
    node.find<AgentAttributes>()->timestamp_ns = static_cast<int64_t>(k) * 1000000000;
    frontend.addOrUpdateNode(node);
    if (k > 0) {
      PoseGraphEdge e;
      e.from = NodeId::station(id.prefix(), id, k - 1);
      e.to = kf;
      e.T_from_to = r.odom[k - 1].inverse() * r.odom[k];
      e.information = Matrix6d::Identity() * 100.0;
      r.pose_graph.push_back(e);
    }
    ControlPoint cp;
    cp.id = k;
    cp.position = r.odom[k] * Eigen::Vector3d(0, 1, 0);
    cp.time_ns = static_cast<int64_t>(k) * 1000000000;
    cp.keyframe = kf;
    r.control_points.push_back(cp);
    if (k > 0) r.control_point_edges.push_back({k - 1, k});
  }
  return r;
}

NodeId keyframe(const Robot& r, size_t k) { return NodeId::station(r.id.prefix(), r.id, k); }

// True loop closures wherever robots a and b (b started half a circle on) pass the same place.
std::vector<PoseGraphEdge> trueClosures(const Robot& a, const Robot& b) {
  std::vector<PoseGraphEdge> closures;
  for (size_t k = 0; k < 60; k += 3) {
    PoseGraphEdge e;
    e.from = keyframe(a, k);
    e.to = keyframe(b, (k + 30) % 60);
    e.T_from_to = a.truth[k].inverse() * b.truth[(k + 30) % 60];
    e.information = Matrix6d::Identity() * 100.0;
    closures.push_back(e);
  }
  return closures;
}

// The deformation inputs of robots a (the global frame) and b, placed by T_global_b.
std::vector<RobotDeformationInput> twoRobots(const Robot& a, const Robot& b,
                                             const Eigen::Isometry3d& T_global_b) {
  return {{a.id, Eigen::Isometry3d::Identity(), &a.pose_graph, &a.control_points,
           &a.control_point_edges},
          {b.id, T_global_b, &b.pose_graph, &b.control_points, &b.control_point_edges}};
}

TEST(DeformationGraph, LoopClosuresCorrectDriftAndOutliersAreRejected) {
  SceneGraph frontend;
  // Robot a's odometry is exact, robot b's turns 0.3 degrees too much at every keyframe: the
  // loop closures with a are what can straighten b.
  Robot a = drive(RobotId(0), 0.0, 0.0, frontend);
  Robot b = drive(RobotId(1), M_PI, 0.005, frontend);
  const auto kf = keyframe;
  // True closures wherever both robots pass the same place, and wrong ones.
  std::vector<PoseGraphEdge> inter = trueClosures(a, b);
  std::mt19937_64 rng(3);
  const size_t good = inter.size();
  std::uniform_int_distribution<size_t> pick(0, 59);
  for (int i = 0; i < 8; ++i) {
    // Wrong by 3 m and 45 degrees (what a look-alike place gives).
    PoseGraphEdge e = inter.front();
    const size_t ka = pick(rng), kb = pick(rng);
    e.from = kf(a, ka);
    e.to = kf(b, kb);
    Vector6d wrong;
    wrong << 3.0 * std::cos(i), 3.0 * std::sin(i), 0.0, 0.0, 0.0, (i % 2 ? 1 : -1) * M_PI / 4;
    e.T_from_to = a.truth[ka].inverse() * b.truth[kb] * expSE3(wrong);
    inter.push_back(e);
  }
  // The alignment is the truth of the starts (what initial alignment would estimate).
  const Eigen::Isometry3d T_global_b = a.truth.front().inverse() * b.truth.front();
  const std::vector<RobotDeformationInput> inputs = twoRobots(a, b, T_global_b);
  // The edges here carry calibrated information (robot b's drift is in its odometry edges' noise
  // model only as far as their values go): use it rather than Kimera-PGMO's variances.
  DeformationGraphOptions options;
  options.use_sent_information = true;
  const DeformationGraph graph = buildDeformationGraph(frontend, inputs, inter, {}, options);
  EXPECT_EQ(graph.inter_robot_factors, inter.size());
  EXPECT_EQ(graph.anchor, kf(a, 0));
  const DeformationResult result = optimizeDeformationGraph(graph, options);
  // Error of the keyframes against the truth (global = robot a's start), before and after.
  const Eigen::Isometry3d T_global_world = a.truth.front().inverse();
  double before = 0.0, after = 0.0;
  for (const Robot* r : {&a, &b}) {
    for (size_t k = 0; k < 60; ++k) {
      const Eigen::Vector3d truth = (T_global_world * r->truth[k]).translation();
      before = std::max(before, (graph.initial.at(kf(*r, k)).translation() - truth).norm());
      after = std::max(after, (result.poses.at(kf(*r, k)).translation() - truth).norm());
    }
  }
  EXPECT_GT(before, 1.0);
  EXPECT_LT(after, 0.3);
  size_t accepted_good = 0, accepted_bad = 0;
  for (size_t i = 0; i < inter.size(); ++i) {
    const bool inlier = result.robust_inlier.at({inter[i].from, inter[i].to});
    (i < good ? accepted_good : accepted_bad) += inlier;
  }
  EXPECT_EQ(accepted_good, good);
  EXPECT_EQ(accepted_bad, 0u);
}

// The whole-graph solve's analysis made while GNC runs, for the robust factors GNC starts with all
// kept: taken where GNC keeps just those (every closure true; the wrong ones held out from the
// start), analyzed anew where it does not (wrong closures GNC rejects); the same poses to the bit
// as without it in all three.
TEST(DeformationGraph, TheWholeGraphAnalysisMadeAheadIsTakenWhereGncKeptWhatItExpected) {
  SceneGraph frontend;
  Robot a = drive(RobotId(0), 0.0, 0.0, frontend);
  Robot b = drive(RobotId(1), M_PI, 0.005, frontend);
  std::vector<PoseGraphEdge> inter = trueClosures(a, b);
  const size_t good = inter.size();
  std::set<std::pair<NodeId, NodeId>> wrong;
  for (int i = 0; i < 4; ++i) {
    PoseGraphEdge e = inter.front();
    e.from = keyframe(a, 7 * i + 1);
    e.to = keyframe(b, 11 * i + 5);
    Vector6d off;
    off << 3.0 * std::cos(i), 3.0 * std::sin(i), 0.0, 0.0, 0.0, M_PI / 4;
    e.T_from_to = a.truth[7 * i + 1].inverse() * b.truth[11 * i + 5] * expSE3(off);
    inter.push_back(e);
    wrong.insert({e.from, e.to});
  }
  const std::vector<RobotDeformationInput> inputs =
      twoRobots(a, b, a.truth.front().inverse() * b.truth.front());
  DeformationGraphOptions ahead, own;
  ahead.use_sent_information = own.use_sent_information = true;
  ahead.whole_graph_analysis_ahead = true;
  const auto solve = [&](size_t closures, const std::set<std::pair<NodeId, NodeId>>& held_out,
                         bool expect_ahead, const char* what) {
    const std::vector<PoseGraphEdge> these(inter.begin(), inter.begin() + closures);
    const DeformationGraph graph = buildDeformationGraph(frontend, inputs, these, {}, ahead);
    int calls = 0;
    RobustVerdicts decided;
    const DeformationResult with =
        optimizeDeformationGraph(graph, ahead, held_out, nullptr, [&](const RobustVerdicts& v) {
          ++calls;
          decided = v;
        });
    const DeformationResult without = optimizeDeformationGraph(graph, own, held_out);
    // The verdicts handed on as GNC decided them are the result's.
    EXPECT_EQ(calls, 1) << what;
    EXPECT_EQ(decided, with.robust_inlier) << what;
    EXPECT_EQ(with.whole_graph_analyzed_ahead, expect_ahead) << what;
    EXPECT_FALSE(without.whole_graph_analyzed_ahead) << what;
    EXPECT_EQ(with.robust_inlier, without.robust_inlier) << what;
    ASSERT_EQ(with.poses.size(), without.poses.size()) << what;
    for (const auto& [id, pose] : with.poses)
      EXPECT_TRUE(pose.matrix() == without.poses.at(id).matrix()) << what << ": " << id.str();
    size_t kept_wrong = 0;
    for (const auto& edge : wrong) {
      const auto it = with.robust_inlier.find(edge);
      kept_wrong += it != with.robust_inlier.end() && it->second;
    }
    EXPECT_EQ(kept_wrong, 0u) << what;
  };
  solve(good, {}, true, "true closures");
  solve(inter.size(), {}, false, "wrong closures GNC rejects");
  solve(inter.size(), wrong, true, "wrong closures held out");
}

// A round after another, robot b 10 keyframes further: the whole-graph solve started from the
// last round's solution moves only the nodes near what changed, and ends where the solve of the
// whole graph ends, within the solver's own tolerance.
TEST(DeformationGraph, AWarmStartedRoundSolvesTheWholeGraphOnlyWhereItChanged) {
  SceneGraph later;
  Robot a = drive(RobotId(0), 0.0, 0.0, later);
  Robot b = drive(RobotId(1), M_PI, 0.0005, later);
  const std::vector<PoseGraphEdge> inter = trueClosures(a, b);
  const Eigen::Isometry3d T_global_b = a.truth.front().inverse() * b.truth.front();
  // Earlier: b's first 50 keyframes, control points and loop closures.
  constexpr size_t kEarlier = 50;
  SceneGraph earlier = later;
  for (size_t k = kEarlier; k < 60; ++k) earlier.removeNode(keyframe(b, k));
  Robot b_then = b;
  b_then.pose_graph.resize(kEarlier - 1);
  b_then.control_points.resize(kEarlier);
  b_then.control_point_edges.resize(kEarlier - 1);
  std::vector<PoseGraphEdge> inter_then;
  for (const PoseGraphEdge& e : inter) {
    if (e.to.index() < kEarlier) inter_then.push_back(e);
  }
  const auto inputs = [&](const Robot& robot_b) { return twoRobots(a, robot_b, T_global_b); };
  DeformationGraphOptions options;
  options.whole_graph_analysis_ahead = true;
  const DeformationResult then = optimizeDeformationGraph(
      buildDeformationGraph(earlier, inputs(b_then), inter_then, {}, options), options);
  DeformationWarmStart warm;
  warm.poses = then.solve.poses;
  warm.verdicts = then.robust_inlier;
  warm.last_whole = then.poses;
  warm.last_skeleton = then.solve.poses;

  const DeformationGraph graph = buildDeformationGraph(later, inputs(b), inter, {}, options);
  const DeformationResult local = optimizeDeformationGraph(graph, options, {}, &warm);
  DeformationGraphOptions everywhere = options;
  everywhere.local_whole_graph = false;
  const DeformationResult whole = optimizeDeformationGraph(graph, everywhere, {}, &warm);
  EXPECT_EQ(whole.whole_graph_free, graph.initial.size());
  EXPECT_GT(local.whole_graph_free, 20u);  // b's new keyframes and control points at least
  EXPECT_LT(local.whole_graph_free, graph.initial.size() / 2);
  double apart = 0.0;
  for (const auto& [id, pose] : whole.poses)
    apart = std::max(apart, (local.poses.at(id).translation() - pose.translation()).norm());
  EXPECT_LT(apart, 0.01);
  // The analysis made ahead for a whole-graph solve changes nothing in a local one.
  DeformationGraphOptions unaided = options;
  unaided.whole_graph_analysis_ahead = false;
  const DeformationResult alone = optimizeDeformationGraph(graph, unaided, {}, &warm);
  ASSERT_EQ(alone.poses.size(), local.poses.size());
  for (const auto& [id, pose] : alone.poses)
    EXPECT_TRUE(local.poses.at(id).matrix() == pose.matrix()) << id.str();
  // More changed than local_max_share allows: the whole graph, as without the option.
  DeformationGraphOptions narrow = options;
  narrow.local_max_share =
      0.5 * static_cast<double>(local.whole_graph_free) / static_cast<double>(graph.initial.size());
  narrow.local_deferred_share = narrow.local_max_share;  // none deferred
  const DeformationResult over = optimizeDeformationGraph(graph, narrow, {}, &warm);
  EXPECT_EQ(over.whole_graph_free, graph.initial.size());
  EXPECT_FALSE(over.whole_graph_deferred);
  for (const auto& [id, pose] : whole.poses)
    EXPECT_TRUE(over.poses.at(id).isApprox(pose, 1e-12)) << id.str();
  EXPECT_FALSE(local.whole_graph_deferred);
  // Within local_deferred_share: the local solve, and the next round owes a whole one.
  DeformationGraphOptions deferring = narrow;
  deferring.local_deferred_share = 1.0;
  const DeformationResult deferred = optimizeDeformationGraph(graph, deferring, {}, &warm);
  EXPECT_EQ(deferred.whole_graph_free, local.whole_graph_free);
  EXPECT_TRUE(deferred.whole_graph_deferred);
  for (const auto& [id, pose] : local.poses)
    EXPECT_TRUE(deferred.poses.at(id).isApprox(pose, 1e-12)) << id.str();
  DeformationWarmStart owed = warm;
  owed.whole_owed = true;
  const DeformationResult paid = optimizeDeformationGraph(graph, deferring, {}, &owed);
  EXPECT_EQ(paid.whole_graph_free, graph.initial.size());
  EXPECT_FALSE(paid.whole_graph_deferred);
  for (const auto& [id, pose] : whole.poses)
    EXPECT_TRUE(paid.poses.at(id).isApprox(pose, 1e-12)) << id.str();
}

// Robots a and b of the circle, true loop closures between them, and one object per robot beside
// each of three places both pass, with a merge candidate joining each pair (`wrong` more: a's
// object of the first place with b's of the second), as Backend::round's solve with merges has
// them; `loop_closures` is the solve before it, without merges.
struct ObjectsToMerge {
  SceneGraph frontend;
  Robot a, b;
  Eigen::Isometry3d T_global_b;
  std::vector<PoseGraphEdge> inter, merges;
  DeformationResult loop_closures;
  std::vector<RobotDeformationInput> inputs() const { return twoRobots(a, b, T_global_b); }
};

std::unique_ptr<ObjectsToMerge> objectsToMerge(const DeformationGraphOptions& skeleton,
                                               bool wrong) {
  auto s = std::make_unique<ObjectsToMerge>();
  s->a = drive(RobotId(0), 0.0, 0.0, s->frontend);
  s->b = drive(RobotId(1), M_PI, 0.005, s->frontend);
  s->inter = trueClosures(s->a, s->b);
  s->T_global_b = s->a.truth.front().inverse() * s->b.truth.front();
  std::vector<std::pair<NodeId, NodeId>> pairs;
  for (const size_t k : {9u, 21u, 45u}) {
    const size_t kb = (k + 30) % 60;
    const Eigen::Vector3d world = s->a.truth[k] * Eigen::Vector3d(0.0, 0.5, 0.0);
    const NodeId oa = NodeId::station('O', s->a.id, k), ob = NodeId::station('O', s->b.id, kb);
    Node na = makeNode(oa, Layer::kObjects, s->a.odom[k] * (s->a.truth[k].inverse() * world));
    na.last_update_time_ns = static_cast<int64_t>(k) * 1000000000;
    Node nb = makeNode(ob, Layer::kObjects, s->b.odom[kb] * (s->b.truth[kb].inverse() * world));
    nb.last_update_time_ns = static_cast<int64_t>(kb) * 1000000000;
    s->frontend.addOrUpdateNode(na);
    s->frontend.addOrUpdateNode(nb);
    pairs.push_back({oa, ob});
  }
  if (wrong) pairs.push_back({pairs[0].first, pairs[1].second});
  for (const auto& [from, to] : pairs) {
    PoseGraphEdge e;
    e.from = from;
    e.to = to;
    e.information = Matrix6d::Identity();
    s->merges.push_back(e);
  }
  s->loop_closures = optimizeDeformationGraph(
      buildDeformationGraph(s->frontend, s->inputs(), s->inter, {}, skeleton), skeleton);
  return s;
}

// The solve with merges after the loop closures' solve (Backend::round): objects that only the
// merge candidates bring in are not in the earlier solve's poses. Each starts at its tie to its
// keyframe, so the first solve, merges held out, starts at the earlier optimum: its cost does not
// fall. (At its aligned frontend position robot b's drift would put each metres off.)
TEST(DeformationGraph, ObjectsNewToTheSolveStartAtTheirKeyframe) {
  DeformationGraphOptions skeleton;
  skeleton.final_iterations = 0;
  const auto s = objectsToMerge(skeleton, false);
  DeformationWarmStart warm;
  warm.poses = s->loop_closures.poses;
  warm.verdicts = s->loop_closures.robust_inlier;
  const DeformationGraph graph =
      buildDeformationGraph(s->frontend, s->inputs(), s->inter, s->merges, skeleton);
  for (const PoseGraphEdge& e : s->merges) {
    ASSERT_TRUE(graph.skeleton.poses.count(e.from) && graph.skeleton.poses.count(e.to));
    ASSERT_FALSE(warm.poses.count(e.from) || warm.poses.count(e.to));
  }
  std::set<std::pair<NodeId, NodeId>> held_out;
  for (const PoseGraphEdge& e : s->merges) held_out.insert({e.from, e.to});
  std::vector<std::string> lines;
  skeleton.solver.progress = [&lines](const std::string& line) { lines.push_back(line); };
  optimizeDeformationGraph(graph, skeleton, held_out, &warm);
  ASSERT_FALSE(lines.empty());
  double start = 0.0, end = 0.0;
  ASSERT_EQ(std::sscanf(lines.front().c_str(),
                        "solve over the %*d inlier edges: %*d iterations in "
                        "%*f s, cost %lf -> %lf",
                        &start, &end),
            2)
      << lines.front();
  EXPECT_LE(start, end * 1.01 + 1e-9) << lines.front();
}

// A solve that stops at the skeleton (the loop closures' solve of a round) needs no factor of the
// whole graph: built for it, the graph holds the same skeleton, nodes and robust factors as the
// whole one, no whole-graph factor, and the solve gives the same poses and verdicts to the bit.
TEST(DeformationGraph, AGraphForTheSkeletonAloneSolvesAsTheWholeOne) {
  DeformationGraphOptions skeleton;
  skeleton.final_iterations = 0;
  const auto s = objectsToMerge(skeleton, true);
  const DeformationGraph whole =
      buildDeformationGraph(s->frontend, s->inputs(), s->inter, s->merges, {});
  const DeformationGraph alone =
      buildDeformationGraph(s->frontend, s->inputs(), s->inter, s->merges, skeleton);
  ASSERT_GT(whole.graph.edges.size(), whole.skeleton.edges.size());
  EXPECT_TRUE(alone.graph.edges.empty());
  EXPECT_TRUE(alone.graph.poses.empty());
  ASSERT_EQ(alone.skeleton.edges.size(), whole.skeleton.edges.size());
  for (size_t k = 0; k < whole.skeleton.edges.size(); ++k) {
    const PoseGraphEdge &a = alone.skeleton.edges[k], &w = whole.skeleton.edges[k];
    EXPECT_TRUE(a.from == w.from && a.to == w.to && a.kind == w.kind) << k;
    EXPECT_TRUE(a.T_from_to.isApprox(w.T_from_to, 0.0) && a.information == w.information) << k;
  }
  EXPECT_EQ(alone.skeleton.poses.size(), whole.skeleton.poses.size());
  EXPECT_EQ(alone.initial.size(), whole.initial.size());
  EXPECT_EQ(alone.observed_by, whole.observed_by);
  EXPECT_EQ(alone.anchor, whole.anchor);
  EXPECT_EQ(alone.robust_factors, whole.robust_factors);
  EXPECT_EQ(alone.inter_robot_factors, whole.inter_robot_factors);
  EXPECT_EQ(alone.merge_factors, whole.merge_factors);
  const DeformationResult from_whole = optimizeDeformationGraph(whole, skeleton);
  const DeformationResult from_alone = optimizeDeformationGraph(alone, skeleton);
  EXPECT_EQ(from_alone.robust_inlier, from_whole.robust_inlier);
  ASSERT_EQ(from_alone.poses.size(), from_whole.poses.size());
  for (const auto& [id, pose] : from_whole.poses)
    EXPECT_TRUE(from_alone.poses.at(id).isApprox(pose, 0.0)) << id.str();
}

// Merges new in an incremental round that fit the solve's start are known inliers there
// (DeformationWarmStart::admit_if_fitting): no solve without them, nothing to take back after it.
// A wrong one stays held out and rejected. The verdicts are those of holding all of them out.
TEST(DeformationGraph, NewMergesThatFitTheStartAreKnown) {
  DeformationGraphOptions skeleton;
  skeleton.final_iterations = 0;
  const auto s = objectsToMerge(skeleton, true);
  const DeformationGraph graph =
      buildDeformationGraph(s->frontend, s->inputs(), s->inter, s->merges, skeleton);
  DeformationWarmStart warm;
  warm.poses = s->loop_closures.poses;
  warm.verdicts = s->loop_closures.robust_inlier;
  std::set<std::pair<NodeId, NodeId>> held_out;
  for (const PoseGraphEdge& e : s->merges) held_out.insert({e.from, e.to});
  const DeformationResult all_held = optimizeDeformationGraph(graph, skeleton, held_out, &warm);
  warm.admit_if_fitting = held_out;
  const DeformationResult admitted = optimizeDeformationGraph(graph, skeleton, held_out, &warm);
  EXPECT_EQ(all_held.admitted, 0u);
  EXPECT_EQ(admitted.admitted, 3u);
  EXPECT_EQ(admitted.robust_inlier, all_held.robust_inlier);
  for (size_t i = 0; i < s->merges.size(); ++i) {
    const bool inlier = admitted.robust_inlier.at({s->merges[i].from, s->merges[i].to});
    EXPECT_EQ(inlier, i < 3) << "merge " << i;
  }
  EXPECT_FALSE(all_held.solve.held_out_poses.empty());  // the three taken back after a solve
  EXPECT_TRUE(admitted.solve.held_out_poses.empty());
  EXPECT_LT(admitted.solve.solves, all_held.solve.solves);
}

// Merges held out of GNC are expected back (it takes back those that fit): the whole graph's
// analysis made ahead counts them in, and is taken where GNC took every one back (three true
// merges), not where it left one out (a wrong fourth); the same poses to the bit as without.
TEST(DeformationGraph, TheWholeGraphAnalysisMadeAheadCountsHeldOutMergesIn) {
  for (const bool wrong : {false, true}) {
    DeformationGraphOptions ahead;
    ahead.whole_graph_analysis_ahead = true;
    const auto s = objectsToMerge(ahead, wrong);
    const DeformationGraph graph =
        buildDeformationGraph(s->frontend, s->inputs(), s->inter, s->merges, ahead);
    ASSERT_EQ(graph.merge_factors.size(), s->merges.size());
    DeformationWarmStart warm;
    warm.poses = s->loop_closures.poses;
    warm.verdicts = s->loop_closures.robust_inlier;
    std::set<std::pair<NodeId, NodeId>> held_out;
    for (const PoseGraphEdge& e : s->merges) held_out.insert({e.from, e.to});
    DeformationGraphOptions own = ahead;
    own.whole_graph_analysis_ahead = false;
    const DeformationResult with = optimizeDeformationGraph(graph, ahead, held_out, &warm);
    const DeformationResult without = optimizeDeformationGraph(graph, own, held_out, &warm);
    size_t kept = 0;
    for (const PoseGraphEdge& e : s->merges) kept += with.robust_inlier.at({e.from, e.to});
    EXPECT_EQ(kept, 3u) << wrong;
    EXPECT_EQ(with.whole_graph_analyzed_ahead, !wrong);
    EXPECT_EQ(with.robust_inlier, without.robust_inlier) << wrong;
    ASSERT_EQ(with.poses.size(), without.poses.size());
    for (const auto& [id, pose] : with.poses)
      EXPECT_TRUE(pose.matrix() == without.poses.at(id).matrix()) << wrong << ": " << id.str();
  }
}

// A robot passes a corridor twice, and its odometry turned 3 degrees too little at the turn between
// the passes: in its own map the way back runs onto the way out, up to 1 m at the far end, and the
// control points it made on the way back sit beside, and are tied by its mesh edges to, those of
// the way out at their drifted offsets. Loop closures with an exact robot along both passes hold
// the truth. Ties only between what the robot made within link_max_dt_s of each other let the way
// back go where the loop closures put it; ties of any age hold it at its drift.
TEST(DeformationGraph, MeshTiesAcrossARevisitDoNotHoldTheDrift) {
  constexpr int64_t kS = 1000000000;
  const RobotId ra(0), rb(1);
  SceneGraph frontend;
  const auto pose = [](double x, double y, double yaw) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.translation() << x, y, 0.0;
    T.linear() = Eigen::AngleAxisd(yaw, Eigen::Vector3d::UnitZ()).toRotationMatrix();
    return T;
  };
  struct Run {
    std::vector<Eigen::Isometry3d> truth, odom;
    std::vector<PoseGraphEdge> pose_graph;
    std::vector<ControlPoint> control_points;
    std::vector<ControlPointEdge> control_point_edges;
  } a, b;
  // a: along y = 0, exact. b: out along y = 0.5 (t = 0-20 s), back along y = -0.5 (t = 21-41 s).
  for (int k = 0; k <= 20; ++k) a.truth.push_back(pose(k, 0.0, 0.0));
  a.odom = a.truth;
  for (int k = 0; k <= 20; ++k) b.truth.push_back(pose(k, 0.5, 0.0));
  for (int k = 20; k >= 0; --k) b.truth.push_back(pose(k, -0.5, M_PI));
  b.odom.push_back(Eigen::Isometry3d::Identity());
  for (size_t k = 1; k < b.truth.size(); ++k) {
    Eigen::Isometry3d step = b.truth[k - 1].inverse() * b.truth[k];
    if (k == 21) step = step * pose(0, 0, -3.0 * M_PI / 180.0);
    b.odom.push_back(b.odom.back() * step);
  }
  const auto kf = [](RobotId r, size_t k) { return NodeId::station(r.prefix(), r, k); };
  for (const auto& [robot, run] : {std::pair<RobotId, Run*>{ra, &a}, {rb, &b}}) {
    for (size_t k = 0; k < run->odom.size(); ++k) {
      const int64_t t = static_cast<int64_t>(k) * kS;
      Node node = makeNode(kf(robot, k), Layer::kAgents, run->odom[k].translation());
      node.find<AgentAttributes>()->orientation = Eigen::Quaterniond(run->odom[k].linear());
      node.find<AgentAttributes>()->timestamp_ns = t;
      frontend.addOrUpdateNode(node);
      if (k > 0) {
        PoseGraphEdge e;
        e.from = kf(robot, k - 1);
        e.to = kf(robot, k);
        e.T_from_to = run->odom[k - 1].inverse() * run->odom[k];
        run->pose_graph.push_back(e);
      }
      // A control point 1 m to the side, away from the other lane.
      run->control_points.push_back({k, run->odom[k] * Eigen::Vector3d(0, 1, 0), t, kf(robot, k)});
      if (k > 0) run->control_point_edges.push_back({k - 1, k});
    }
  }
  // b's mesh edges between its passes: each control point of the way back to the way out's
  // nearest one in b's own map.
  for (size_t k = 21; k < b.control_points.size(); ++k) {
    size_t nearest = 0;
    for (size_t j = 1; j <= 20; ++j) {
      if ((b.control_points[j].position - b.control_points[k].position).norm() <
          (b.control_points[nearest].position - b.control_points[k].position).norm())
        nearest = j;
    }
    b.control_point_edges.push_back({nearest, k});
  }
  // A place b mapped on the way back, 0.6 m to the side of its keyframe 39 (x = 2); in b's map
  // a keyframe of the way out lies nearer.
  const NodeId place = NodeId::station('p', rb, 0);
  const Eigen::Vector3d place_offset(0.0, -0.6, 0.0);
  Node place_node = makeNode(place, Layer::kPlaces, b.odom[39] * place_offset);
  place_node.last_update_time_ns = 39 * kS;
  frontend.addOrUpdateNode(place_node);
  size_t nearest_to_place = 0;
  for (size_t k = 1; k < b.odom.size(); ++k) {
    if ((b.odom[k].translation() - place_node.position).norm() <
        (b.odom[nearest_to_place].translation() - place_node.position).norm())
      nearest_to_place = k;
  }
  ASSERT_LE(nearest_to_place, 20u);
  std::vector<PoseGraphEdge> inter;
  for (size_t k = 0; k < b.truth.size(); k += 2) {
    PoseGraphEdge e;
    const size_t j = k <= 20 ? k : 41 - k;  // a's keyframe beside b's
    e.from = kf(ra, j);
    e.to = kf(rb, k);
    e.T_from_to = a.truth[j].inverse() * b.truth[k];
    inter.push_back(e);
  }
  const std::vector<RobotDeformationInput> inputs = {
      {ra, Eigen::Isometry3d::Identity(), &a.pose_graph, &a.control_points, &a.control_point_edges},
      {rb, b.truth.front(), &b.pose_graph, &b.control_points, &b.control_point_edges}};
  // The worst keyframe error of b and the place's error after the solve.
  const auto errors = [&](double link_max_dt_s) {
    DeformationGraphOptions options;
    options.link_max_dt_s = link_max_dt_s;
    const DeformationGraph graph = buildDeformationGraph(frontend, inputs, inter, {}, options);
    const DeformationResult result = optimizeDeformationGraph(graph, options);
    double worst = 0.0;
    for (size_t k = 0; k < b.truth.size(); ++k)
      worst = std::max(
          worst, (result.poses.at(kf(rb, k)).translation() - b.truth[k].translation()).norm());
    const double place_error =
        (result.poses.at(place).translation() - b.truth[39] * place_offset).norm();
    return std::make_pair(worst, place_error);
  };
  const double drift =
      (b.truth.front() * b.odom.back().translation() - b.truth.back().translation()).norm();
  EXPECT_GT(drift, 0.9);
  const auto [worst_keyframe, place_error] = errors(10.0);
  EXPECT_LT(worst_keyframe, 0.15);
  EXPECT_LT(place_error, 0.15);
  const auto [worst_keyframe_any_age, place_error_any_age] = errors(0.0);
  EXPECT_GT(worst_keyframe_any_age, 0.3);
  EXPECT_GT(place_error_any_age, 0.3);
}

// An object is of the time of its vertices (the median), not of its last update: seen on a first
// pass, detected on a second one. Without its robot's mesh, or for other nodes, the last update.
TEST(DeformationGraph, AnObjectIsOfTheTimeOfItsVertices) {
  constexpr int64_t kS = 1000000000;
  Mesh mesh;
  for (const int64_t t : {4 * kS, 5 * kS, 6 * kS, 590 * kS}) {
    MeshVertex v;
    v.time_ns = t;
    mesh.vertices.push_back(v);
  }
  Node object = makeNode(NodeId('O', 0), Layer::kObjects, Eigen::Vector3d::Zero());
  object.last_update_time_ns = 591 * kS;
  object.find<ObjectAttributes>()->mesh_vertices = {0, 1, 2, 7};  // 7: not in the mesh
  EXPECT_EQ(madeAtNs(object, &mesh), 5 * kS);
  EXPECT_EQ(madeAtNs(object, nullptr), 591 * kS);
  object.find<ObjectAttributes>()->mesh_vertices = {};
  EXPECT_EQ(madeAtNs(object, &mesh), 591 * kS);
  Node place = makeNode(NodeId('p', 0), Layer::kPlaces, Eigen::Vector3d::Zero());
  place.last_update_time_ns = 42 * kS;
  EXPECT_EQ(madeAtNs(place, &mesh), 42 * kS);
}

// The backend graph in two steps: unplaced, the frontend's nodes, edges and positions; placed,
// keyframes at their solved poses, an object (no mesh) moved as its nearest control point of its
// time, and a keyframe the poses lack gone with its edges.
TEST(DeformationGraph, TheBackendGraphIsMadeUnplacedThenPlacedAtTheSolvedPoses) {
  SceneGraph frontend;
  Robot a = drive(RobotId(0), 0.0, 0.0, frontend);
  Robot b = drive(RobotId(1), M_PI, 0.005, frontend);
  Node object = makeNode(NodeId::station('O', b.id, 0), Layer::kObjects, b.odom[10].translation());
  object.last_update_time_ns = 10 * 1000000000LL;
  frontend.addOrUpdateNode(object);
  for (size_t k = 1; k < 60; ++k) frontend.addOrUpdateEdge(keyframe(b, k - 1), keyframe(b, k));
  const Eigen::Isometry3d T_global_b = a.truth.front().inverse() * b.truth.front();
  const std::vector<RobotDeformationInput> inputs = twoRobots(a, b, T_global_b);
  const DeformationGraph graph =
      buildDeformationGraph(frontend, inputs, trueClosures(a, b), {}, {});
  const DeformationResult result = optimizeDeformationGraph(graph);

  SceneGraph map = unplacedMap(frontend, inputs);
  EXPECT_EQ(map.numNodes(), 121u);
  EXPECT_EQ(map.numEdges(), 59u);
  EXPECT_EQ(map.getNode(keyframe(b, 5)).position, frontend.getNode(keyframe(b, 5)).position);

  std::map<NodeId, Eigen::Isometry3d> poses = result.poses;
  poses.erase(keyframe(b, 59));
  std::map<RobotId, Eigen::Isometry3d> first;
  // The placements asked for are given also for a node the map no longer holds (merged away).
  SceneGraph merged_away = map;
  merged_away.removeNode(object.id);
  std::map<NodeId, Placement> placements = {{object.id, {}}, {keyframe(b, 5), {}}};
  placeMap(merged_away, frontend, inputs, graph, poses, {}, 4, nullptr, nullptr, &placements);
  placeMap(map, frontend, inputs, graph, poses, {}, 4, &first);
  EXPECT_EQ(placements.at(object.id).position, map.getNode(object.id).position);
  EXPECT_EQ(placements.at(keyframe(b, 5)).position, map.getNode(keyframe(b, 5)).position);
  EXPECT_EQ(merged_away.getNode(keyframe(b, 5)).position, map.getNode(keyframe(b, 5)).position);
  EXPECT_FALSE(map.hasNode(keyframe(b, 59)));
  EXPECT_EQ(map.numEdges(), 58u);
  EXPECT_EQ(map.getNode(keyframe(b, 5)).position, result.poses.at(keyframe(b, 5)).translation());
  EXPECT_TRUE(first.at(b.id).isApprox(result.poses.at(keyframe(b, 0))));
  // The object rides with the control point of its keyframe (1 m beside it).
  const NodeId cp = controlPointId(b.id, 10);
  const Eigen::Vector3d expected =
      result.poses.at(cp) * graph.initial.at(cp).inverse() * (T_global_b * object.position);
  EXPECT_GT((expected - T_global_b * object.position).norm(), 0.05);
  EXPECT_LT((map.getNode(object.id).position - expected).norm(), 1e-9);
}

// On a coarser grid, each voxel keeps the first control point the robot made in it, and the
// rigidity edges join the kept points of their ends' voxels, once each; a robot's later points
// only add to the result.
TEST(DeformationGraph, CoarserControlPointsKeepTheFirstOfEachVoxel) {
  // A 2.5 m lattice of 4 x 2 points along x and y (ids 0-7, made in that order), a 5 m grid.
  std::vector<ControlPoint> points;
  std::vector<ControlPointEdge> edges;
  for (uint64_t id = 0; id < 8; ++id) {
    ControlPoint cp;
    cp.id = id;
    cp.position = {2.5 * double(id % 4) + 0.1, 2.5 * double(id / 4) + 0.1, 0.0};
    cp.time_ns = int64_t(id) * 1'000'000'000;
    points.push_back(cp);
    if (id % 4 != 0) edges.push_back({id - 1, id});  // along x
    if (id >= 4) edges.push_back({id - 4, id});      // along y
  }
  const ControlPointGraph coarse = coarserControlPoints(points, edges, 5.0);
  // Voxels [0, 5) and [5, 10) in x, one in y: points 0 and 2 kept, 1, 4, 5 join 0 and 3, 6, 7
  // join 2.
  ASSERT_EQ(coarse.points.size(), 2u);
  EXPECT_EQ(coarse.points[0], points[0]);
  EXPECT_EQ(coarse.points[1], points[2]);
  // Edges within a voxel vanish; the two across (1-2 and 5-6) become one edge 0-2.
  ASSERT_EQ(coarse.edges.size(), 1u);
  EXPECT_EQ(coarse.edges[0], (ControlPointEdge{0, 2}));
  // The first points alone give a prefix of the result.
  const ControlPointGraph earlier = coarserControlPoints({points.begin(), points.begin() + 2},
                                                         {edges.begin(), edges.begin() + 1}, 5.0);
  ASSERT_EQ(earlier.points.size(), 1u);
  EXPECT_EQ(earlier.points[0], points[0]);
  EXPECT_TRUE(earlier.edges.empty());
  // A voxel no larger than the points' spacing keeps them all.
  const ControlPointGraph same = coarserControlPoints(points, edges, 2.5);
  EXPECT_EQ(same.points, points);
  EXPECT_EQ(same.edges.size(), edges.size());
}

}  // namespace
}  // namespace hydra_multi
