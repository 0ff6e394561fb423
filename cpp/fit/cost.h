// The fit's cost for Ceres: the weighted residuals of the observations and
// priors at a point of the fitted variables, and their Jacobian by finite
// differences of forward runs (with fallbacks where a neighbour's run does
// not converge).
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

#include <ceres/ceres.h>

#include "fit/fit.h"
#include "fit/forward.h"

namespace nct::fit
{

/// The weighted residuals (model - measured) / sd of the observations
/// (model values given), then the priors' (value - mean) / sd, at the
/// fitted variables theta.
std::vector<double> weighted(const Fit& fit, const std::vector<double>& model,
                             const std::vector<double>& theta);

/// The fit's residuals for Ceres: each evaluation one batch of forward
/// runs (the point, and with the Jacobian its finite-difference
/// neighbours, in parallel).
class Cost : public ceres::CostFunction
{
public:
  /// `at_once`: forward runs at once; when a point and its neighbours fit
  /// in one batch, a point's residuals come with its neighbours' runs
  /// (the Jacobian, if the step is taken, then costs no wait).
  Cost(const Fit& fit, Forward& forward, int at_once);

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override;

  /// What the last Jacobian's differences fell back to, for the progress
  /// line (taken by it).
  mutable std::vector<std::string> notes;
  mutable std::filesystem::path last_run; ///< the run of the last point evaluated

private:
  /// Parameter i's finite-difference step at theta: relative on a log
  /// scale, else relative to the value (or to the bounds' span near 0).
  double step(std::size_t i, const std::vector<double>& theta) const;

  /// Each parameter's two difference points: theta + h and theta (forward)
  /// or theta - h (central); one-sided backwards at the upper bound,
  /// forwards at the lower.
  std::vector<std::array<double, 2>> difference_points(const std::vector<double>& theta) const;

  /// A neighbour of parameter i did not converge: the difference on the
  /// other side of theta, else a quarter of the step on either side (a
  /// one-sided difference with theta's run, `run0`). True with the points
  /// (a, b) and their runs of the first that converged; each try noted.
  bool fall_back(std::size_t i, const std::vector<double>& theta,
                 const std::filesystem::path& run0, double& a, double& b,
                 std::filesystem::path& run_a, std::filesystem::path& run_b) const;

  const Fit& _fit;
  Forward& _forward;
  bool _speculate;
};

} // namespace nct::fit
