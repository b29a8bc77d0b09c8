#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <set>
#include <thread>

#include "hydra_multi/optim/chordal_initialization.h"
#include "hydra_multi/optim/io/g2o_format.h"
#include "hydra_multi/optim/outlier_injection.h"
#include "hydra_multi/optim/pose_graph_optimizer.h"
#include "hydra_multi/optim/sparse_levenberg_marquardt.h"
#include "support/random_graphs.h"

namespace hydra_multi {
namespace {

// A random trajectory with odometry and loop closures, exact or with noise.
PoseGraph syntheticGraph(std::mt19937& rng, int n, double noise,
                         std::map<NodeId, Eigen::Isometry3d>& truth) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  truth = testing::randomTrajectory(rng, n);
  PoseGraph g;
  auto addEdge = [&](int a, int b) {
    PoseGraphEdge e;
    e.from = NodeId('x', static_cast<uint64_t>(a));
    e.to = NodeId('x', static_cast<uint64_t>(b));
    Vector6d xi;
    for (int k = 0; k < 6; ++k) xi[k] = noise * gauss(rng);
    e.T_from_to = truth[e.from].inverse() * truth[e.to] * expSE3(xi);
    e.information = Matrix6d::Identity() * (noise > 0 ? 1.0 / (noise * noise) : 1.0);
    g.edges.push_back(e);
  };
  for (int i = 0; i + 1 < n; ++i) addEdge(i, i + 1);
  for (int i = 0; i + 7 < n; i += 3) addEdge(i, i + 7);
  classifyEdges(g);
  return g;
}

// Noise-free data: chordal initialization is exact, and both residuals recover the truth from a
// perturbed start.
TEST(PoseGraphOptimizer, RecoversTruthFromExactData) {
  std::mt19937 rng(81);
  std::map<NodeId, Eigen::Isometry3d> truth;
  const PoseGraph g = syntheticGraph(rng, 40, 0.0, truth);
  const NodeId anchor('x', 0);
  auto init = chordalInitialization(g, anchor);
  ASSERT_TRUE(init.ok()) << init.error();
  for (const auto& [id, T] : truth)
    EXPECT_LT((init.value().at(id).matrix() - T.matrix()).norm(), 1e-9);

  const std::map<NodeId, Eigen::Isometry3d> perturbed =
      testing::perturbPoses(truth, anchor, 0.05, rng);
  for (const ResidualType type : {ResidualType::kGeodesic, ResidualType::kChordal}) {
    PoseGraphOptimizerOptions options;
    options.residual = type;
    options.function_tolerance = 1e-12;
    PoseGraphProblem problem(g, perturbed, anchor, options);
    const SolveSummary summary = problem.solve();
    ASSERT_TRUE(summary.usable) << summary.message;
    for (const auto& [id, T] : problem.poses()) {
      EXPECT_LT((T.matrix() - truth.at(id).matrix()).norm(), 1e-5) << residualTypeName(type);
    }
    // The anchor is the gauge: it never moves.
    EXPECT_EQ(problem.poses().at(anchor).matrix(), perturbed.at(anchor).matrix());
  }
}

// posesInto writes the solution in place into a map of the problem's nodes (the same entries,
// the values poses() gives), and makes a map of other nodes anew.
TEST(PoseGraphOptimizer, PosesWrittenInPlaceWhereTheMapHoldsTheProblemsNodes) {
  std::mt19937 rng(83);
  std::map<NodeId, Eigen::Isometry3d> truth;
  const PoseGraph g = syntheticGraph(rng, 30, 0.01, truth);
  const NodeId anchor('x', 0);
  PoseGraphProblem problem(g, testing::perturbPoses(truth, anchor, 0.05, rng), anchor);
  ASSERT_TRUE(problem.solve().usable);
  const std::map<NodeId, Eigen::Isometry3d> solved = problem.poses();

  std::map<NodeId, Eigen::Isometry3d> into = truth;
  const Eigen::Isometry3d* entry = &into.at(NodeId('x', 5));
  problem.posesInto(into);
  EXPECT_EQ(&into.at(NodeId('x', 5)), entry);  // in place
  ASSERT_EQ(into.size(), solved.size());
  for (const auto& [id, T] : solved) EXPECT_EQ(into.at(id).matrix(), T.matrix());

  for (auto other :
       {std::map<NodeId, Eigen::Isometry3d>{},
        std::map<NodeId, Eigen::Isometry3d>{{NodeId('y', 1), truth.begin()->second}}, truth}) {
    if (other.size() == truth.size()) {  // as many nodes, one of them another
      other.erase(std::prev(other.end()));
      other.emplace(NodeId('y', 2), Eigen::Isometry3d::Identity());
    }
    problem.posesInto(other);
    ASSERT_EQ(other.size(), solved.size());
    for (const auto& [id, T] : solved) EXPECT_EQ(other.at(id).matrix(), T.matrix());
  }
}

// Weights scale edges: a zero-weight wrong edge has no effect on the solution.
TEST(PoseGraphOptimizer, ZeroWeightRemovesAnEdge) {
  std::mt19937 rng(82);
  std::map<NodeId, Eigen::Isometry3d> truth;
  PoseGraph g = syntheticGraph(rng, 20, 0.0, truth);
  PoseGraphEdge wrong = g.edges.back();
  wrong.T_from_to = wrong.T_from_to * expSE3((Vector6d() << 5, 0, 0, 0, 0, 1).finished());
  g.edges.push_back(wrong);
  PoseGraphOptimizerOptions options;
  options.function_tolerance = 1e-12;
  PoseGraphProblem problem(g, truth, NodeId('x', 0), options);
  std::vector<double> weights(g.edges.size(), 1.0);
  weights.back() = 0.0;
  problem.setWeights(weights);
  problem.solve();
  for (const auto& [id, T] : problem.poses())
    EXPECT_LT((T.matrix() - truth.at(id).matrix()).norm(), 1e-6);
  EXPECT_GT(problem.squaredResiduals().back(), 1.0);
  EXPECT_LT(problem.squaredResiduals().front(), 1e-12);
}

// From `start`, `held` poses constant, the sparse Levenberg-Marquardt (CHOLMOD) and Ceres'
// conjugate gradients, two independent solvers, reach the same optimum, for both residuals.
void expectSparseCholeskyReachesCeres(const PoseGraph& g,
                                      const std::map<NodeId, Eigen::Isometry3d>& start,
                                      NodeId anchor, const std::set<NodeId>& held = {}) {
  for (const ResidualType type : {ResidualType::kGeodesic, ResidualType::kChordal}) {
    PoseGraphOptimizerOptions options;
    options.residual = type;
    options.function_tolerance = 1e-14;
    options.max_iterations = 200;
    PoseGraphProblem sparse(g, start, anchor, options);
    options.linear_solver = PoseGraphOptimizerOptions::LinearSolver::kConjugateGradients;
    options.max_linear_iterations = 1000;
    PoseGraphProblem ceres(g, start, anchor, options);
    if (!held.empty()) {
      sparse.holdConstant(held);
      ceres.holdConstant(held);
    }
    const SolveSummary by_cholmod = sparse.solve();
    const SolveSummary by_ceres = ceres.solve();
    ASSERT_TRUE(by_cholmod.usable) << by_cholmod.message;
    ASSERT_TRUE(by_ceres.usable) << by_ceres.message;
    EXPECT_LT(by_cholmod.final_cost, by_cholmod.initial_cost);
    EXPECT_NEAR(by_cholmod.final_cost, by_ceres.final_cost, 1e-6 * by_ceres.final_cost)
        << residualTypeName(type) << ", " << held.size() << " held";
    for (const auto& [id, T] : sparse.poses())
      EXPECT_LT((T.matrix() - ceres.poses().at(id).matrix()).norm(), 1e-5) << id.str();
  }
}

// ... of a noisy graph.
TEST(PoseGraphOptimizer, SparseCholeskyAndCeresReachTheSameOptimum) {
  std::mt19937 rng(83);
  std::map<NodeId, Eigen::Isometry3d> truth;
  const PoseGraph g = syntheticGraph(rng, 60, 0.02, truth);
  const NodeId anchor('x', 0);
  expectSparseCholeskyReachesCeres(g, testing::perturbPoses(truth, anchor, 0.05, rng), anchor);
}

// Poses joined to at most two others (chains, leaves, a chain cut by a held pose) are eliminated
// before CHOLMOD factorizes the rest, and their steps substituted back: the optimum is Ceres'.
TEST(PoseGraphOptimizer, ChainsAndLeavesEliminatedFirstReachTheSameOptimum) {
  std::mt19937 rng(86);
  std::normal_distribution<double> gauss(0.0, 1.0);
  const std::map<NodeId, Eigen::Isometry3d> truth = testing::randomTrajectory(rng, 96);
  const auto x = [](int k) { return NodeId('x', static_cast<uint64_t>(k)); };
  PoseGraph g;
  const auto addEdge = [&](int a, int b) {
    PoseGraphEdge e;
    e.from = x(a);
    e.to = x(b);
    Vector6d xi;
    for (int k = 0; k < 6; ++k) xi[k] = 0.02 * gauss(rng);
    e.T_from_to = truth.at(e.from).inverse() * truth.at(e.to) * expSE3(xi);
    e.information = Matrix6d::Identity() * 2500.0;
    g.edges.push_back(e);
  };
  for (int i = 0; i + 1 < 80; ++i) addEdge(i, i + 1);  // one chain
  for (const auto& [a, b] : {std::pair{0, 30}, {10, 50}, {30, 79}, {20, 60}}) addEdge(a, b);
  for (int leaf = 80; leaf < 96; ++leaf) addEdge((leaf * 7) % 80, leaf);  // leaves
  addEdge(90, 91);  // two leaves made a chain between two poses
  classifyEdges(g);
  const NodeId anchor = x(0);
  const auto start = testing::perturbPoses(truth, anchor, 0.05, rng);
  expectSparseCholeskyReachesCeres(g, start, anchor);
  expectSparseCholeskyReachesCeres(g, start, anchor, {x(40), x(85)});  // in the chain, a leaf
}

// The sparse solver analyzes the graph once and keeps it: after solves with other weights (zero
// among them), a solve gives what a new problem gives from the same poses.
TEST(PoseGraphOptimizer, ASolveAfterOthersWithOtherWeightsIsAsAFirstSolve) {
  std::mt19937 rng(84);
  std::map<NodeId, Eigen::Isometry3d> truth;
  const PoseGraph g = syntheticGraph(rng, 50, 0.02, truth);
  const NodeId anchor('x', 3);
  const auto start = testing::perturbPoses(truth, anchor, 0.05, rng);
  PoseGraphOptimizerOptions options;
  options.max_iterations = 5;
  PoseGraphProblem reused(g, start, anchor, options);
  std::vector<double> weights(g.edges.size(), 1.0);
  for (size_t k = 0; k < weights.size(); k += 4) weights[k] = 0.0;
  reused.setWeights(weights);
  const SolveSummary analyzed = reused.solve();
  std::vector<double> halves(g.edges.size(), 0.5);
  reused.setWeights(halves);
  reused.solve();
  const auto poses = reused.poses();

  PoseGraphProblem fresh(g, poses, anchor, options);
  fresh.setWeights(halves);
  const SolveSummary first = fresh.solve();
  const SolveSummary again = reused.solve();
  EXPECT_EQ(first.iterations, again.iterations);
  EXPECT_NEAR(first.final_cost, again.final_cost, 1e-12 * first.final_cost);
  for (const auto& [id, T] : fresh.poses())
    EXPECT_LT((T.matrix() - reused.poses().at(id).matrix()).norm(), 1e-12);
  EXPECT_LT((reused.poses().at(anchor).matrix() - start.at(anchor).matrix()).norm(), 1e-12);
  // The first solve of each problem reports its analysis; the solves after it reuse it.
  EXPECT_GT(analyzed.analysis_s, 0.0);
  EXPECT_GT(first.analysis_s, 0.0);
  EXPECT_EQ(again.analysis_s, 0.0);
  for (const SolveSummary* s : {&analyzed, &first, &again}) {
    EXPECT_GT(s->factorization_s, 0.0);
    EXPECT_LE(s->factorization_s, s->time_s);
  }
}

// A local solve: with poses held constant at the optimum, the others, moved off it, come back to
// it, and the held ones do not move, for both linear solvers.
TEST(PoseGraphOptimizer, PosesHeldConstantStayAndTheOthersReachTheOptimum) {
  std::mt19937 rng(85);
  std::map<NodeId, Eigen::Isometry3d> truth;
  const PoseGraph g = syntheticGraph(rng, 60, 0.02, truth);
  const NodeId anchor('x', 0);
  PoseGraphOptimizerOptions options;
  options.function_tolerance = 1e-14;
  options.max_iterations = 200;
  PoseGraphProblem full(g, truth, anchor, options);
  ASSERT_TRUE(full.solve().usable);
  const std::map<NodeId, Eigen::Isometry3d> optimum = full.poses();

  std::set<NodeId> held;
  std::map<NodeId, Eigen::Isometry3d> start = optimum;
  for (const auto& [id, T] : optimum) {
    if (id.index() >= 20 && id.index() < 35) {
      start[id] = T * expSE3((Vector6d() << 0.05, -0.03, 0.02, 0.2, 0.1, -0.1).finished());
    } else {
      held.insert(id);
    }
  }
  for (const auto solver : {PoseGraphOptimizerOptions::LinearSolver::kSparseCholesky,
                            PoseGraphOptimizerOptions::LinearSolver::kConjugateGradients}) {
    options.linear_solver = solver;
    options.max_linear_iterations = 1000;
    PoseGraphProblem local(g, start, NodeId('x', 999), options);  // no anchor: the held are
    local.holdConstant(held);
    const SolveSummary summary = local.solve();
    ASSERT_TRUE(summary.usable) << summary.message;
    for (const auto& [id, T] : local.poses()) {
      if (held.count(id)) {
        EXPECT_LT((T.matrix() - start.at(id).matrix()).norm(), 1e-12) << id.str();
      } else {
        EXPECT_LT((T.matrix() - optimum.at(id).matrix()).norm(), 1e-5) << id.str();
      }
    }
  }
}

double optimizedSesyncCost(const std::string& file) {
  auto g2o = io::readG2o(testing::dataDir() + "/pgo/" + file);
  EXPECT_TRUE(g2o.ok()) << g2o.error();
  const PoseGraph& g = g2o.value().graph;
  const NodeId anchor = g.poses.begin()->first;
  auto init = chordalInitialization(g, anchor);
  EXPECT_TRUE(init.ok()) << init.error();
  PoseGraphOptimizerOptions options;
  options.residual = ResidualType::kChordal;
  PoseGraphProblem problem(g, init.value(), anchor, options);
  EXPECT_TRUE(problem.solve().usable);
  return sesyncCost(g.edges, problem.poses()).value();
}

// The real benchmarks: chordal residual from chordal initialization reaches the certified global
// optimum f* of SE-Sync within 0.1 % (data/README.md).
TEST(PoseGraphOptimizer, ReachesCertifiedOptimumOnSphere2500) {
  const double f_star = 1687.01;
  const double f = optimizedSesyncCost("sphere2500.g2o");
  EXPECT_GE(f, f_star * (1 - 1e-5));
  EXPECT_LE(f, f_star * 1.001);
}

TEST(PoseGraphOptimizer, ReachesCertifiedOptimumOnParkingGarage) {
  const double f_star = 1.2626;
  const double f = optimizedSesyncCost("parking-garage.g2o");
  EXPECT_GE(f, f_star * (1 - 1e-4));
  EXPECT_LE(f, f_star * 1.001);
}

// A benchmark of ../shared/data/pgo with its edges classified; empty if it cannot be read.
PoseGraph classifiedBenchmark(const std::string& file) {
  auto g2o = io::readG2o(testing::dataDir() + "/pgo/" + file);
  EXPECT_TRUE(g2o.ok()) << g2o.error();
  if (!g2o.ok()) return {};
  PoseGraph g = g2o.value().graph;
  classifyEdges(g);
  return g;
}

PoseGraph sphere2500() { return classifiedBenchmark("sphere2500.g2o"); }

// The fill GNC's choice of linear solver reads (RobustPgoOptions::cholesky_mflops_per_pose_limit,
// 2): sphere2500 as it is stays sparse, with half of its loop closures random outliers it fills in.
TEST(PoseGraphOptimizer, OutliersThatJoinRandomPosesFillTheFactorIn) {
  PoseGraph g = sphere2500();
  ASSERT_FALSE(g.poses.empty());
  const NodeId anchor = g.poses.begin()->first;
  const double clean = PoseGraphProblem(g, g.poses, anchor).choleskyFlopsPerPose() / 1e6;
  EXPECT_GT(injectOutliers(g, g.poses, 0.5, 1), 2000u);
  const double outliers = PoseGraphProblem(g, g.poses, anchor).choleskyFlopsPerPose() / 1e6;
  EXPECT_GT(clean, 0.01);
  EXPECT_LT(clean, 0.5);
  EXPECT_GT(outliers, 10.0);
}

// Edges left out of a problem are no factors and no part of its sparse factor: sphere2500 with
// random outliers at weight 0 takes the same steps with them in the pattern and left out of it,
// left out with the clean graph's factor; an outlier given a weight again is back in.
TEST(PoseGraphOptimizer, LeftOutEdgesAreNoFactorsAndAddNoFillIn) {
  PoseGraph g = sphere2500();
  ASSERT_FALSE(g.poses.empty());
  const NodeId anchor = g.poses.begin()->first;
  const double clean = PoseGraphProblem(g, g.poses, anchor).choleskyFlopsPerPose();
  const auto start = chordalInitialization(g, anchor);
  ASSERT_TRUE(start.ok()) << start.error();
  const size_t first_outlier = g.edges.size();
  // A few: SuiteSparseBlocks' tests expect no kept block of 64 MB from the tests before them.
  ASSERT_EQ(injectOutliers(g, g.poses, 0.02, 2), 50u);
  std::vector<double> weights(g.edges.size(), 1.0);
  std::vector<bool> out(g.edges.size(), false);
  for (size_t k = first_outlier; k < g.edges.size(); ++k) {
    weights[k] = 0.0;
    out[k] = true;
  }
  PoseGraphOptimizerOptions options;
  options.max_iterations = 3;  // the same steps either way, to rounding
  PoseGraphProblem zero(g, start.value(), anchor, options), left(g, start.value(), anchor, options);
  zero.setWeights(weights);
  left.setWeights(weights);
  left.leaveOut(out);
  EXPECT_GT(zero.choleskyFlopsPerPose(), 1.3 * left.choleskyFlopsPerPose());
  EXPECT_NEAR(left.choleskyFlopsPerPose(), clean, 1e-9 * clean);
  EXPECT_FALSE(left.edgeIncluded(first_outlier));
  EXPECT_TRUE(zero.edgeIncluded(first_outlier));

  const auto sameSteps = [&](PoseGraphProblem& a, PoseGraphProblem& b) {
    const SolveSummary by_a = a.solve(), by_b = b.solve();
    ASSERT_TRUE(by_a.usable && by_b.usable) << by_a.message << " / " << by_b.message;
    EXPECT_NEAR(by_a.final_cost, by_b.final_cost, 1e-8 * by_b.final_cost);
    double apart = 0.0;
    const auto b_poses = b.poses();
    for (const auto& [id, T] : a.poses())
      apart = std::max(apart, (T.translation() - b_poses.at(id).translation()).norm());
    EXPECT_LT(apart, 1e-6);
  };
  sameSteps(left, zero);
  EXPECT_EQ(left.squaredResiduals()[first_outlier], 0.0);
  EXPECT_GT(zero.squaredResiduals()[first_outlier], 0.0);

  weights[first_outlier] = 1.0;  // an outlier back, by its weight alone
  left.setWeights(weights);
  zero.setWeights(weights);
  sameSteps(left, zero);
  EXPECT_TRUE(left.edgeIncluded(first_outlier));
  EXPECT_GT(left.squaredResiduals()[first_outlier], 0.0);
}

// Solves of `g` on 1, 2 and 3 threads end at the same poses, to the bit; its first `held` poses
// held constant.
void threadsTakeTheStepsOfOne(const PoseGraph& g, size_t held = 40) {
  ASSERT_GE(g.edges.size(), 4096u);  // below, the solver linearizes on one thread anyway
  const NodeId anchor = g.poses.begin()->first;
  const auto start = chordalInitialization(g, anchor);
  ASSERT_TRUE(start.ok()) << start.error();
  std::vector<double> weights(g.edges.size(), 1.0);
  weights[7] = 0.0;
  weights[100] = 0.25;
  std::set<NodeId> constant;  // poses held: terms between two of them add a cost and no block
  for (const auto& [id, T] : g.poses) {
    if (constant.size() < held) constant.insert(id);
  }
  const auto solved = [&](int threads) {
    PoseGraphOptimizerOptions options;
    options.max_iterations = 4;
    options.linearization_threads = threads;
    PoseGraphProblem problem(g, start.value(), anchor, options);
    problem.holdConstant(constant);
    problem.setWeights(weights);
    const SolveSummary summary = problem.solve();
    EXPECT_TRUE(summary.usable) << summary.message;
    EXPECT_EQ(summary.iterations, 4);
    return std::make_pair(summary, problem.poses());
  };
  const auto [one, one_poses] = solved(1);
  for (const int threads : {2, 3}) {
    const auto [many, many_poses] = solved(threads);
    EXPECT_EQ(many.initial_cost, one.initial_cost) << threads;
    EXPECT_EQ(many.final_cost, one.final_cost) << threads;
    for (const auto& [id, T] : one_poses) {
      ASSERT_TRUE(T.matrix() == many_poses.at(id).matrix()) << id.str() << ", " << threads;
    }
  }
}

// Hubs on a grid, 10 m apart, each joined to its neighbours by `chains` chains of `length`
// poses (odometry-like edges along them, with noise): the poses a solver eliminates before
// CHOLMOD, in many parts that meet at the hubs.
PoseGraph chainedGrid(std::mt19937& rng, int side, int chains, int length, double noise) {
  std::normal_distribution<double> gauss(0.0, 1.0);
  std::map<NodeId, Eigen::Isometry3d> truth;
  uint64_t next = 0;
  const auto pose = [&](const Eigen::Vector3d& at) {
    Vector6d xi;
    for (int k = 0; k < 6; ++k) xi[k] = 0.05 * gauss(rng);
    Eigen::Isometry3d T = expSE3(xi);
    T.translation() += at;
    const NodeId id('x', next++);
    truth[id] = T;
    return id;
  };
  std::vector<NodeId> hubs;
  for (int i = 0; i < side * side; ++i)
    hubs.push_back(pose(Eigen::Vector3d(10.0 * (i % side), 10.0 * (i / side), 0.0)));
  PoseGraph g;
  const auto edge = [&](NodeId a, NodeId b) {
    PoseGraphEdge e;
    e.from = a;
    e.to = b;
    Vector6d xi;
    for (int k = 0; k < 6; ++k) xi[k] = noise * gauss(rng);
    e.T_from_to = truth[a].inverse() * truth[b] * expSE3(xi);
    e.information = Matrix6d::Identity() / (noise * noise);
    g.edges.push_back(e);
  };
  for (int i = 0; i < side * side; ++i) {
    for (const int j : {i + 1, i + side}) {
      if (j >= side * side || (j == i + 1 && j % side == 0)) continue;
      for (int c = 0; c < chains; ++c) {
        NodeId last = hubs[i];
        for (int s = 1; s <= length; ++s) {
          const double f = double(s) / (length + 1);
          const Eigen::Vector3d at = (1.0 - f) * truth[hubs[i]].translation() +
                                     f * truth[hubs[j]].translation() +
                                     Eigen::Vector3d(0.0, 0.0, 0.5 * c);
          const NodeId id = pose(at);
          edge(last, id);
          last = id;
        }
        edge(last, hubs[j]);
      }
    }
  }
  g.poses = truth;
  classifyEdges(g);
  return g;
}

// The solver's threads (linearization, cost, the eliminations and the substitution back) take
// the steps of one thread, to the bit: on sphere2500, and on the parking garage and a grid of hubs
// joined by chains, whose chains the solver eliminates before CHOLMOD.
TEST(PoseGraphOptimizer, SolverThreadsTakeTheStepsOfOneThreadToTheBit) {
  for (const std::string file : {"sphere2500.g2o", "parking-garage.g2o"}) {
    SCOPED_TRACE(file);
    const PoseGraph g = classifiedBenchmark(file);
    ASSERT_FALSE(g.edges.empty());
    threadsTakeTheStepsOfOne(g);
  }
  SCOPED_TRACE("chained grid");
  std::mt19937 rng(83);
  const PoseGraph grid = chainedGrid(rng, 8, 2, 20, 0.01);
  threadsTakeTheStepsOfOne(grid);
  // No pose held but the anchor: the hubs stay in A, and chains on either side of where the
  // eliminations split for two threads end at the same hubs.
  threadsTakeTheStepsOfOne(grid, 0);
}

// `g` solved from `start` on two threads, the factorizations of at least `single_from_flops` flops
// in single precision (negative: none); its summary and poses.
std::pair<SolveSummary, std::map<NodeId, Eigen::Isometry3d>> solvedInPrecision(
    const PoseGraph& g, const std::map<NodeId, Eigen::Isometry3d>& start, NodeId anchor,
    double single_from_flops, int max_iterations = PoseGraphOptimizerOptions{}.max_iterations) {
  PoseGraphOptimizerOptions options;
  options.linearization_threads = 2;
  options.max_iterations = max_iterations;
  options.single_precision_from_flops = single_from_flops;
  PoseGraphProblem problem(g, start, anchor, options);
  const SolveSummary summary = problem.solve();
  EXPECT_TRUE(summary.usable) << summary.message;
  return {summary, problem.poses()};
}

// The factorizations in single precision, each solve refined once in double
// (single_precision_from_flops 0: all of them), on the real benchmarks from chordal
// initialization: the steps of double precision within rounding, so the same iterations, the
// final cost within 1e-9 of it and every pose within 1e-5; not the same to the bit (floats).
TEST(PoseGraphOptimizer, FactorsInSinglePrecisionRefinedTakeTheStepsOfDoublePrecision) {
  for (const std::string file : {"sphere2500.g2o", "parking-garage.g2o"}) {
    SCOPED_TRACE(file);
    const PoseGraph g = classifiedBenchmark(file);
    ASSERT_FALSE(g.edges.empty());
    const NodeId anchor = g.poses.begin()->first;
    const auto start = chordalInitialization(g, anchor);
    ASSERT_TRUE(start.ok()) << start.error();
    const auto [exact, exact_poses] = solvedInPrecision(g, start.value(), anchor, -1.0);
    const auto [single, single_poses] = solvedInPrecision(g, start.value(), anchor, 0.0);
    EXPECT_EQ(exact.single_precision_factorizations, 0);
    EXPECT_GT(single.single_precision_factorizations, 0);
    EXPECT_EQ(single.single_precision_fallbacks, 0);
    EXPECT_EQ(single.iterations, exact.iterations);
    EXPECT_NEAR(single.final_cost, exact.final_cost, 1e-9 * exact.final_cost);
    double largest = 0.0;
    for (const auto& [id, T] : exact_poses)
      largest = std::max(largest, (T.matrix() - single_poses.at(id).matrix()).norm());
    EXPECT_LT(largest, 1e-5);
    EXPECT_GT(largest, 0.0) << "factorized in floats";
  }
}

// Every edge's information times 2^126 (the same minimum; exact in double): H's entries are then
// beyond floats' range, so each factorization asked for in single precision fails in it and is
// made in double instead, and the solve takes the steps of double precision to the bit.
TEST(PoseGraphOptimizer, AFactorizationBeyondFloatsRangeIsMadeInDouble) {
  PoseGraph g = sphere2500();
  ASSERT_FALSE(g.edges.empty());
  for (PoseGraphEdge& edge : g.edges) edge.information *= std::ldexp(1.0, 126);
  const NodeId anchor = g.poses.begin()->first;
  const auto [exact, exact_poses] = solvedInPrecision(g, g.poses, anchor, -1.0, 4);
  const auto [fallen_back, fallen_back_poses] = solvedInPrecision(g, g.poses, anchor, 0.0, 4);
  EXPECT_EQ(fallen_back.single_precision_factorizations, 0);
  EXPECT_EQ(fallen_back.single_precision_fallbacks, fallen_back.iterations);
  EXPECT_NE(fallen_back.message.find("made in double where single precision failed"),
            std::string::npos)
      << fallen_back.message;
  EXPECT_GT(fallen_back.iterations, 0);
  EXPECT_LT(exact.final_cost, exact.initial_cost);
  EXPECT_EQ(fallen_back.iterations, exact.iterations);
  EXPECT_EQ(fallen_back.final_cost, exact.final_cost);
  for (const auto& [id, T] : exact_poses)
    EXPECT_EQ(T.matrix(), fallen_back_poses.at(id).matrix()) << id.value();
}

// An analysis made ahead on another thread (PoseGraphOptimizerOptions::analyses, keep_analysis),
// its supernodal factor's values allocated there, is taken by a later problem of its pattern
// alone, which then takes the steps of a problem that analyzes its own, to the bit; problems with
// another term or other fixed poses leave it, its factor's values freed. Dropped, it frees what it
// holds, and an analysis made for it after is neither made nor kept.
TEST(PoseGraphOptimizer, AnAnalysisMadeAheadIsTakenByItsPatternAloneUntilDropped) {
  const PoseGraph g = sphere2500();
  ASSERT_FALSE(g.poses.empty());
  const NodeId anchor = g.poses.begin()->first;
  PoseGraphOptimizerOptions own;
  own.max_iterations = 3;
  const auto analyses = std::make_shared<SparseAnalyses>();
  PoseGraphOptimizerOptions prepare = own;
  prepare.max_iterations = 0;
  prepare.analyses = analyses;
  prepare.keep_analysis = true;
  std::thread([&] { PoseGraphProblem(g, g.poses, anchor, prepare).solve(); }).join();
  ASSERT_TRUE(analyses->holds());
  EXPECT_GT(analyses->heldFactorValues(), 0u);
  PoseGraphOptimizerOptions take = own;
  take.analyses = analyses;

  PoseGraph moved = g;  // as many terms, one of them between other poses
  moved.edges.back().to = std::next(g.poses.begin(), 3)->first;
  PoseGraphProblem(moved, moved.poses, anchor, take).solve();
  EXPECT_TRUE(analyses->holds());
  EXPECT_EQ(analyses->heldFactorValues(), 0u);
  PoseGraphProblem held(g, g.poses, anchor, take);
  held.holdConstant({std::next(g.poses.begin(), 5)->first});
  held.solve();
  EXPECT_TRUE(analyses->holds());

  PoseGraphProblem taking(g, g.poses, anchor, take);
  const SolveSummary taken = taking.solve();
  EXPECT_FALSE(analyses->holds());
  PoseGraphProblem analyzing(g, g.poses, anchor, own);
  const SolveSummary analyzed = analyzing.solve();
  EXPECT_TRUE(taken.usable) << taken.message;
  EXPECT_EQ(taken.iterations, 3);
  EXPECT_EQ(taken.final_cost, analyzed.final_cost);
  const auto taken_poses = taking.poses(), analyzed_poses = analyzing.poses();
  for (const auto& [id, T] : analyzed_poses)
    ASSERT_TRUE(T.matrix() == taken_poses.at(id).matrix()) << id.str();

  PoseGraphProblem(g, g.poses, anchor, prepare).solve();
  ASSERT_TRUE(analyses->holds());
  EXPECT_FALSE(analyses->dropped());
  analyses->drop();
  EXPECT_TRUE(analyses->dropped());
  EXPECT_FALSE(analyses->holds());
  EXPECT_FALSE(PoseGraphProblem(g, g.poses, anchor, prepare).solve().usable);  // no analysis
  EXPECT_FALSE(analyses->holds());
  EXPECT_EQ(PoseGraphProblem(g, g.poses, anchor, take).solve().final_cost, analyzed.final_cost);
}

}  // namespace
}  // namespace hydra_multi
