// The minimiser's settings and the answer's covariance (cpp/fit/solver.h).
#include "fit/solver.h"

#include <algorithm>

#include "io/format.h"

namespace nct::fit
{
using io::nan;

/// Levenberg-Marquardt with the fit's limits, Ceres' own log silent.
ceres::Solver::Options solver_options(const Fit& fit)
{
  ceres::Solver::Options options;
  options.minimizer_type = ceres::TRUST_REGION;
  options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = fit.max_iterations;
  options.function_tolerance = fit.tolerance;
  options.parameter_tolerance = fit.tolerance;
  options.gradient_tolerance = 1e-10;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  options.update_state_every_iteration = true;
  return options;
}

std::vector<double> covariance_at(ceres::Problem& problem, double* theta, std::size_t n,
                                  bool& identifiable)
{
  std::vector<double> covariance(n * n, nan);
  ceres::Covariance::Options options;
  options.algorithm_type = ceres::DENSE_SVD;
  options.num_threads = 1;
  ceres::Covariance cov(options);
  identifiable
      = cov.Compute(std::vector<std::pair<const double*, const double*>>{{theta, theta}}, &problem)
        && cov.GetCovarianceBlock(theta, theta, covariance.data());
  if (!identifiable)
    std::fill(covariance.begin(), covariance.end(), nan);
  return covariance;
}

} // namespace nct::fit
