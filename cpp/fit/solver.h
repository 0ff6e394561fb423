// The minimiser's settings and the answer's covariance, shared by the fit
// on forward runs (fit.cpp) and on an emulator (emulated.cpp).
#pragma once

#include <cstddef>
#include <vector>

#include <ceres/ceres.h>

#include "fit/fit.h"

namespace nct::fit
{

/// A problem that leaves its cost to its owner, Ceres' own log (glog)
/// silent but for fatal errors: the fit reports itself.
ceres::Problem::Options problem_options();

/// The fit's cost on the variables theta, each inside its parameter's bounds.
void add_bounded(ceres::Problem& problem, const Fit& fit, ceres::CostFunction& cost,
                 std::vector<double>& theta);

/// Levenberg-Marquardt with the fit's limits, Ceres' own log silent.
ceres::Solver::Options solver_options(const Fit& fit);

/// The covariance of the fitted variables at theta (row by row; the
/// Gauss-Newton inverse of J^T J); NaN everywhere when the Jacobian is
/// rank-deficient.
std::vector<double> covariance_at(ceres::Problem& problem, double* theta, std::size_t n,
                                  bool& identifiable);

} // namespace nct::fit
