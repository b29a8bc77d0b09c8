#include "hydra_multi/optim/sparse_levenberg_marquardt.h"

#include <ceres/ceres.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <stdexcept>
#include <string>

#include "hydra_multi/core/parallel.h"
#include "hydra_multi/optim/serial_openmp.h"
#include "hydra_multi/optim/sparse_lm_impl.h"

namespace hydra_multi {

using namespace sparse_lm;

namespace {

// Ceres' Levenberg-Marquardt constants (Solver::Options defaults).
constexpr double kInitialRadius = 1e4;
constexpr double kMaxRadius = 1e16;
constexpr double kMinRadius = 1e-32;
constexpr double kMinDiagonal = 1e-6;
constexpr double kMaxDiagonal = 1e32;
constexpr double kMinRelativeDecrease = 1e-3;
constexpr int kMaxConsecutiveInvalidSteps = 5;

}  // namespace

bool sparse_lm::choleskyFactor(const Block& D, Block& L) {
  for (int j = 0; j < 6; ++j) {
    double d = D(j, j);
    for (int k = 0; k < j; ++k) d -= L(j, k) * L(j, k);
    if (!(d > 0.0)) return false;
    L(j, j) = std::sqrt(d);
    const double reciprocal = 1.0 / L(j, j);
    for (int i = j + 1; i < 6; ++i) {
      double s = D(i, j);
      for (int k = 0; k < j; ++k) s -= L(i, k) * L(j, k);
      L(i, j) = s * reciprocal;
    }
    for (int i = 0; i < j; ++i) L(i, j) = 0.0;
  }
  return true;
}

void sparse_lm::solveLower(const Block& L, Vector6& x) {
  for (int i = 0; i < 6; ++i) {
    double s = x[i];
    for (int k = 0; k < i; ++k) s -= L(i, k) * x[k];
    x[i] = s / L(i, i);
  }
}

void sparse_lm::solveLowerTransposed(const Block& L, Vector6& x) {
  for (int i = 6; i-- > 0;) {
    double s = x[i];
    for (int k = i + 1; k < 6; ++k) s -= L(k, i) * x[k];
    x[i] = s / L(i, i);
  }
}

void sparse_lm::solveRightLowerTransposed(const Block& L, Block& B) {
  for (int j = 0; j < 6; ++j) {
    for (int k = 0; k < j; ++k) B.col(j) -= L(j, k) * B.col(k);
    B.col(j) /= L(j, j);
  }
}

bool SparseLevenbergMarquardt::Impl::eliminateRange(size_t first, size_t last, Eigen::VectorXd& rhs,
                                                    bool defer) {
  for (size_t k = first; k < last; ++k) {
    const Elimination& e = eliminations[k];
    Block& L = factors[k];
    if (!choleskyFactor(read(diagonal_block[e.v], true), L)) return false;
    Vector6& z = solved_rhs[k];
    z = rhs.segment<6>(6 * e.v);
    solveLower(L, z);
    std::array<Block, 2>& Y = neighbour_products[k];
    const uint8_t deferred = defer ? e.deferred : 0;
    for (int n = 0; n < 2 && e.u[n] != kNone; ++n) {
      Y[n] = toNeighbour(e, n);  // H_{u_n v} L^-T
      solveRightLowerTransposed(L, Y[n]);
      const Block update = -(Y[n] * Y[n].transpose());
      const Vector6 w = Y[n] * z;
      if (deferred & (1u << n)) {
        deferred_blocks.push_back({e.uu[n], true, update});
        deferred_rhs.push_back({e.u[n], w});
      } else {
        add(e.uu[n], update, true);
        rhs.segment<6>(6 * e.u[n]) -= w;
      }
    }
    if (e.u01 != kNone) {
      const Block S = Y[0] * Y[1].transpose();  // the update of H_{u0 u1}
      const Block update = e.u[0] < e.u[1] ? Block(-S) : Block(-S.transpose());
      if (deferred & 4u) {
        deferred_blocks.push_back({e.u01, false, update});
      } else {
        add(e.u01, update, false);
      }
    }
  }
  return true;
}

bool SparseLevenbergMarquardt::Impl::eliminate(Eigen::VectorXd& rhs, int threads) {
  factors.resize(eliminations.size());
  solved_rhs.resize(eliminations.size());
  neighbour_products.resize(eliminations.size());
  const size_t split = threads >= 2 ? elimination_split : 0;
  if (split == 0) return eliminateRange(0, eliminations.size(), rhs, false);
  deferred_blocks.clear();
  deferred_rhs.clear();
  char done[2] = {0, 0};
  runOnThreads(2, [&](size_t t) {
    done[t] = t == 0 ? eliminateRange(0, split, rhs, false)
                     : eliminateRange(split, eliminations.size(), rhs, true);
  });
  if (!done[0] || !done[1]) return false;
  for (const DeferredBlock& d : deferred_blocks) add(d.block, d.value, d.diagonal);
  for (const DeferredRhs& d : deferred_rhs) rhs.segment<6>(6 * d.variable) -= d.value;
  return true;
}

void SparseLevenbergMarquardt::Impl::substituteBack(Eigen::VectorXd& step, int threads) {
  const auto substitute = [&](size_t first, size_t last) {
    for (size_t k = last; k-- > first;) {
      const Elimination& e = eliminations[k];
      Vector6 delta = solved_rhs[k];
      for (int n = 0; n < 2 && e.u[n] != kNone; ++n)
        delta -= neighbour_products[k][n].transpose() * step.segment<6>(6 * e.u[n]);
      solveLowerTransposed(factors[k], delta);
      step.segment<6>(6 * e.v) = delta;
    }
  };
  const size_t split = threads >= 2 ? elimination_split : 0;
  if (split == 0) return substitute(0, eliminations.size());
  runOnThreads(2, [&](size_t t) {
    if (t == 0) {
      substitute(0, split);
    } else {
      substitute(split, eliminations.size());
    }
  });
}

SparseLevenbergMarquardt::SparseLevenbergMarquardt(size_t num_poses, std::vector<LmTerm> terms,
                                                   const std::vector<bool>& fixed,
                                                   const ceres::Manifold& rotation,
                                                   SparseAnalyses* analyses, bool keep) {
  for (const LmTerm& t : terms) {
    if (t.geodesic == nullptr && t.cost->num_residuals() > kMaxResiduals)
      throw std::invalid_argument("SparseLevenbergMarquardt: a term has more than " +
                                  std::to_string(kMaxResiduals) + " residuals");
  }
  if (analyses != nullptr) impl_ = analyses->take(num_poses, terms, fixed);
  const bool ahead = impl_ != nullptr;
  if (!ahead) impl_ = std::make_unique<Impl>();
  Impl& m = *impl_;
  m.rotation = &rotation;
  m.terms = std::move(terms);
  m.keep_in = keep ? analyses : nullptr;
  if (ahead || (m.keep_in != nullptr && m.keep_in->dropped())) return;  // dropped: no analysis
  m.analyze(num_poses, fixed);
}

SparseLevenbergMarquardt::~SparseLevenbergMarquardt() {
  SparseAnalyses* keep_in = impl_->keep_in;
  if (keep_in != nullptr && !keep_in->dropped() && impl_->L != nullptr && impl_->H != nullptr) {
    impl_->keep_in = nullptr;
    impl_->allocateFactor();
    keep_in->keep(std::move(impl_));
  }
}

double SparseLevenbergMarquardt::factorizationFlops() const { return impl_->flops; }
size_t SparseLevenbergMarquardt::freePoses() const { return impl_->variables; }

SparseAnalyses::SparseAnalyses() = default;
SparseAnalyses::~SparseAnalyses() = default;

bool SparseAnalyses::holds() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return kept_ != nullptr;
}

size_t SparseAnalyses::heldFactorValues() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (kept_ == nullptr || kept_->L == nullptr || kept_->L->xtype == CHOLMOD_PATTERN) return 0;
  return kept_->L->xsize;
}

void SparseAnalyses::drop() {
  std::unique_ptr<SparseLevenbergMarquardt::Impl> held;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    dropped_ = true;
    held = std::move(kept_);
  }
}

bool SparseAnalyses::dropped() const {
  const std::lock_guard<std::mutex> lock(mutex_);
  return dropped_;
}

void SparseAnalyses::keep(std::unique_ptr<SparseLevenbergMarquardt::Impl> analysis) {
  std::unique_ptr<SparseLevenbergMarquardt::Impl> unkept;
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    if (dropped_) {
      unkept = std::move(analysis);
    } else {
      kept_ = std::move(analysis);
    }
  }
}

std::unique_ptr<SparseLevenbergMarquardt::Impl> SparseAnalyses::take(
    size_t num_poses, const std::vector<LmTerm>& terms, const std::vector<bool>& fixed) {
  const std::lock_guard<std::mutex> lock(mutex_);
  if (kept_ == nullptr) return nullptr;
  bool same = kept_->variable.size() == num_poses && kept_->terms.size() == terms.size();
  for (size_t p = 0; same && p < num_poses; ++p) {
    const bool held = p < fixed.size() && fixed[p];
    same = held == (kept_->variable[p] == kNone);
  }
  for (size_t k = 0; same && k < terms.size(); ++k)
    same = kept_->terms[k].i == terms[k].i && kept_->terms[k].j == terms[k].j;
  if (same) return std::move(kept_);
  kept_->freeFactorValues();  // the block goes back for this problem's own factor
  return nullptr;
}

LmSummary SparseLevenbergMarquardt::solve(std::vector<PoseParameters>& poses,
                                          const std::vector<double>& weights,
                                          const LmOptions& options) {
  Impl& m = *impl_;
  const SerialOpenMp serial;  // CHOLMOD's per-supernode loops, on this thread
  const auto start = std::chrono::steady_clock::now();
  LmSummary summary;
  const auto finish = [&](const std::string& why) {
    summary.message = "Levenberg-Marquardt (CHOLMOD): " + why + ", " +
                      std::to_string(summary.iterations) + " iterations";
    if (summary.single_precision_factorizations + summary.single_precision_fallbacks > 0) {
      summary.message += ", " + std::to_string(summary.single_precision_factorizations) +
                         " factorizations in single precision";
    }
    if (summary.single_precision_fallbacks > 0) {
      summary.message += ", " + std::to_string(summary.single_precision_fallbacks) +
                         " made in double where single precision failed";
    }
    summary.time_s =
        std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    return summary;
  };
  if (m.L == nullptr || m.H == nullptr) return finish("the symbolic factorization failed");
  const size_t n = 6 * m.variables;
  Eigen::VectorXd g;
  // Without iterations (a problem prepared for its analysis), the cost alone.
  double cost = options.max_iterations > 0 ? m.linearize(poses, weights, g, options.threads)
                                           : m.cost(poses, weights, options.threads);
  summary.initial_cost = summary.final_cost = cost;
  if (!std::isfinite(cost)) return finish("the initial cost is not finite");
  summary.usable = true;
  if (m.variables == 0) return finish("no free poses");

  double radius = kInitialRadius, decrease_factor = 2.0;
  int invalid_steps = 0;
  bool linearized = true;
  std::vector<double> diagonal(n);
  Eigen::VectorXd step(static_cast<Eigen::Index>(n));
  cholmod_dense* b = cholmod_l_zeros(6 * m.reduced, 1, CHOLMOD_REAL, &m.common);
  Eigen::VectorXd rhs_of(static_cast<Eigen::Index>(n));  // per variable
  std::vector<PoseParameters> candidate = poses;
  std::string why = "no convergence";
  while (summary.iterations < options.max_iterations) {
    if (!linearized) {
      cost = m.linearize(poses, weights, g, options.threads);
      linearized = true;
    }
    if (g.lpNorm<Eigen::Infinity>() <= options.gradient_tolerance) {
      why = "gradient tolerance reached";
      break;
    }
    if (radius < kMinRadius) {
      why = "trust region radius below its minimum";
      break;
    }
    ++summary.iterations;
    // (H + D / radius) delta = -g, damped and eliminated in place: the next step linearizes anew.
    auto* x = static_cast<double*>(m.H->x);
    for (size_t v = 0; v < m.variables; ++v) {
      for (int c = 0; c < 6; ++c) {
        double& d = x[m.diagonalSlot(v, c)];
        diagonal[6 * v + c] = std::clamp(d, kMinDiagonal, kMaxDiagonal);
        d += diagonal[6 * v + c] / radius;
      }
    }
    rhs_of = -g;
    const bool eliminated = m.eliminate(rhs_of, options.threads);
    auto* rhs = static_cast<double*>(b->x);  // in A's order
    for (size_t k = 0; k < n; ++k) {
      if (m.permuted[k] != kNone) rhs[m.permuted[k]] = rhs_of[static_cast<Eigen::Index>(k)];
    }
    const auto factorization_start = std::chrono::steady_clock::now();
    const bool positive =
        eliminated && m.factorize(options.threads, options.single_precision_from_flops, summary);
    summary.factorization_s +=
        std::chrono::duration<double>(std::chrono::steady_clock::now() - factorization_start)
            .count();
    cholmod_dense* delta = nullptr;
    if (positive && m.supernodal != nullptr) {
      m.supernodal->solve(*m.H, *m.L, rhs, options.threads);  // in place
    } else if (positive) {
      delta = cholmod_l_solve(CHOLMOD_A, m.L, b, &m.common);
    }
    const bool solved = positive && (m.supernodal != nullptr || delta != nullptr);
    if (solved) {
      const double* solution = delta != nullptr ? static_cast<const double*>(delta->x) : rhs;
      for (size_t k = 0; k < n; ++k) {  // solution: in A's order
        if (m.permuted[k] != kNone) step[static_cast<Eigen::Index>(k)] = solution[m.permuted[k]];
      }
      if (delta != nullptr) cholmod_l_free_dense(&delta, &m.common);
      m.substituteBack(step, options.threads);
    }
    linearized = false;
    bool taken = false;
    if (!solved && ++invalid_steps >= kMaxConsecutiveInvalidSteps) {
      why = "the damped normal equations could not be factorized";
      break;
    }
    if (solved) {
      double model_decrease = -step.dot(g);
      for (size_t k = 0; k < n; ++k) model_decrease += diagonal[k] / radius * step[k] * step[k];
      model_decrease *= 0.5;
      double x_norm_sq = 0.0;
      for (size_t p = 0; p < poses.size(); ++p) {
        candidate[p] = poses[p];
        x_norm_sq += poses[p].q.coeffs().squaredNorm() + poses[p].t.squaredNorm();
        const long v = m.variable[p];
        if (v == kNone) continue;
        const Eigen::Vector3d rotation_step = step.segment<3>(6 * v);
        m.rotation->Plus(poses[p].q.coeffs().data(), rotation_step.data(),
                         candidate[p].q.coeffs().data());
        candidate[p].t += step.segment<3>(6 * v + 3);
      }
      const double step_norm = step.norm();
      if (step_norm <=
          options.parameter_tolerance * (std::sqrt(x_norm_sq) + options.parameter_tolerance)) {
        why = "parameter tolerance reached";
        break;
      }
      const double new_cost = m.cost(candidate, weights, options.threads);
      if (std::isfinite(new_cost)) {
        invalid_steps = 0;
        const double decrease = cost - new_cost;
        const double rho = model_decrease > 0.0 ? decrease / model_decrease : -1.0;
        taken = rho > kMinRelativeDecrease;
        if (taken) {
          std::copy(candidate.begin(), candidate.end(), poses.begin());  // in place
          const double previous = cost;
          cost = new_cost;
          radius = std::min(kMaxRadius,
                            radius / std::max(1.0 / 3.0, 1.0 - std::pow(2.0 * rho - 1.0, 3)));
          decrease_factor = 2.0;
          if (std::abs(decrease) <= options.function_tolerance * previous) {
            why = "function tolerance reached";
            break;
          }
        }
      } else if (++invalid_steps >= kMaxConsecutiveInvalidSteps) {
        why = "too many steps whose cost is not finite";
        break;
      }
    }
    if (!taken) {
      radius /= decrease_factor;
      decrease_factor *= 2.0;
    }
  }
  cholmod_l_free_dense(&b, &m.common);
  summary.final_cost = cost;
  return finish(why);
}

}  // namespace hydra_multi
