// The minimiser's settings and the answer's covariance (cpp/fit/solver.h).
#include "fit/solver.h"

#include <algorithm>

#include <glog/logging.h>

#include "io/format.h"

namespace nct::fit
{
using io::nan;

ceres::Problem::Options problem_options()
{
  FLAGS_minloglevel = 3;
  FLAGS_logtostderr = true;
  ceres::Problem::Options options;
  options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  return options;
}

void add_bounded(ceres::Problem& problem, const Fit& fit, ceres::CostFunction& cost,
                 std::vector<double>& theta)
{
  problem.AddResidualBlock(&cost, nullptr, theta.data());
  for (std::size_t i = 0; i < theta.size(); ++i)
  {
    const Parameter& p = fit.parameters[i];
    problem.SetParameterLowerBound(theta.data(), int(i), p.variable(p.lower));
    problem.SetParameterUpperBound(theta.data(), int(i), p.variable(p.upper));
  }
}

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
