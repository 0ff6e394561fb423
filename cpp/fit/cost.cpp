// The fit's cost for Ceres (cpp/fit/cost.h).
#include "fit/cost.h"

#include <algorithm>
#include <cmath>

#include "fit/readings.h"
#include "io/format.h"

namespace nct::fit
{
namespace fs = std::filesystem;
using io::format;

namespace
{

/// theta with its i-th variable at x.
std::vector<double> moved(std::vector<double> theta, std::size_t i, double x)
{
  theta[i] = x;
  return theta;
}

} // namespace

std::vector<double> weighted(const Fit& fit, const std::vector<double>& model,
                             const std::vector<double>& theta)
{
  std::vector<double> r;
  std::size_t j = 0;
  for (auto& o : fit.observations)
    for (std::size_t i = 0; i < o.value.size(); ++i, ++j)
      r.push_back((model[j] - o.value[i]) / o.sd[i]);
  for (std::size_t i = 0; i < fit.parameters.size(); ++i)
    if (const auto& p = fit.parameters[i]; p.prior)
      r.push_back((p.value(theta[i]) - p.prior_mean) / p.prior_sd);
  return r;
}

Cost::Cost(const Fit& fit, Forward& forward, int at_once)
    : _fit(fit), _forward(forward),
      _speculate(int(fit.parameters.size()) * (fit.central ? 2 : 1) + 1 <= at_once)
{
  set_num_residuals(int(fit.residuals()));
  mutable_parameter_block_sizes()->push_back(int(fit.parameters.size()));
}

bool Cost::Evaluate(double const* const* parameters, double* residuals, double** jacobians) const
{
  const std::size_t n = _fit.parameters.size(), m = _fit.residuals();
  const std::vector<double> theta(parameters[0], parameters[0] + n);
  std::vector<std::vector<double>> points = {theta};
  const bool jacobian = jacobians && jacobians[0];
  std::vector<std::array<double, 2>> pairs(n); // each parameter's two points
  if (jacobian || _speculate)
  {
    pairs = difference_points(theta);
    for (std::size_t i = 0; i < n; ++i)
      for (double x : pairs[i])
        points.push_back(moved(theta, i, x));
  }
  std::vector<fs::path> runs;
  try
  {
    runs = _forward.runs(points);
  }
  catch (const Forward::Interrupted&)
  {
    return false;
  }
  if (runs[0].empty())
    return false;
  const auto r0 = weighted(_fit, model_values(_fit, runs[0]), theta);
  std::copy(r0.begin(), r0.end(), residuals);
  last_run = runs[0];
  if (!jacobian)
    return true;
  for (std::size_t i = 0; i < n; ++i)
  {
    auto [a, b] = pairs[i];
    fs::path run_a = runs[1 + 2 * i], run_b = runs[2 + 2 * i];
    if ((run_a.empty() || run_b.empty()) && !fall_back(i, theta, runs[0], a, b, run_a, run_b))
      return false; // no difference of this parameter converged: Ceres shrinks its step
    const auto ra = weighted(_fit, model_values(_fit, run_a), moved(theta, i, a));
    const auto rb = weighted(_fit, model_values(_fit, run_b), moved(theta, i, b));
    for (std::size_t j = 0; j < m; ++j)
      jacobians[0][j * n + i] = (ra[j] - rb[j]) / (a - b);
  }
  return true;
}

double Cost::step(std::size_t i, const std::vector<double>& theta) const
{
  const Parameter& p = _fit.parameters[i];
  return _fit.step * (p.log ? 1.0 : std::max(std::abs(theta[i]), 1e-3 * (p.upper - p.lower)));
}

std::vector<std::array<double, 2>> Cost::difference_points(const std::vector<double>& theta) const
{
  std::vector<std::array<double, 2>> pairs(theta.size());
  for (std::size_t i = 0; i < theta.size(); ++i)
  {
    const Parameter& p = _fit.parameters[i];
    const double h = step(i, theta);
    double a = theta[i] + h, b = _fit.central ? theta[i] - h : theta[i];
    if (a > p.variable(p.upper))
      a = theta[i], b = theta[i] - h;
    else if (b < p.variable(p.lower))
      b = theta[i];
    pairs[i] = {a, b};
  }
  return pairs;
}

bool Cost::fall_back(std::size_t i, const std::vector<double>& theta, const fs::path& run0,
                     double& a, double& b, fs::path& run_a, fs::path& run_b) const
{
  const Parameter& p = _fit.parameters[i];
  const double h = step(i, theta), lo = p.variable(p.lower), hi = p.variable(p.upper);
  const std::string failed = run_a.empty() && run_b.empty() ? "both neighbours"
                             : run_a.empty() ? format("the run at %.6g", p.value(a))
                                             : format("the run at %.6g", p.value(b));
  // The sides to try, in order: the one whose run converged against theta,
  // the other side, then each at a quarter of the step.
  std::vector<double> tries;
  if (!run_b.empty() && b != theta[i])
    tries.push_back(b);
  if (!run_a.empty() && a != theta[i])
    tries.push_back(a);
  for (double x : {theta[i] - h, theta[i] + h, theta[i] + h / 4, theta[i] - h / 4})
    if (x >= lo && x <= hi && x != a && x != b)
      tries.push_back(x);
  for (double x : tries)
  {
    fs::path run;
    if (x == a && !run_a.empty())
      run = run_a;
    else if (x == b && !run_b.empty())
      run = run_b;
    else
      try
      {
        run = _forward.runs({moved(theta, i, x)})[0];
      }
      catch (const Forward::Interrupted&)
      {
        return false;
      }
    if (run.empty())
      continue;
    const bool quarter = std::abs(std::abs(x - theta[i]) - h / 4) < 1e-12 * h;
    notes.push_back(format("%s: %s %s difference (%s did not converge)",
                           p.label.c_str(), quarter ? "a quarter-step" : "a",
                           x > theta[i] ? "forward" : "backward", failed.c_str()));
    a = x, run_a = run, b = theta[i], run_b = run0;
    if (a < b)
      std::swap(a, b), std::swap(run_a, run_b);
    return true;
  }
  notes.push_back(format("%s: no difference converged (%s; the other side and a quarter step "
                         "did not either)",
                         p.label.c_str(), failed.c_str()));
  return false;
}

} // namespace nct::fit
