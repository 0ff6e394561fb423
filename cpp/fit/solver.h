// The minimiser's settings and the answer's covariance, shared by the fit
// on forward runs (fit.cpp) and on an emulator (emulated.cpp).
#pragma once

#include <cstddef>
#include <vector>

#include <ceres/ceres.h>

#include "fit/fit.h"

namespace nct::fit
{

/// Levenberg-Marquardt with the fit's limits, Ceres' own log silent.
ceres::Solver::Options solver_options(const Fit& fit);

/// The covariance of the fitted variables at theta (row by row; the
/// Gauss-Newton inverse of J^T J); NaN everywhere when the Jacobian is
/// rank-deficient.
std::vector<double> covariance_at(ceres::Problem& problem, double* theta, std::size_t n,
                                  bool& identifiable);

} // namespace nct::fit
