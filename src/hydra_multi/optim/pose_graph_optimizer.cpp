#include "hydra_multi/optim/pose_graph_optimizer.h"

#include <ceres/ceres.h>

#include <unordered_map>

#include "hydra_multi/optim/residuals.h"

namespace hydra_multi {

const char* residualTypeName(ResidualType type) {
  return type == ResidualType::kChordal ? "chordal" : "geodesic";
}

struct PoseGraphProblem::Impl {
  struct PoseBlock {
    Eigen::Quaterniond q;  // Ceres parameter blocks point into these
    Eigen::Vector3d t;
  };
  PoseGraphOptimizerOptions options;
  std::vector<NodeId> ids;
  std::unordered_map<NodeId, size_t> index;
  std::vector<PoseBlock> blocks;
  std::vector<PoseBlock> initial;
  // Per edge: the Ceres cost function, the weight wrapper, the residual block (null if excluded),
  // and the pose indices.
  struct EdgeBlock {
    ceres::CostFunction* cost = nullptr;  // owned by the problem
    ceres::LossFunctionWrapper* loss = nullptr;
    ceres::ResidualBlockId id = nullptr;
    size_t i = 0, j = 0;
  };
  std::vector<EdgeBlock> edges;
  ceres::Problem problem;
};

PoseGraphProblem::PoseGraphProblem(const PoseGraph& graph,
                                   const std::map<NodeId, Eigen::Isometry3d>& initial,
                                   NodeId anchor, const PoseGraphOptimizerOptions& options)
    : impl_(std::make_unique<Impl>()) {
  Impl& m = *impl_;
  m.options = options;
  m.blocks.reserve(initial.size());
  for (const auto& [id, T] : initial) {
    m.index[id] = m.ids.size();
    m.ids.push_back(id);
    m.blocks.push_back({Eigen::Quaterniond(T.linear()).normalized(), T.translation()});
  }
  m.initial = m.blocks;
  // The geodesic cost gives its Jacobian in the tangent space (residuals.h).
  ceres::Manifold* quaternion_manifold =
      options.residual == ResidualType::kChordal
          ? static_cast<ceres::Manifold*>(new ceres::EigenQuaternionManifold)
          : new LeftQuaternionTangentManifold;
  for (auto& block : m.blocks) {
    m.problem.AddParameterBlock(block.q.coeffs().data(), 4, quaternion_manifold);
    m.problem.AddParameterBlock(block.t.data(), 3);
  }
  m.edges.resize(graph.edges.size());
  for (size_t k = 0; k < graph.edges.size(); ++k) {
    const PoseGraphEdge& edge = graph.edges[k];
    const auto i = m.index.find(edge.from);
    const auto j = m.index.find(edge.to);
    if (i == m.index.end() || j == m.index.end() || i->second == j->second) continue;
    Impl::EdgeBlock& e = m.edges[k];
    e.i = i->second;
    e.j = j->second;
    e.cost = options.residual == ResidualType::kChordal
                 ? ChordalResidual::Create(edge.T_from_to, isotropicWeights(edge.information))
                 : new GeodesicCost(edge.T_from_to, edge.information);
    e.loss = new ceres::LossFunctionWrapper(nullptr, ceres::TAKE_OWNERSHIP);
    e.id = m.problem.AddResidualBlock(e.cost, e.loss, m.blocks[e.i].q.coeffs().data(),
                                      m.blocks[e.i].t.data(), m.blocks[e.j].q.coeffs().data(),
                                      m.blocks[e.j].t.data());
  }
  // Gauge: hold the anchor fixed.
  if (auto a = m.index.find(anchor); a != m.index.end()) {
    m.problem.SetParameterBlockConstant(m.blocks[a->second].q.coeffs().data());
    m.problem.SetParameterBlockConstant(m.blocks[a->second].t.data());
  }
}

PoseGraphProblem::~PoseGraphProblem() = default;

void PoseGraphProblem::setOptions(const PoseGraphOptimizerOptions& options) {
  impl_->options = options;
}

const PoseGraphOptimizerOptions& PoseGraphProblem::options() const { return impl_->options; }

void PoseGraphProblem::setWeights(const std::vector<double>& weights) {
  for (size_t k = 0; k < impl_->edges.size() && k < weights.size(); ++k) {
    Impl::EdgeBlock& e = impl_->edges[k];
    if (!e.id) continue;
    // A weight of exactly 1 uses no loss at all (plain least squares).
    e.loss->Reset(weights[k] == 1.0
                      ? nullptr
                      : new ceres::ScaledLoss(nullptr, weights[k], ceres::TAKE_OWNERSHIP),
                  ceres::TAKE_OWNERSHIP);
  }
}

SolveSummary PoseGraphProblem::solve() {
  ceres::Solver::Options options;
  if (impl_->options.linear_solver ==
      PoseGraphOptimizerOptions::LinearSolver::kConjugateGradients) {
    options.linear_solver_type = ceres::CGNR;
    options.preconditioner_type = ceres::JACOBI;
    options.max_linear_solver_iterations = impl_->options.max_linear_iterations;
  } else {
    options.linear_solver_type = ceres::SPARSE_NORMAL_CHOLESKY;
    options.sparse_linear_algebra_library_type = ceres::SUITE_SPARSE;
  }
  options.max_num_iterations = impl_->options.max_iterations;
  options.function_tolerance = impl_->options.function_tolerance;
  options.gradient_tolerance = impl_->options.gradient_tolerance;
  options.parameter_tolerance = impl_->options.parameter_tolerance;
  options.num_threads = impl_->options.num_threads;
  options.minimizer_progress_to_stdout = impl_->options.verbose;
  options.logging_type = impl_->options.verbose ? ceres::PER_MINIMIZER_ITERATION : ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &impl_->problem, &summary);
  SolveSummary result;
  result.usable = summary.IsSolutionUsable();
  result.message = summary.BriefReport();
  result.iterations = static_cast<int>(summary.iterations.size()) - 1;
  result.initial_cost = summary.initial_cost;
  result.final_cost = summary.final_cost;
  result.time_s = summary.total_time_in_seconds;
  return result;
}

void PoseGraphProblem::resetToInitial() {
  for (size_t i = 0; i < impl_->blocks.size(); ++i) {
    impl_->blocks[i].q = impl_->initial[i].q;
    impl_->blocks[i].t = impl_->initial[i].t;
  }
}

PoseGraphProblem& PoseGraphProblem::setPoses(const std::map<NodeId, Eigen::Isometry3d>& poses) {
  for (const auto& [id, T] : poses) {
    const auto i = impl_->index.find(id);
    if (i == impl_->index.end()) continue;
    impl_->blocks[i->second].q = Eigen::Quaterniond(T.linear()).normalized();
    impl_->blocks[i->second].t = T.translation();
  }
  return *this;
}

std::map<NodeId, Eigen::Isometry3d> PoseGraphProblem::poses() const {
  std::map<NodeId, Eigen::Isometry3d> result;
  for (size_t i = 0; i < impl_->ids.size(); ++i) {
    Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
    T.linear() = impl_->blocks[i].q.normalized().toRotationMatrix();
    T.translation() = impl_->blocks[i].t;
    result[impl_->ids[i]] = T;
  }
  return result;
}

std::vector<double> PoseGraphProblem::squaredResiduals() const {
  std::vector<double> result(impl_->edges.size(), 0.0);
  for (size_t k = 0; k < impl_->edges.size(); ++k) {
    const Impl::EdgeBlock& e = impl_->edges[k];
    if (!e.id) continue;
    const double* parameters[4] = {
        impl_->blocks[e.i].q.coeffs().data(), impl_->blocks[e.i].t.data(),
        impl_->blocks[e.j].q.coeffs().data(), impl_->blocks[e.j].t.data()};
    Eigen::VectorXd residual(e.cost->num_residuals());
    e.cost->Evaluate(parameters, residual.data(), nullptr);
    result[k] = residual.squaredNorm();
  }
  return result;
}

bool PoseGraphProblem::edgeIncluded(size_t edge) const {
  return edge < impl_->edges.size() && impl_->edges[edge].id != nullptr;
}

Result<double> sesyncCost(const std::vector<PoseGraphEdge>& edges,
                          const std::map<NodeId, Eigen::Isometry3d>& poses) {
  double total = 0.0;
  for (const PoseGraphEdge& edge : edges) {
    const auto i = poses.find(edge.from);
    const auto j = poses.find(edge.to);
    if (i == poses.end() || j == poses.end()) {
      return Error{"edge " + edge.from.str() + " - " + edge.to.str() + " has no pose at an end"};
    }
    const IsotropicWeights w = isotropicWeights(edge.information);
    const Eigen::Matrix3d& R_i = i->second.linear();
    const Eigen::Matrix3d& R_j = j->second.linear();
    total += w.kappa * (R_j - R_i * edge.T_from_to.linear()).squaredNorm();
    total += w.tau * (j->second.translation() - i->second.translation() -
                      R_i * edge.T_from_to.translation())
                         .squaredNorm();
  }
  return total;
}

}  // namespace hydra_multi
