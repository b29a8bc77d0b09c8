#include <gtest/gtest.h>

#include <fstream>
#include <functional>
#include <random>
#include <regex>
#include <set>

#include "hydra_multi/optim/io/g2o_format.h"
#include "hydra_multi/optim/robust_pose_graph.h"
#include "support/random_graphs.h"

namespace hydra_multi {
namespace {

struct Classification {
  double precision = 0, recall = 0;
};

// grid1000 with labelled outliers (gt_info.xml lists the 1-based indices of inlier loop
// closures).
struct LabelledGraph {
  PoseGraph graph;
  std::set<size_t> inliers;
};
LabelledGraph readLabelledGrid(const std::string& name) {
  const std::string dir = testing::dataDir() + "/pgo/" + name;
  auto file = io::readG2o(dir + "/measurements.g2o");
  EXPECT_TRUE(file.ok()) << file.error();
  LabelledGraph labelled{file.value().graph, {}};
  classifyEdges(labelled.graph);
  std::ifstream xml(dir + "/gt_info.xml");
  const std::string text((std::istreambuf_iterator<char>(xml)), std::istreambuf_iterator<char>());
  const std::regex tag("<inlier_lc_indices>(\\d+)</inlier_lc_indices>");
  for (auto it = std::sregex_iterator(text.begin(), text.end(), tag); it != std::sregex_iterator();
       ++it) {
    labelled.inliers.insert(std::stoul((*it)[1]) - 1);
  }
  EXPECT_GT(labelled.inliers.size(), 300u);
  return labelled;
}

Classification classify(const LabelledGraph& g, const RobustPgoResult& result) {
  size_t true_positive = 0, predicted = 0;
  for (size_t k = 0; k < g.graph.edges.size(); ++k) {
    if (g.graph.edges[k].kind != PoseGraphEdge::Kind::kLoopClosure) continue;
    predicted += result.edge_inlier[k] ? 1 : 0;
    true_positive += (result.edge_inlier[k] && g.inliers.count(k)) ? 1 : 0;
  }
  return {double(true_positive) / double(predicted),
          double(true_positive) / double(g.inliers.size())};
}

Classification classifyGrid(const std::string& name) {
  const LabelledGraph g = readLabelledGrid(name);
  const NodeId anchor(0, 0);
  return classify(g, optimizePoseGraph(g.graph, odometryInitialization(g.graph, anchor), anchor));
}

// Options that take `batch`'s verdicts: known inliers, the rejected held out, and so are the loop
// closures `doubt` names.
RobustPgoOptions asDecided(const LabelledGraph& g, const RobustPgoResult& batch,
                           const std::function<bool(size_t)>& doubt = nullptr) {
  RobustPgoOptions options;
  options.known_inlier.assign(g.graph.edges.size(), false);
  options.held_out.assign(g.graph.edges.size(), false);
  for (size_t k = 0; k < g.graph.edges.size(); ++k) {
    if (g.graph.edges[k].kind != PoseGraphEdge::Kind::kLoopClosure) continue;
    const bool held = (doubt && doubt(k)) || !batch.edge_inlier[k];
    (held ? options.held_out : options.known_inlier)[k] = true;
  }
  return options;
}

// Loop closures new beside many known ones are decided on GNC's faster incremental schedule, the
// same as on the full one; a batch without known verdicts keeps the full schedule.
TEST(RobustPoseGraph, FewNewLoopClosuresTakeTheIncrementalSchedule) {
  const LabelledGraph g = readLabelledGrid("grid1000_10p_outliers");
  const NodeId anchor(0, 0);
  const auto initial = odometryInitialization(g.graph, anchor);
  RobustPgoOptions full_schedule;
  full_schedule.incremental_mu_step = 1.0;
  const RobustPgoResult batch = optimizePoseGraph(g.graph, initial, anchor);
  const RobustPgoResult batch_full = optimizePoseGraph(g.graph, initial, anchor, full_schedule);
  EXPECT_EQ(batch.gnc.iterations, batch_full.gnc.iterations);
  EXPECT_EQ(batch.edge_inlier, batch_full.edge_inlier);

  // Every tenth loop closure undecided (inliers and outliers among them), the others as decided.
  size_t seen = 0, undecided = 0;
  RobustPgoOptions incremental = asDecided(g, batch);
  for (size_t k = 0; k < g.graph.edges.size(); ++k) {
    if (g.graph.edges[k].kind != PoseGraphEdge::Kind::kLoopClosure || seen++ % 10 != 0) continue;
    incremental.known_inlier[k] = incremental.held_out[k] = false;
    ++undecided;
  }
  ASSERT_GT(undecided, 20u);
  RobustPgoOptions full = incremental;
  full.incremental_mu_step = 1.0;
  const RobustPgoResult fast = optimizePoseGraph(g.graph, batch.poses, anchor, incremental);
  const RobustPgoResult slow = optimizePoseGraph(g.graph, batch.poses, anchor, full);
  EXPECT_EQ(fast.edge_inlier, slow.edge_inlier);
  EXPECT_EQ(fast.edge_inlier, batch.edge_inlier);
  EXPECT_LT(fast.gnc.iterations, slow.gnc.iterations);
}

// A solve that takes an earlier solve's verdicts (known inliers, the rejected held out) and starts
// from its poses decides the same without GNC's schedule; known inliers that are wrong (true
// outliers given as inliers) are contradicted by the result and rejected.
TEST(RobustPoseGraph, KnownVerdictsAreKeptUnlessTheResultContradictsThem) {
  const LabelledGraph g = readLabelledGrid("grid1000_10p_outliers");
  const NodeId anchor(0, 0);
  const RobustPgoResult batch =
      optimizePoseGraph(g.graph, odometryInitialization(g.graph, anchor), anchor);
  RobustPgoOptions warm = asDecided(g, batch);
  size_t wrong_given = 0;
  const RobustPgoResult again = optimizePoseGraph(g.graph, batch.poses, anchor, warm);
  EXPECT_EQ(again.edge_inlier, batch.edge_inlier);
  EXPECT_EQ(again.known_contradicted, 0u);
  EXPECT_LE(again.solves, 2);
  EXPECT_GT(batch.solves, 5);

  // Twenty true outliers given as known inliers, from the batch's poses.
  for (size_t k = 0; k < g.graph.edges.size() && wrong_given < 20; ++k) {
    if (g.graph.edges[k].kind != PoseGraphEdge::Kind::kLoopClosure || g.inliers.count(k)) continue;
    warm.known_inlier[k] = true;
    warm.held_out[k] = false;
    ++wrong_given;
  }
  ASSERT_EQ(wrong_given, 20u);
  const RobustPgoResult contradicted = optimizePoseGraph(g.graph, batch.poses, anchor, warm);
  EXPECT_GE(contradicted.known_contradicted, 20u);
  const Classification c = classify(g, contradicted);
  EXPECT_GE(c.precision, 0.99);
  EXPECT_GE(c.recall, 0.98);
}

// grid1000 with every third true inlier held out (doubted) and the rest as a batch decided them:
// the first solve, which re-admits the doubted ones that fit, and a second one from its held-out
// solution (leaves from its final one) that knows no earlier solve.
struct Readmission {
  LabelledGraph g = readLabelledGrid("grid1000_10p_outliers");
  NodeId anchor{0, 0};
  RobustPgoOptions options;
  RobustPgoResult first, plain;
  std::map<NodeId, Eigen::Isometry3d> start;

  Readmission() {
    const RobustPgoResult batch =
        optimizePoseGraph(g.graph, odometryInitialization(g.graph, anchor), anchor);
    size_t held = 0;
    options = asDecided(g, batch, [&](size_t k) { return g.inliers.count(k) && held++ % 3 == 0; });
    first = optimizePoseGraph(g.graph, batch.poses, anchor, options);
    start = first.poses;
    for (const auto& [id, pose] : first.held_out_poses) start[id] = pose;
    plain = optimizePoseGraph(g.graph, start, anchor, options);
  }
  /// The options with the first solve as the earlier one.
  RobustPgoOptions withEarlier() const {
    RobustPgoOptions earlier = options;
    earlier.earlier_held_out = first.held_out_poses;
    earlier.earlier_readmitted = first.poses;
    return earlier;
  }
};

// A later solve of the same problem that knows the earlier one's solutions without and with what
// it re-admitted starts its re-admission solve where the earlier one's ended: the same verdicts
// and optimum, in fewer iterations than from the held-out solution.
TEST(RobustPoseGraph, ReadmissionStartsWhereTheEarlierOneEnded) {
  const Readmission r;
  ASSERT_FALSE(r.first.held_out_poses.empty());  // they fit, and were re-admitted
  const RobustPgoResult again = optimizePoseGraph(r.g.graph, r.start, r.anchor, r.withEarlier());
  EXPECT_EQ(again.edge_inlier, r.first.edge_inlier);
  EXPECT_EQ(r.plain.edge_inlier, r.first.edge_inlier);
  EXPECT_NEAR(again.final_cost, r.first.final_cost, 1e-6 * r.first.final_cost);
  EXPECT_LT(again.solver_time.iterations, r.plain.solver_time.iterations);
  double apart = 0.0;  // the same optimum, to the solver's tolerance
  for (const auto& [id, pose] : r.first.poses)
    apart = std::max(apart, (again.poses.at(id).translation() - pose.translation()).norm());
  EXPECT_LT(apart, 0.01);
}

// An earlier solve that fits this one's inliers worse than the solution a re-admission adds to
// (here its poses 0.5 m off at random) is not where the next solve starts.
TEST(RobustPoseGraph, ReadmissionKeepsItsOwnSolutionWhereTheEarlierOneFitsWorse) {
  const Readmission r;
  ASSERT_FALSE(r.first.held_out_poses.empty());
  RobustPgoOptions earlier = r.withEarlier();
  std::mt19937 rng(3);
  std::normal_distribution<double> noise(0.0, 0.5);
  for (auto& [id, pose] : earlier.earlier_readmitted)
    pose.translation() += Eigen::Vector3d(noise(rng), noise(rng), noise(rng));
  const RobustPgoResult again = optimizePoseGraph(r.g.graph, r.start, r.anchor, earlier);
  EXPECT_EQ(again.edge_inlier, r.plain.edge_inlier);
  EXPECT_NEAR(again.final_cost, r.plain.final_cost, 1e-6 * r.plain.final_cost);
  EXPECT_EQ(again.solver_time.iterations, r.plain.solver_time.iterations);
}

// A re-admission that follows a solve after an earlier one, and is smaller than
// readmit_unsolved_share of the inliers, is taken back without solving again: fewer iterations,
// the loop closures only its solve would have shown to fit left rejected, and a later solve with
// its verdicts (the rejected held out) takes them back and ends where the whole cascade ended.
TEST(RobustPoseGraph, AFewReadmittedAfterASolveAreLeftToALaterSolve) {
  const Readmission r;
  RobustPgoOptions whole = r.options;
  whole.reduce_chains = false;  // as the station solves: the result is the last polish's
  RobustPgoOptions cut = whole;
  cut.readmit_unsolved_share = 0.01;
  const RobustPgoResult cascade = optimizePoseGraph(r.g.graph, r.start, r.anchor, whole);
  const RobustPgoResult quick = optimizePoseGraph(r.g.graph, r.start, r.anchor, cut);
  EXPECT_LT(quick.solver_time.iterations, cascade.solver_time.iterations);
  size_t tail = 0;
  for (size_t k = 0; k < r.g.graph.edges.size(); ++k) {
    if (quick.edge_inlier[k]) {
      EXPECT_TRUE(cascade.edge_inlier[k]) << "edge " << k;
    } else {
      tail += cascade.edge_inlier[k] ? 1 : 0;
    }
  }
  EXPECT_GT(tail, 0u);
  // What was taken back fits the result; what is left rejected does not.
  std::vector<size_t> rejected;
  for (size_t k = 0; k < r.g.graph.edges.size(); ++k) {
    if (r.g.graph.edges[k].kind == PoseGraphEdge::Kind::kLoopClosure && !quick.edge_inlier[k])
      rejected.push_back(k);
  }
  EXPECT_TRUE(edgesThatFit(r.g.graph, rejected, quick.poses, r.anchor, cut).empty());
  const RobustPgoResult later =
      optimizePoseGraph(r.g.graph, quick.poses, r.anchor, asDecided(r.g, quick));
  EXPECT_EQ(later.edge_inlier, cascade.edge_inlier);
  EXPECT_NEAR(later.final_cost, cascade.final_cost, 1e-4 * cascade.final_cost);
  // The result names what it took back unsolved: the cascade's second step.
  EXPECT_FALSE(quick.readmitted_unsolved.empty());
  for (const size_t k : quick.readmitted_unsolved) EXPECT_TRUE(quick.edge_inlier[k]) << k;
  EXPECT_TRUE(cascade.readmitted_unsolved.empty());
  // From the first re-admission on (readmit_unsolved_first): the cascade's first step, unsolved.
  RobustPgoOptions from_first = cut;
  from_first.readmit_unsolved_first = true;
  from_first.readmit_unsolved_share = 0.5;
  const RobustPgoResult first = optimizePoseGraph(r.g.graph, r.start, r.anchor, from_first);
  EXPECT_LT(first.solves, quick.solves);
  EXPECT_GT(first.readmitted_unsolved.size(), quick.readmitted_unsolved.size());
  for (const size_t k : first.readmitted_unsolved) {
    EXPECT_TRUE(first.edge_inlier[k]) << k;
    EXPECT_TRUE(cascade.edge_inlier[k]) << k;
  }
}

// GNC's last solve, converged on weights of 0 or 1, kept as the first solve over the inliers: one
// solve fewer, the same verdicts, and the inliers' optimum to the solver's tolerance.
TEST(RobustPoseGraph, AConvergedGncSolveStandsAsTheSolveOverTheInliers) {
  const LabelledGraph g = readLabelledGrid("grid1000_10p_outliers");
  const NodeId anchor(0, 0);
  const auto initial = odometryInitialization(g.graph, anchor);
  RobustPgoOptions again;
  again.reduce_chains = false;  // as the station solves
  RobustPgoOptions keep = again;
  keep.keep_converged_gnc_solve = true;
  const RobustPgoResult solved = optimizePoseGraph(g.graph, initial, anchor, again);
  const RobustPgoResult kept = optimizePoseGraph(g.graph, initial, anchor, keep);
  ASSERT_EQ(kept.gnc.stop_reason, "weights converged");
  EXPECT_EQ(kept.solves + 1, solved.solves);
  EXPECT_LT(kept.solver_time.iterations, solved.solver_time.iterations);
  EXPECT_EQ(kept.edge_inlier, solved.edge_inlier);
  // The kept solution is the inliers' optimum: solving over them again barely lowers its cost.
  RobustPgoOptions over = asDecided(g, kept);
  over.readmit_consistent = false;
  const RobustPgoResult polished = optimizePoseGraph(g.graph, kept.poses, anchor, over);
  EXPECT_LE(polished.solver_time.iterations, 2);
  EXPECT_NEAR(polished.final_cost, solved.final_cost, 1e-4 * solved.final_cost);
  EXPECT_GE(classify(g, kept).precision, 0.99);
  EXPECT_GE(classify(g, kept).recall, 0.98);
  // GNC's solves cut at one iteration: the last one did not converge, and the inliers are solved.
  again.gnc_inner_iterations = keep.gnc_inner_iterations = 1;
  const RobustPgoResult cut = optimizePoseGraph(g.graph, initial, anchor, again);
  const RobustPgoResult cut_kept = optimizePoseGraph(g.graph, initial, anchor, keep);
  EXPECT_EQ(cut_kept.solves, cut.solves);
  EXPECT_EQ(cut_kept.final_cost, cut.final_cost);
}

// Poses with one known-inlier edge (a place tied to its keyframe) are solved after the rest: the
// others come out as without them, each leaf where its edge puts it, the leaf edges inliers.
TEST(RobustPoseGraph, LeavesAreSolvedAfterTheRest) {
  const LabelledGraph g = readLabelledGrid("grid1000_10p_outliers");
  const NodeId anchor(0, 0);
  const auto initial = odometryInitialization(g.graph, anchor);
  const RobustPgoResult without = optimizePoseGraph(g.graph, initial, anchor);
  PoseGraph with = g.graph;
  auto with_initial = initial;
  std::mt19937 rng(5);
  std::uniform_int_distribution<size_t> pick(0, initial.size() - 1);
  std::normal_distribution<double> noise(0.0, 0.3);
  // Leaves hang from poses that are none themselves (a leaf of the plain graph would no longer
  // be one, and be solved, to the solver's tolerance, instead of placed).
  std::map<NodeId, int> degree;
  for (const PoseGraphEdge& e : g.graph.edges) {
    ++degree[e.from];
    ++degree[e.to];
  }
  std::vector<NodeId> ids;
  for (const auto& [id, count] : degree) {
    if (count > 1) ids.push_back(id);
  }
  pick = std::uniform_int_distribution<size_t>(0, ids.size() - 1);
  for (uint64_t k = 0; k < 200; ++k) {
    PoseGraphEdge e;
    e.to = NodeId('L', k);
    e.from = ids[pick(rng)];
    e.T_from_to = Eigen::Isometry3d::Identity();
    e.T_from_to.translation() = Eigen::Vector3d(noise(rng), noise(rng), 1.0);
    e.T_from_to.linear() =
        Eigen::AngleAxisd(noise(rng), Eigen::Vector3d::UnitZ()).toRotationMatrix();
    e.information = Matrix6d::Identity();
    e.kind = PoseGraphEdge::Kind::kOdometry;
    if (k % 2 == 1) {  // half of them as the edge's "from" end
      std::swap(e.from, e.to);
      e.T_from_to = e.T_from_to.inverse();
    }
    with.edges.push_back(e);
    with_initial[NodeId('L', k)] = Eigen::Isometry3d::Identity();
  }
  const RobustPgoResult result = optimizePoseGraph(with, with_initial, anchor);
  ASSERT_EQ(result.edge_inlier.size(), with.edges.size());
  for (size_t k = 0; k < g.graph.edges.size(); ++k)
    EXPECT_EQ(result.edge_inlier[k], without.edge_inlier[k]) << "edge " << k;
  for (const auto& [id, pose] : without.poses)
    EXPECT_LT((result.poses.at(id).matrix() - pose.matrix()).norm(), 1e-9) << id.str();
  for (size_t k = g.graph.edges.size(); k < with.edges.size(); ++k) {
    const PoseGraphEdge& e = with.edges[k];
    EXPECT_TRUE(result.edge_inlier[k]);
    const Eigen::Isometry3d residual =
        e.T_from_to.inverse() * result.poses.at(e.from).inverse() * result.poses.at(e.to);
    EXPECT_LT((residual.matrix() - Eigen::Matrix4d::Identity()).norm(), 1e-9);
  }
}

// Held-out and known-inlier flags stay with their edges when leaves sit between them: grid1000
// with a leaf edge before every tenth edge decides every edge as the plain graph does with the
// same flags (every third true inlier doubted, the rest as a batch decided them).
TEST(RobustPoseGraph, FlagsStayWithTheirEdgesAmongLeaves) {
  const LabelledGraph g = readLabelledGrid("grid1000_10p_outliers");
  const NodeId anchor(0, 0);
  const RobustPgoResult batch =
      optimizePoseGraph(g.graph, odometryInitialization(g.graph, anchor), anchor);
  size_t held = 0;
  const RobustPgoOptions decided =
      asDecided(g, batch, [&](size_t k) { return g.inliers.count(k) && held++ % 3 == 0; });
  const RobustPgoResult plain = optimizePoseGraph(g.graph, batch.poses, anchor, decided);
  ASSERT_FALSE(plain.held_out_poses.empty());  // doubted ones fit, and were re-admitted

  std::map<NodeId, int> degree;
  for (const PoseGraphEdge& e : g.graph.edges) {
    ++degree[e.from];
    ++degree[e.to];
  }
  PoseGraph with;
  RobustPgoOptions shifted;
  std::vector<size_t> at;  // per edge of the plain graph, its index in `with`
  auto initial = batch.poses;
  for (size_t k = 0; k < g.graph.edges.size(); ++k) {
    const PoseGraphEdge& e = g.graph.edges[k];
    if (k % 10 == 0 && degree[e.from] > 1) {
      PoseGraphEdge leaf;
      leaf.from = e.from;
      leaf.to = NodeId('L', k);
      leaf.T_from_to = Eigen::Isometry3d::Identity();
      leaf.T_from_to.translation() = Eigen::Vector3d(0.0, 0.0, 1.0);
      with.edges.push_back(leaf);
      shifted.held_out.push_back(false);
      shifted.known_inlier.push_back(false);
      initial[leaf.to] = Eigen::Isometry3d::Identity();
    }
    at.push_back(with.edges.size());
    with.edges.push_back(e);
    shifted.held_out.push_back(decided.held_out[k]);
    shifted.known_inlier.push_back(decided.known_inlier[k]);
  }
  ASSERT_GT(with.edges.size(), g.graph.edges.size() + 100);
  const RobustPgoResult result = optimizePoseGraph(with, initial, anchor, shifted);
  ASSERT_EQ(result.edge_inlier.size(), with.edges.size());
  for (size_t k = 0; k < g.graph.edges.size(); ++k)
    EXPECT_EQ(result.edge_inlier[at[k]], plain.edge_inlier[k]) << "edge " << k;
  EXPECT_EQ(result.known_contradicted, plain.known_contradicted);
  EXPECT_FALSE(result.held_out_poses.empty());
  for (const auto& [id, pose] : plain.poses)
    EXPECT_LT((result.poses.at(id).translation() - pose.translation()).norm(), 1e-6) << id.str();
}

// In a solve that is not robust, held-out factors are no part of it: grid1000 with every fifth
// loop closure held out, and a pose tied by odometry and by a held-out loop closure (a leaf
// without it), solves as the graph without those edges does, the held-out ones rejected.
TEST(RobustPoseGraph, HeldOutFactorsAreNoPartOfASolveThatIsNotRobust) {
  const LabelledGraph g = readLabelledGrid("grid1000_10p_outliers");
  const NodeId anchor(0, 0);
  PoseGraph with = g.graph;
  auto initial = odometryInitialization(g.graph, anchor);
  PoseGraphEdge tie;
  tie.from = NodeId(0, 10);
  tie.to = NodeId('L', 0);
  tie.T_from_to.translation() = Eigen::Vector3d(0.0, 0.0, 1.0);
  PoseGraphEdge closure = tie;
  closure.from = NodeId(0, 500);
  closure.kind = PoseGraphEdge::Kind::kLoopClosure;
  with.edges.push_back(tie);
  with.edges.push_back(closure);
  initial[tie.to] = Eigen::Isometry3d::Identity();
  RobustPgoOptions options;
  options.robust = false;
  options.held_out.assign(with.edges.size(), false);
  PoseGraph without;
  size_t closures = 0;
  for (size_t k = 0; k < with.edges.size(); ++k) {
    const bool closes = with.edges[k].kind == PoseGraphEdge::Kind::kLoopClosure;
    options.held_out[k] = closes && (closures++ % 5 == 0 || k + 1 == with.edges.size());
    if (!options.held_out[k]) without.edges.push_back(with.edges[k]);
  }
  ASSERT_GT(with.edges.size(), without.edges.size() + 50);
  RobustPgoOptions plain;
  plain.robust = false;
  const RobustPgoResult expected = optimizePoseGraph(without, initial, anchor, plain);
  const RobustPgoResult result = optimizePoseGraph(with, initial, anchor, options);
  for (size_t k = 0; k < with.edges.size(); ++k)
    EXPECT_EQ(result.edge_inlier[k], !options.held_out[k]) << "edge " << k;
  for (const auto& [id, pose] : expected.poses)
    EXPECT_LT((result.poses.at(id).matrix() - pose.matrix()).norm(), 1e-9) << id.str();
  const Eigen::Isometry3d placed = result.poses.at(tie.from) * tie.T_from_to;
  EXPECT_LT((result.poses.at(tie.to).matrix() - placed.matrix()).norm(), 1e-9);
}

// The bar on real labelled data: precision >= 0.99 and recall >= 0.98.
TEST(RobustPoseGraph, Grid1000With10PercentOutliers) {
  const Classification c = classifyGrid("grid1000_10p_outliers");
  EXPECT_GE(c.precision, 0.99);
  EXPECT_GE(c.recall, 0.98);
}

TEST(RobustPoseGraph, Grid1000With30PercentOutliers) {
  const Classification c = classifyGrid("grid1000_30p_outliers");
  EXPECT_GE(c.precision, 0.99);
  EXPECT_GE(c.recall, 0.98);
}

}  // namespace
}  // namespace hydra_multi
