// SparseLevenbergMarquardt's linearization: H = J^T W J and g = J^T W r into the stored blocks,
// each block summed by one thread in term order; the cost alone for a trial step.

#include <ceres/ceres.h>

#include <algorithm>
#include <cmath>

#include "hydra_multi/core/parallel.h"
#include "hydra_multi/optim/residuals.h"
#include "hydra_multi/optim/sparse_lm_impl.h"

namespace hydra_multi {

using namespace sparse_lm;

bool SparseLevenbergMarquardt::Impl::evaluate(size_t k, const std::vector<PoseParameters>& poses,
                                              Residual& r, JacobianRows* J_i,
                                              JacobianRows* J_j) const {
  const LmTerm& term = terms[k];
  const PoseParameters& a = poses[term.i];
  const PoseParameters& b = poses[term.j];
  const bool free_i = variable[term.i] != kNone, free_j = variable[term.j] != kNone;
  if (term.geodesic != nullptr) {
    Vector6 r6;
    Block J6_i, J6_j;
    const bool jacobians = J_i != nullptr;
    term.geodesic->evaluate(a.q, a.t, b.q, b.t, r6, jacobians && free_i ? &J6_i : nullptr,
                            jacobians && free_j ? &J6_j : nullptr);
    r = r6;
    if (jacobians && free_i) *J_i = J6_i;
    if (jacobians && free_j) *J_j = J6_j;
    return true;
  }
  const double* parameters[4] = {a.q.coeffs().data(), a.t.data(), b.q.coeffs().data(), b.t.data()};
  const int m = term.cost->num_residuals();
  r.resize(m);
  if (J_i == nullptr) return term.cost->Evaluate(parameters, r.data(), nullptr);
  AmbientJacobian<4> q_i(m, 4), q_j(m, 4);
  AmbientJacobian<3> t_i(m, 3), t_j(m, 3);
  double* jacobians[4] = {free_i ? q_i.data() : nullptr, free_i ? t_i.data() : nullptr,
                          free_j ? q_j.data() : nullptr, free_j ? t_j.data() : nullptr};
  if (!term.cost->Evaluate(parameters, r.data(), jacobians)) return false;
  Eigen::Matrix<double, 4, 3, Eigen::RowMajor> plus;
  if (free_i) {
    rotation->PlusJacobian(a.q.coeffs().data(), plus.data());
    J_i->resize(m, 6);
    J_i->leftCols<3>() = q_i * plus;
    J_i->rightCols<3>() = t_i;
  }
  if (free_j) {
    rotation->PlusJacobian(b.q.coeffs().data(), plus.data());
    J_j->resize(m, 6);
    J_j->leftCols<3>() = q_j * plus;
    J_j->rightCols<3>() = t_j;
  }
  return true;
}

size_t SparseLevenbergMarquardt::Impl::threadsFor(int requested) const {
  if (requested <= 1 || terms.size() < kThreadsFrom) return 1;
  return std::min<size_t>(static_cast<size_t>(requested), 8);
}

double SparseLevenbergMarquardt::Impl::cost(const std::vector<PoseParameters>& poses,
                                            const std::vector<double>& weights,
                                            int requested_threads) const {
  const size_t threads = threadsFor(requested_threads);
  term_cost.assign(terms.size(), 0.0);
  std::vector<char> failed(threads, 0);
  runOnThreads(threads, [&](size_t t) {
    Residual r;
    const size_t first = terms.size() * t / threads, last = terms.size() * (t + 1) / threads;
    for (size_t k = first; k < last; ++k) {
      const double w = k < weights.size() ? weights[k] : 1.0;
      if (w == 0.0) continue;
      if (!evaluate(k, poses, r, nullptr, nullptr)) {
        failed[t] = 1;
        return;
      }
      term_cost[k] = 0.5 * w * r.squaredNorm();
    }
  });
  return summedCost(failed);
}

double SparseLevenbergMarquardt::Impl::summedCost(const std::vector<char>& failed) const {
  if (std::find(failed.begin(), failed.end(), 1) != failed.end()) return HUGE_VAL;
  double total = 0.0;
  for (const double c : term_cost) total += c;
  return std::isfinite(total) ? total : HUGE_VAL;
}

void SparseLevenbergMarquardt::Impl::partition(size_t threads) {
  if (visits.size() == threads) return;
  std::vector<size_t> ends(variables, 0);
  size_t total = 0;
  for (const LmTerm& t : terms) {
    for (const size_t pose : {t.i, t.j}) {
      if (variable[pose] == kNone) continue;
      ++ends[static_cast<size_t>(variable[pose])];
      ++total;
    }
  }
  std::vector<size_t> owner(variables);
  size_t seen = 0;
  for (size_t v = 0; v < variables; ++v) {
    owner[v] = std::min(threads - 1, seen * threads / std::max<size_t>(total, 1));
    seen += ends[v];
  }
  visits.assign(threads, {});
  for (size_t k = 0; k < terms.size(); ++k) {
    const long vi = variable[terms[k].i], vj = variable[terms[k].j];
    const size_t cost_owner = vi != kNone ? owner[vi] : vj != kNone ? owner[vj] : 0;
    for (size_t t = 0; t < threads; ++t) {
      uint8_t parts = t == cost_owner ? kOwnCost : 0;
      if (vi != kNone && owner[vi] == t) parts |= kOwnI;
      if (vj != kNone && owner[vj] == t) parts |= kOwnJ;
      if (vi != kNone && vj != kNone && vi != vj && owner[std::max(vi, vj)] == t) parts |= kOwnIJ;
      if (parts != 0) visits[t].push_back({static_cast<uint32_t>(k), parts});
    }
  }
}

template <typename ResidualType, typename JacobianType>
void SparseLevenbergMarquardt::Impl::addTerm(size_t k, uint8_t parts, double w, Eigen::VectorXd& g,
                                             const ResidualType& r, const JacobianType& J_i,
                                             const JacobianType& J_j) {
  if (parts & kOwnCost) term_cost[k] = 0.5 * w * r.squaredNorm();
  const long vi = variable[terms[k].i], vj = variable[terms[k].j];
  const TermBlocks& b = term_blocks[k];
  if (parts & kOwnI) {
    add(b.ii, w * J_i.transpose() * J_i, true);
    g.segment<6>(6 * vi) += w * J_i.transpose() * r;
  }
  if (parts & kOwnJ) {
    add(b.jj, w * J_j.transpose() * J_j, true);
    g.segment<6>(6 * vj) += w * J_j.transpose() * r;
  }
  if (parts & kOwnIJ) {
    const Block ij = vi < vj ? Block(w * J_i.transpose() * J_j) : Block(w * J_j.transpose() * J_i);
    add(b.ij, ij, false);
  }
}

bool SparseLevenbergMarquardt::Impl::linearizeTerm(size_t k, uint8_t parts,
                                                   const std::vector<PoseParameters>& poses,
                                                   double w, Eigen::VectorXd& g, Residual& r,
                                                   JacobianRows& J_i, JacobianRows& J_j) {
  const LmTerm& term = terms[k];
  if (term.geodesic != nullptr) {
    const PoseParameters& a = poses[term.i];
    const PoseParameters& b = poses[term.j];
    Vector6 r6;
    Block J6_i, J6_j;
    term.geodesic->evaluate(a.q, a.t, b.q, b.t, r6, variable[term.i] != kNone ? &J6_i : nullptr,
                            variable[term.j] != kNone ? &J6_j : nullptr);
    addTerm(k, parts, w, g, r6, J6_i, J6_j);
    return true;
  }
  if (!evaluate(k, poses, r, &J_i, &J_j)) return false;
  addTerm(k, parts, w, g, r, J_i, J_j);
  return true;
}

double SparseLevenbergMarquardt::Impl::linearize(const std::vector<PoseParameters>& poses,
                                                 const std::vector<double>& weights,
                                                 Eigen::VectorXd& g, int requested_threads) {
  std::fill_n(static_cast<double*>(H->x), H->nzmax, 0.0);
  g.setZero(static_cast<Eigen::Index>(6 * variables));
  const size_t threads = threadsFor(requested_threads);
  partition(threads);
  term_cost.assign(terms.size(), 0.0);
  std::vector<char> failed(threads, 0);
  runOnThreads(threads, [&](size_t t) {
    Residual r;
    JacobianRows J_i, J_j;
    for (const Visit& visit : visits[t]) {
      const double w = visit.term < weights.size() ? weights[visit.term] : 1.0;
      if (w == 0.0) continue;
      if (!linearizeTerm(visit.term, visit.parts, poses, w, g, r, J_i, J_j)) {
        failed[t] = 1;
        return;
      }
    }
  });
  return summedCost(failed);
}

}  // namespace hydra_multi
