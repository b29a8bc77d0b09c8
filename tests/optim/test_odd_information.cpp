// Edges whose information matrix is not positive definite (real benchmarks have them): read and
// named by file and line, weighed as SE-Sync weighs them (tau and kappa from the translation and
// rotation blocks) in the chordal solve and by the nearest positive-definite matrix in the
// geodesic one; both reach the known optimum. Edges whose blocks are not positive definite are
// refused.

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <sstream>

#include "hydra_multi/optim/io/g2o_format.h"
#include "hydra_multi/optim/pose_graph_optimizer.h"
#include "hydra_multi/optim/residuals.h"
#include "support/random_graphs.h"

namespace hydra_multi {
namespace {

// Translation block a I, rotation block b I, coupling c I: indefinite when c^2 > a b.
Matrix6d coupled(double a, double b, double c) {
  Matrix6d info = Matrix6d::Zero();
  info.topLeftCorner<3, 3>() = a * Eigen::Matrix3d::Identity();
  info.bottomRightCorner<3, 3>() = b * Eigen::Matrix3d::Identity();
  info.topRightCorner<3, 3>() = c * Eigen::Matrix3d::Identity();
  info.bottomLeftCorner<3, 3>() = c * Eigen::Matrix3d::Identity();
  return info;
}

std::string upperTriangle(const Matrix6d& info) {
  std::ostringstream s;
  for (int i = 0; i < 6; ++i) {
    for (int j = i; j < 6; ++j) s << " " << info(i, j);
  }
  return s.str();
}

TEST(OddInformation, AnIndefiniteMatrixWithDefiniteBlocksIsReadAndNamedByLine) {
  const std::string text =
      "VERTEX_SE3:QUAT 0 0 0 0 0 0 0 1\n"
      "VERTEX_SE3:QUAT 1 1 0 0 0 0 0 1\n"
      "EDGE_SE3:QUAT 0 1 1 0 0 0 0 0 1" +
      upperTriangle(Matrix6d::Identity()) +
      "\n"
      "EDGE_SE3:QUAT 0 1 1 0 0 0 0 0 1" +
      upperTriangle(coupled(100, 100, 200)) +
      "\n"
      "EDGE_SE2 0 1 1 0 0 1 0 3 1 0 1\n";
  auto read = io::parseG2o(text, "o.g2o");
  ASSERT_TRUE(read.ok()) << read.error();
  EXPECT_EQ(read.value().graph.edges.size(), 3u);
  ASSERT_EQ(read.value().notes.size(), 2u);
  EXPECT_EQ(read.value().notes[0],
            "o.g2o:4: the information matrix is not positive definite (smallest eigenvalue -100); "
            "weighed by its translation and rotation blocks (SE-Sync's tau and kappa) in the "
            "chordal solve, by its nearest positive-definite matrix in the geodesic one");
  EXPECT_EQ(read.value().notes[1].rfind("o.g2o:5: the information matrix is not positive definite "
                                        "(smallest eigenvalue -2); weighed by",
                                        0),
            0u)
      << read.value().notes[1];
  EXPECT_TRUE(read.value().warnings.empty());
  // The matrix is kept as written (a graph written back says what it read).
  EXPECT_EQ(read.value().graph.edges[1].information, coupled(100, 100, 200));

  // A block that is not positive definite gives no weight at all: refused, named.
  auto refused = io::parseG2o(
      "EDGE_SE3:QUAT 0 1 1 0 0 0 0 0 1" + upperTriangle(coupled(100, -1, 0)) + "\n", "r.g2o");
  ASSERT_FALSE(refused.ok());
  EXPECT_EQ(refused.error(),
            "r.g2o:1: the information matrix is not positive definite (smallest eigenvalue -1), "
            "nor is its rotation block: no weight can be derived from it");
}

// Two measurements of the same step, one of them with an indefinite information matrix: the
// chordal optimum is their average weighed by tau, tau = 3 / tr(I_t^-1) = 100 for the odd one
// (SE-Sync's reader), 25 for the other, so t = (100 * 1 + 25 * 2) / 125 = 1.2.
TEST(OddInformation, TheChordalSolveWeighsItByItsBlocksAsSESyncDoes) {
  const IsotropicWeights odd = isotropicWeights(coupled(100, 100, 200));
  EXPECT_NEAR(odd.tau, 100.0, 1e-9);
  EXPECT_NEAR(odd.kappa, 50.0, 1e-9);
  const IsotropicWeights plain = isotropicWeights(25.0 * Matrix6d::Identity());
  EXPECT_NEAR(plain.tau, 25.0, 1e-9);

  PoseGraph g;
  const NodeId x0('x', 0), x1('x', 1);
  PoseGraphEdge a, b;
  a.from = b.from = x0;
  a.to = b.to = x1;
  a.T_from_to.translation() = Eigen::Vector3d(1, 0, 0);
  a.information = coupled(100, 100, 200);
  b.T_from_to.translation() = Eigen::Vector3d(2, 0, 0);
  b.information = 25.0 * Matrix6d::Identity();
  g.edges = {a, b};
  std::map<NodeId, Eigen::Isometry3d> initial;
  initial[x0] = Eigen::Isometry3d::Identity();
  initial[x1] = Eigen::Isometry3d::Identity();
  initial[x1].translation() = Eigen::Vector3d(5, 1, -1);
  PoseGraphOptimizerOptions options;
  options.residual = ResidualType::kChordal;
  options.function_tolerance = 1e-14;
  PoseGraphProblem problem(g, initial, x0, options);
  const SolveSummary summary = problem.solve();
  ASSERT_TRUE(summary.usable) << summary.message;
  ASSERT_TRUE(std::isfinite(summary.final_cost));
  EXPECT_LT((problem.poses().at(x1).translation() - Eigen::Vector3d(1.2, 0, 0)).norm(), 1e-6);
  // The SE-Sync cost at the optimum: 100 * 0.2^2 + 25 * 0.8^2 = 20.
  EXPECT_NEAR(sesyncCost(g.edges, problem.poses()).value(), 20.0, 1e-6);
}

// A trajectory with exact measurements, every third edge's information indefinite: written as
// g2o text, read back, and solved from a perturbed start, both residuals reach the truth at cost
// 0 (before, the chordal solve's weights were not numbers and the geodesic one stopped short).
TEST(OddInformation, BothSolvesReachTheOptimumOfExactData) {
  std::mt19937 rng(91);
  std::map<NodeId, Eigen::Isometry3d> truth = testing::randomTrajectory(rng, 30);
  PoseGraph g;
  g.poses = truth;
  size_t odd = 0;
  const auto edge = [&](int i, int j) {
    PoseGraphEdge e;
    e.from = NodeId('x', static_cast<uint64_t>(i));
    e.to = NodeId('x', static_cast<uint64_t>(j));
    e.T_from_to = truth[e.from].inverse() * truth[e.to];
    e.information = g.edges.size() % 3 == 2 ? coupled(50, 200, 150) : 20.0 * Matrix6d::Identity();
    odd += g.edges.size() % 3 == 2;
    g.edges.push_back(e);
  };
  for (int i = 0; i + 1 < 30; ++i) edge(i, i + 1);
  for (int i = 0; i + 6 < 30; i += 4) edge(i, i + 6);
  auto read = io::parseG2o(io::writeG2o(g), "exact.g2o");
  ASSERT_TRUE(read.ok()) << read.error();
  EXPECT_EQ(read.value().notes.size(), odd);
  const PoseGraph& graph = read.value().graph;
  const NodeId anchor('x', 0);
  const std::map<NodeId, Eigen::Isometry3d> perturbed =
      testing::perturbPoses(graph.poses, anchor, 0.05, rng);
  for (const ResidualType type : {ResidualType::kChordal, ResidualType::kGeodesic}) {
    PoseGraphOptimizerOptions options;
    options.residual = type;
    options.function_tolerance = 1e-14;
    options.max_iterations = 200;
    PoseGraphProblem problem(graph, perturbed, anchor, options);
    const SolveSummary summary = problem.solve();
    ASSERT_TRUE(summary.usable) << residualTypeName(type) << ": " << summary.message;
    EXPECT_LT(summary.final_cost, 1e-10) << residualTypeName(type);
    double worst = 0.0;
    for (const auto& [id, pose] : problem.poses())
      worst = std::max(worst, (pose.matrix() - graph.poses.at(id).matrix()).norm());
    EXPECT_LT(worst, 1e-5) << residualTypeName(type);
  }
}

TEST(OddInformation, TheNearestPositiveDefiniteMatrixClampsOnlyWhatIsNotPositive) {
  const Matrix6d info = coupled(100, 100, 200);  // eigenvalues 300 (x3) and -100 (x3)
  const Matrix6d pd = nearestPositiveDefinite(info);
  const Eigen::SelfAdjointEigenSolver<Matrix6d> eigen(pd);
  EXPECT_NEAR(eigen.eigenvalues().maxCoeff(), 300.0, 1e-9);
  EXPECT_NEAR(eigen.eigenvalues().minCoeff(), 300.0 * kPositiveDefiniteFloor, 1e-12);
  EXPECT_EQ(pd.llt().info(), Eigen::Success);
  // A positive-definite matrix is its own nearest.
  const Matrix6d plain = 7.0 * Matrix6d::Identity();
  EXPECT_LT((nearestPositiveDefinite(plain) - plain).norm(), 1e-12);
}

}  // namespace
}  // namespace hydra_multi
