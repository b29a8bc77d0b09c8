#include "hydra_multi/optim/gnc.h"

#include <math.h>
#include <algorithm>

#include <cmath>

namespace hydra_multi {
namespace {

// Regularized lower incomplete gamma P(a, x): series for x < a + 1, continued fraction otherwise
// (Numerical Recipes, 6.2).
double regularizedGammaP(double a, double x) {
  if (x <= 0.0) return 0.0;
  // lgamma_r, not std::lgamma: that one writes the global signgam, a data race between the solves
  // that run on two threads.
  int sign = 0;
  const double log_prefactor = -x + a * std::log(x) - lgamma_r(a, &sign);
  if (x < a + 1.0) {
    double term = 1.0 / a, sum = term;
    for (int n = 1; n < 500; ++n) {
      term *= x / (a + n);
      sum += term;
      if (std::abs(term) < std::abs(sum) * 1e-15) break;
    }
    return sum * std::exp(log_prefactor);
  }
  const double tiny = 1e-300;
  double b = x + 1.0 - a, c = 1.0 / tiny, d = 1.0 / b, h = d;
  for (int i = 1; i < 500; ++i) {
    const double an = -i * (i - a);
    b += 2.0;
    d = an * d + b;
    if (std::abs(d) < tiny) d = tiny;
    c = b + an / c;
    if (std::abs(c) < tiny) c = tiny;
    d = 1.0 / d;
    const double delta = d * c;
    h *= delta;
    if (std::abs(delta - 1.0) < 1e-15) break;
  }
  return 1.0 - std::exp(log_prefactor) * h;
}

bool weightsConverged(const std::vector<double>& weights, double tolerance) {
  return std::all_of(weights.begin(), weights.end(),
                     [tolerance](double w) { return w <= tolerance || w >= 1.0 - tolerance; });
}

}  // namespace

double chiSquaredQuantile(int dof, double p) {
  double lo = 0.0, hi = std::max(1.0, 10.0 * dof);
  while (regularizedGammaP(0.5 * dof, 0.5 * hi) < p) hi *= 2.0;
  for (int i = 0; i < 200; ++i) {
    const double mid = 0.5 * (lo + hi);
    (regularizedGammaP(0.5 * dof, 0.5 * mid) < p ? lo : hi) = mid;
  }
  return 0.5 * (lo + hi);
}

double GncOptions::thresholdSq() const {
  return inlier_threshold_sq > 0.0 ? inlier_threshold_sq
                                   : chiSquaredQuantile(residual_dof, inlier_probability);
}

double tlsWeight(double r2, double mu, double c2) {
  if (r2 <= mu / (mu + 1.0) * c2) return 1.0;
  if (r2 >= (mu + 1.0) / mu * c2) return 0.0;
  return std::sqrt(c2) * std::sqrt(mu * (mu + 1.0)) / std::sqrt(r2) - mu;
}

GncResult runGnc(size_t num_robust, const WeightedSolver& solve, const GncOptions& options,
                 const std::vector<double>* initial_squared_residuals) {
  const double c2 = options.thresholdSq();
  GncResult result;
  result.weights.assign(num_robust, 1.0);
  WeightedSolution solution;
  if (initial_squared_residuals) {
    solution.squared_residuals = *initial_squared_residuals;
    for (const double r2 : solution.squared_residuals) solution.cost += r2;
  } else {
    solution = solve(result.weights);
  }
  const double max_r2 =
      solution.squared_residuals.empty()
          ? 0.0
          : *std::max_element(solution.squared_residuals.begin(), solution.squared_residuals.end());
  result.mu = c2 / (2.0 * max_r2 - c2);
  if (num_robust == 0 || result.mu <= 0.0) {
    result.stop_reason = "no outliers";
  } else {
    double previous_cost = solution.cost;
    result.stop_reason = "max iterations";
    for (int iteration = 0; iteration < options.max_iterations; ++iteration) {
      for (size_t k = 0; k < num_robust; ++k) {
        result.weights[k] = tlsWeight(solution.squared_residuals[k], result.mu, c2);
      }
      solution = solve(result.weights);
      result.iterations = iteration + 1;
      if (weightsConverged(result.weights, options.weight_tolerance)) {
        result.stop_reason = "weights converged";
        break;
      }
      if (std::abs(solution.cost - previous_cost) <=
          options.cost_tolerance * std::max(previous_cost, 1e-300)) {
        result.stop_reason = "cost converged";
        break;
      }
      previous_cost = solution.cost;
      result.mu *= options.mu_step;
    }
  }
  result.inliers.resize(num_robust);
  for (size_t k = 0; k < num_robust; ++k) {
    result.inliers[k] = result.weights[k] > options.inlier_weight;
    result.num_inliers += result.inliers[k] ? 1 : 0;
  }
  return result;
}

}  // namespace hydra_multi
