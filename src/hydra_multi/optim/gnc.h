#pragma once
// Graduated Non-Convexity with the truncated least squares cost (Yang, Antonante, Tzoumas, Carlone,
// RA-L 2020), generic over any weighted least-squares problem, as in GTSAM's GncOptimizer.
//
// With r_k^2 the squared (Mahalanobis) residual of robust factor k and c^2 the inlier threshold:
//   mu_0 = c^2 / (2 max_k r_k^2 - c^2)           (if <= 0, every factor is an inlier: stop)
//   w_k  = 1                                      if r_k^2 <= mu / (mu + 1) c^2
//          0                                      if r_k^2 >= (mu + 1) / mu c^2
//          c sqrt(mu (mu + 1)) / r_k - mu          otherwise
//   solve the weighted problem; mu <- 1.4 mu; stop when every weight is within 1e-4 of 0 or 1, the
//   cost changes less than 1e-5 relatively, or after 100 iterations.
// Known inliers (odometry, rigidity) are not robust factors and keep weight 1. A robust factor is
// an inlier when its final weight is > 0.5.

#include <functional>
#include <string>
#include <vector>

namespace hydra_multi {

/// The p-quantile of the chi-square distribution with `dof` degrees of freedom (by bisection on
/// the regularized lower incomplete gamma function).
double chiSquaredQuantile(int dof, double p);

struct GncOptions {
  /// c^2; when <= 0 it is chiSquaredQuantile(residual_dof, inlier_probability).
  double inlier_threshold_sq = 0.0;
  int residual_dof = 6;
  double inlier_probability = 0.99;
  double mu_step = 1.4;
  int max_iterations = 100;
  double weight_tolerance = 1e-4;
  double cost_tolerance = 1e-5;
  double inlier_weight = 0.5;  ///< final weight above which a factor is an inlier

  double thresholdSq() const;
};

/// What a weighted solve reports back to GNC.
struct WeightedSolution {
  std::vector<double> squared_residuals;  ///< r_k^2 of every robust factor at the new solution
  double cost = 0.0;                      ///< the weighted cost, for the convergence test
};

/// Solves the problem with the given robust-factor weights (known inliers at weight 1).
using WeightedSolver = std::function<WeightedSolution(const std::vector<double>& weights)>;

struct GncResult {
  std::vector<double> weights;
  std::vector<bool> inliers;
  size_t num_inliers = 0;
  int iterations = 0;  ///< GNC iterations (weighted solves after the first least squares)
  double mu = 0.0;     ///< the final control parameter
  std::string
      stop_reason;  ///< "no outliers", "weights converged", "cost converged", "max iterations"
};

/// The TLS weight of a factor with squared residual r2 at control parameter mu.
double tlsWeight(double r2, double mu, double c2);

/// Runs GNC over `num_robust` robust factors. Without `initial_squared_residuals`, the first call
/// of `solve` uses unit weights (plain least squares) and mu_0 and the first weights come from its
/// solution, as in GTSAM. With them (the residuals at the initial estimate), GNC starts from the
/// initial estimate instead: a least-squares solve over many gross outliers can throw away a good
/// initial guess that GNC then never recovers (measured on CSAIL and sphere2500 with outliers).
GncResult runGnc(size_t num_robust, const WeightedSolver& solve, const GncOptions& options = {},
                 const std::vector<double>* initial_squared_residuals = nullptr);

}  // namespace hydra_multi
