// What a fit minimises over: its forward model at a point of the fitted
// variables. Two stand behind one interface: forward runs (each a child nct
// run, fit/forward.h, with finite-difference sensitivities, fit/cost.h) and
// an emulator of them (its likelihood, fit/emulated.h). fit::run (fit.cpp)
// is the one driver: the start, Levenberg-Marquardt with bounds, the
// answer's covariance and results; each model adds what it owns.
#pragma once

#include <chrono>
#include <memory>
#include <string>
#include <vector>

#include <ceres/ceres.h>

#include "fit/fit.h"
#include "fit/results.h"

namespace nct::fit
{

/// A fit's forward model.
class Model
{
public:
  virtual ~Model() = default;

  /// Where its evaluations go, for the fit's first line.
  virtual std::string plan() const = 0;
  /// What the start's check covered, for a dry run's last line.
  virtual std::string checked() const = 0;
  /// Before anything is minimised: what must hold at the start theta
  /// (throws scene::Error saying why not). False when interrupted.
  virtual bool check_start(const std::vector<double>& theta) = 0;

  /// The weighted residuals and their Jacobian at theta, for Ceres.
  virtual ceres::CostFunction& cost() = 0;
  /// The progress callback of its iterations (iterations.csv into `out`).
  virtual std::unique_ptr<Progress> progress(const double* theta,
                                             const std::filesystem::path& out) = 0;
  /// After the solver: the variables at a bound whose cost's gradient
  /// points out of the box, held there while the others are solved again
  /// (an active set); none where that costs more evaluations than it is
  /// worth.
  virtual std::vector<int> held_at_bounds(const std::vector<double>& theta) const = 0;

  /// Why the minimisation failed (the solver's summary): the words after
  /// "fit: failed" on stderr.
  virtual std::string failure(const ceres::Solver::Summary& summary) const = 0;
  /// What an interrupted fit had done: the words after "fit: interrupted".
  virtual std::string interrupted() const = 0;

  /// The answer at theta: the weighted residuals, the model's values at
  /// the observation points, chi2 where the residuals correlate, the run
  /// there. Throws std::runtime_error where the model cannot answer there.
  virtual Outcome answer(const std::vector<double>& theta) = 0;
  /// What the model adds to the answer (its runs, its posterior, a
  /// confirmation), the fit started at `start`.
  virtual void finish(Outcome& outcome, std::chrono::steady_clock::time_point start) = 0;
};

/// The forward runs of `fit` into options.out/runs.
std::unique_ptr<Model> forward_runs(const Fit& fit, const Options& options);
/// The fit's emulator (fit.emulator) and its confirming run.
std::unique_ptr<Model> emulated(const Fit& fit, const Options& options);

} // namespace nct::fit
