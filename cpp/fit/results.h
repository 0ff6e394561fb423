// A fit's results: a progress line and a row of iterations.csv per
// iteration, and the answer (fit.json: the parameters with their
// uncertainty and correlations, the observations' fit, warnings;
// observations.csv: every measured point against the model) with its
// summary on the console.
#pragma once

#include <chrono>
#include <array>
#include <cmath>
#include <filesystem>
#include <sstream>
#include <string>
#include <vector>

#include <ceres/ceres.h>
#include <nlohmann/json.hpp>

#include "fit/cost.h"
#include "fit/fit.h"
#include "fit/forward.h"

namespace nct::fit
{

/// A progress line and a row of iterations.csv per iteration; stops the
/// solver when interrupted.
class Progress : public ceres::IterationCallback
{
public:
  /// `theta`: the variables the solver updates; iterations.csv goes into
  /// `out`; `forward` and `cost` null for a fit without forward runs.
  Progress(const Fit& fit, const Forward* forward, const Cost* cost, const double* theta,
           const std::filesystem::path& out);

  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override;

  /// Every fallback of the differences so far.
  std::vector<std::string> fallbacks;

private:
  const Fit& _fit;
  const Forward* _forward;
  const Cost* _cost;
  const double* _theta;
  std::filesystem::path _out;
  std::chrono::steady_clock::time_point _start;
  std::ostringstream _csv;
};

/// Where a fit ended: what its answer reports.
struct Outcome
{
  std::string status;             ///< "converged" or "max_iterations"
  std::string message;            ///< the solver's
  int iterations = 0;             ///< iterations taken (the start not counted)
  double cost = 0;                ///< the solver's final cost: chi2 / 2
  std::vector<double> theta;      ///< the fitted variables
  std::vector<double> residuals;  ///< the weighted residuals at theta
  std::vector<double> model;      ///< the model's values at the observation points
  std::vector<double> covariance; ///< theta's, row by row; NaN where not identifiable
  bool identifiable = true;       ///< the covariance could be computed
  std::vector<int> held;          ///< the variables the active set held at a bound
  std::filesystem::path best_run; ///< the forward run at theta
  std::vector<std::string> sets;  ///< its overrides
  int forward_runs = 0;           ///< forward runs finished, reused or not
  int reused = 0;                 ///< of them, found on disk at the start
  std::vector<std::string> fallbacks; ///< what the finite differences fell back to
  double wall_s = 0;              ///< the fit's time so far
  /// chi2 when the residuals are not independent (an emulator's
  /// likelihood); NaN: the sum of the residuals' squares.
  double chi2 = std::nan("");
  /// 95 % intervals and SEs of the values from a posterior's samples;
  /// empty: from the covariance.
  std::vector<std::array<double, 2>> intervals;
  std::vector<double> se;
  nlohmann::json extra = nlohmann::json::object(); ///< merged into fit.json
};

/// The answer into `folder` (fit.json, observations.csv) and its summary
/// on stdout.
void report_answer(const Fit& fit, const Outcome& outcome, const std::filesystem::path& folder);

/// The folder `out` made the fit's (or the cohort's, `what`): created, and
/// refused with a scene::Error if it holds another one (its fit.toml differs).
void claim_folder(const Fit& fit, const std::filesystem::path& out, const char* what);

} // namespace nct::fit
