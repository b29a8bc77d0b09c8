#include "hydra_multi/optim/pose_graph_optimizer.h"

#include <ceres/ceres.h>

#include <chrono>
#include <cstdio>
#include <optional>
#include <unordered_map>
#include <utility>

#include "hydra_multi/optim/residuals.h"
#include "hydra_multi/optim/sparse_levenberg_marquardt.h"

namespace hydra_multi {

const char* residualTypeName(ResidualType type) {
  return type == ResidualType::kChordal ? "chordal" : "geodesic";
}

struct PoseGraphProblem::Impl {
  PoseGraphOptimizerOptions options;
  std::vector<NodeId> ids;
  std::unordered_map<NodeId, size_t> index;
  std::vector<PoseParameters> blocks;  // Ceres parameter blocks point into these
  std::vector<PoseParameters> initial;
  std::optional<size_t> anchor;
  std::vector<bool> constant;  // per block (empty: none), besides the anchor
  std::unique_ptr<ceres::Manifold> rotation;
  // Per edge: its cost (none if excluded): a geodesic factor (in `geodesic`, one array for all)
  // or a Ceres cost function (chordal); its weight and its poses; left out (leaveOut): kept, but
  // not in the problem.
  struct EdgeBlock {
    const GeodesicFactor* geodesic = nullptr;
    std::unique_ptr<ceres::CostFunction> cost;
    double weight = 1.0;
    size_t i = 0, j = 0;
    bool left_out = false;
    bool hasCost() const { return geodesic != nullptr || cost != nullptr; }
    bool active() const { return hasCost() && !left_out; }
  };
  std::vector<GeodesicFactor> geodesic;
  std::vector<EdgeBlock> edges;
  // The Ceres cost functions of the geodesic factors, for a Ceres problem (made with it).
  std::vector<std::unique_ptr<ceres::CostFunction>> geodesic_costs;
  // Sparse Cholesky: our Levenberg-Marquardt, its analysis kept between solves.
  std::unique_ptr<SparseLevenbergMarquardt> lm;
  double analysis_s = 0.0;  ///< the analyses since the last solve reported them
  // Conjugate gradients: a Ceres problem, built on its first solve.
  std::unique_ptr<ceres::Problem> problem;
  std::vector<ceres::LossFunctionWrapper*> losses;  // per edge, owned by the problem

  // Drops the solvers built so far: the next solve builds them for the factors and free poses of
  // then.
  void reset() {
    lm.reset();
    problem.reset();
    losses.clear();
    geodesic_costs.clear();
  }

  static ceres::LossFunction* lossOf(double weight) {
    // A weight of exactly 1 uses no loss at all (plain least squares).
    return weight == 1.0 ? nullptr : new ceres::ScaledLoss(nullptr, weight, ceres::TAKE_OWNERSHIP);
  }

  ceres::Problem& ceresProblem() {
    if (problem) return *problem;
    ceres::Problem::Options po;
    po.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    po.manifold_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
    problem = std::make_unique<ceres::Problem>(po);
    for (auto& block : blocks) {
      problem->AddParameterBlock(block.q.coeffs().data(), 4, rotation.get());
      problem->AddParameterBlock(block.t.data(), 3);
    }
    losses.assign(edges.size(), nullptr);
    for (size_t k = 0; k < edges.size(); ++k) {
      EdgeBlock& e = edges[k];
      if (!e.active()) continue;
      ceres::CostFunction* cost = e.cost.get();
      if (e.geodesic != nullptr) {
        geodesic_costs.push_back(std::make_unique<GeodesicCost>(*e.geodesic));
        cost = geodesic_costs.back().get();
      }
      losses[k] = new ceres::LossFunctionWrapper(lossOf(e.weight), ceres::TAKE_OWNERSHIP);
      problem->AddResidualBlock(cost, losses[k], blocks[e.i].q.coeffs().data(),
                                blocks[e.i].t.data(), blocks[e.j].q.coeffs().data(),
                                blocks[e.j].t.data());
    }
    // Gauge: hold the anchor fixed, and the poses held constant.
    const std::vector<bool> fixed = fixedBlocks();
    for (size_t i = 0; i < fixed.size(); ++i) {
      if (!fixed[i]) continue;
      problem->SetParameterBlockConstant(blocks[i].q.coeffs().data());
      problem->SetParameterBlockConstant(blocks[i].t.data());
    }
    return *problem;
  }

  SparseLevenbergMarquardt& sparse() {
    if (lm) return *lm;
    const auto start = std::chrono::steady_clock::now();
    std::vector<LmTerm> terms;
    for (const EdgeBlock& e : edges) {
      if (e.active()) terms.push_back({e.cost.get(), e.i, e.j, e.geodesic});
    }
    lm = std::make_unique<SparseLevenbergMarquardt>(blocks.size(), std::move(terms), fixedBlocks(),
                                                    *rotation, options.analyses.get(),
                                                    options.keep_analysis);
    analysis_s += std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return *lm;
  }

  std::vector<bool> fixedBlocks() const {
    std::vector<bool> fixed = constant;
    fixed.resize(blocks.size(), false);
    if (anchor) fixed[*anchor] = true;
    return fixed;
  }
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
  if (options.residual == ResidualType::kChordal) {
    m.rotation = std::make_unique<ceres::EigenQuaternionManifold>();
  } else {
    m.rotation = std::make_unique<LeftQuaternionTangentManifold>();
  }
  m.edges.resize(graph.edges.size());
  if (options.residual != ResidualType::kChordal) m.geodesic.reserve(graph.edges.size());
  for (size_t k = 0; k < graph.edges.size(); ++k) {
    const PoseGraphEdge& edge = graph.edges[k];
    const auto i = m.index.find(edge.from);
    const auto j = m.index.find(edge.to);
    if (i == m.index.end() || j == m.index.end() || i->second == j->second) continue;
    Impl::EdgeBlock& e = m.edges[k];
    e.i = i->second;
    e.j = j->second;
    if (options.residual == ResidualType::kChordal) {
      e.cost.reset(ChordalResidual::Create(edge.T_from_to, isotropicWeights(edge.information)));
    } else {
      e.geodesic = &m.geodesic.emplace_back(edge.T_from_to, edge.information);
    }
  }
  if (const auto a = m.index.find(anchor); a != m.index.end()) m.anchor = a->second;
}

PoseGraphProblem::~PoseGraphProblem() = default;

void PoseGraphProblem::setOptions(const PoseGraphOptimizerOptions& options) {
  impl_->options = options;
}

const PoseGraphOptimizerOptions& PoseGraphProblem::options() const { return impl_->options; }

void PoseGraphProblem::setWeights(const std::vector<double>& weights) {
  Impl& m = *impl_;
  for (size_t k = 0; k < m.edges.size() && k < weights.size(); ++k) {
    if (!m.edges[k].hasCost()) continue;
    m.edges[k].weight = weights[k];
    if (m.problem && m.losses[k] != nullptr)
      m.losses[k]->Reset(Impl::lossOf(weights[k]), ceres::TAKE_OWNERSHIP);
  }
}

SolveSummary PoseGraphProblem::solve() {
  Impl& m = *impl_;
  const PoseGraphOptimizerOptions& o = m.options;
  SolveSummary result;
  // A left-out edge given a weight is a factor again: the problem is built anew.
  for (Impl::EdgeBlock& e : m.edges) {
    if (!e.left_out || e.weight == 0.0) continue;
    e.left_out = false;
    m.reset();
  }
  if (o.linear_solver == PoseGraphOptimizerOptions::LinearSolver::kSparseCholesky) {
    std::vector<double> weights;
    for (const Impl::EdgeBlock& e : m.edges) {
      if (e.active()) weights.push_back(e.weight);
    }
    const LmSummary summary = m.sparse().solve(
        m.blocks, weights,
        {o.max_iterations, o.function_tolerance, o.gradient_tolerance, o.parameter_tolerance,
         o.linearization_threads, o.single_precision_from_flops});
    result.usable = summary.usable;
    result.message = summary.message;
    result.iterations = summary.iterations;
    result.initial_cost = summary.initial_cost;
    result.final_cost = summary.final_cost;
    result.time_s = summary.time_s;
    result.factorization_s = summary.factorization_s;
    result.single_precision_factorizations = summary.single_precision_factorizations;
    result.single_precision_fallbacks = summary.single_precision_fallbacks;
    result.analysis_s = std::exchange(m.analysis_s, 0.0);
    if (o.verbose) std::fprintf(stderr, "%s\n", summary.message.c_str());
    return result;
  }
  ceres::Solver::Options options;
  options.linear_solver_type = ceres::CGNR;
  options.preconditioner_type = ceres::JACOBI;
  options.max_linear_solver_iterations = o.max_linear_iterations;
  options.max_num_iterations = o.max_iterations;
  options.function_tolerance = o.function_tolerance;
  options.gradient_tolerance = o.gradient_tolerance;
  options.parameter_tolerance = o.parameter_tolerance;
  options.num_threads = o.num_threads;
  options.minimizer_progress_to_stdout = o.verbose;
  options.logging_type = o.verbose ? ceres::PER_MINIMIZER_ITERATION : ceres::SILENT;
  ceres::Solver::Summary summary;
  ceres::Solve(options, &m.ceresProblem(), &summary);
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

PoseGraphProblem& PoseGraphProblem::holdConstant(const std::set<NodeId>& ids) {
  Impl& m = *impl_;
  m.constant.assign(m.blocks.size(), false);
  for (const NodeId id : ids) {
    if (const auto i = m.index.find(id); i != m.index.end()) m.constant[i->second] = true;
  }
  m.reset();  // analyzed again for the new free set on the next solve
  return *this;
}

PoseGraphProblem& PoseGraphProblem::leaveOut(const std::vector<bool>& edges) {
  Impl& m = *impl_;
  bool changed = false;
  for (size_t k = 0; k < m.edges.size(); ++k) {
    // An edge without a cost is no factor either way (and its weight is never set).
    const bool out = m.edges[k].hasCost() && k < edges.size() && edges[k];
    changed = changed || m.edges[k].left_out != out;
    m.edges[k].left_out = out;
  }
  if (changed) m.reset();
  return *this;
}

namespace {

Eigen::Isometry3d isometry(const PoseParameters& pose) {
  Eigen::Isometry3d T = Eigen::Isometry3d::Identity();
  T.linear() = pose.q.normalized().toRotationMatrix();
  T.translation() = pose.t;
  return T;
}

}  // namespace

std::map<NodeId, Eigen::Isometry3d> PoseGraphProblem::poses() const {
  std::map<NodeId, Eigen::Isometry3d> result;
  for (size_t i = 0; i < impl_->ids.size(); ++i)  // ids ascend (the constructor's map)
    result.emplace_hint(result.end(), impl_->ids[i], isometry(impl_->blocks[i]));
  return result;
}

void PoseGraphProblem::posesInto(std::map<NodeId, Eigen::Isometry3d>& poses) const {
  const std::vector<NodeId>& ids = impl_->ids;
  bool same = poses.size() == ids.size();
  auto it = poses.begin();
  for (size_t i = 0; same && i < ids.size(); ++i, ++it) same = it->first == ids[i];
  if (!same) {
    poses = this->poses();
    return;
  }
  it = poses.begin();
  for (size_t i = 0; i < ids.size(); ++i, ++it) it->second = isometry(impl_->blocks[i]);
}

std::vector<double> PoseGraphProblem::squaredResiduals() const {
  std::vector<double> result(impl_->edges.size(), 0.0);
  for (size_t k = 0; k < impl_->edges.size(); ++k) {
    const Impl::EdgeBlock& e = impl_->edges[k];
    if (!e.active()) continue;
    const PoseParameters &a = impl_->blocks[e.i], &b = impl_->blocks[e.j];
    if (e.geodesic != nullptr) {
      Vector6d residual;
      e.geodesic->evaluate(a.q, a.t, b.q, b.t, residual, nullptr, nullptr);
      // Summed as a vector of run-time size, in the order the solver sums a term's.
      result[k] = Eigen::Map<const Eigen::VectorXd>(residual.data(), 6).squaredNorm();
      continue;
    }
    const double* parameters[4] = {a.q.coeffs().data(), a.t.data(), b.q.coeffs().data(),
                                   b.t.data()};
    Eigen::VectorXd residual(e.cost->num_residuals());
    e.cost->Evaluate(parameters, residual.data(), nullptr);
    result[k] = residual.squaredNorm();
  }
  return result;
}

double PoseGraphProblem::choleskyFlopsPerPose() {
  const SparseLevenbergMarquardt& lm = impl_->sparse();
  return lm.factorizationFlops() / static_cast<double>(std::max<size_t>(lm.freePoses(), 1));
}

bool PoseGraphProblem::edgeIncluded(size_t edge) const {
  return edge < impl_->edges.size() && impl_->edges[edge].active();
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
