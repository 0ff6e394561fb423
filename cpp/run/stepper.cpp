#include "run/stepper.h"

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdlib>

#include "io/format.h"
#include "run/run.h"

namespace nct
{
namespace
{

using io::format;

std::string history(const std::vector<double>& residuals)
{
  std::string s;
  for (double r : residuals)
    s += format(" %.3e", r);
  return s;
}

/// The last converged (x, y), to return to when a step fails.
struct Saved
{
  explicit Saved(const solver::System& s) : x(*s.x), y(*s.y) {}
  void keep(const solver::System& s) { keep(*s.x, *s.y); }
  void keep(const Saved& other) { keep(other.x, other.y); }
  void keep(const dolfinx::la::Vector<double>& x_new, const std::vector<double>& y_new)
  {
    std::copy(x_new.array().begin(), x_new.array().end(), x.mutable_array().begin());
    y = y_new;
  }
  void restore(const solver::System& s) const
  {
    std::copy(x.array().begin(), x.array().end(), s.x->mutable_array().begin());
    *s.y = y;
  }
  /// The predictor of a ramp: (x, y) = this + r (this - earlier), the
  /// secant through the last two converged states.
  void extrapolate(const Saved& earlier, double r, const solver::System& s) const
  {
    auto out = s.x->mutable_array();
    for (std::size_t i = 0; i < out.size(); ++i)
      out[i] = x.array()[i] + r * (x.array()[i] - earlier.x.array()[i]);
    for (std::size_t i = 0; i < y.size(); ++i)
      (*s.y)[i] = y[i] + r * (y[i] - earlier.y[i]);
  }
  dolfinx::la::Vector<double> x;
  std::vector<double> y;
};

} // namespace

bool Stepper::attempt(solver::Newton& newton, const std::string& where,
                      const solver::System& system, solver::NewtonReport& report)
{
  report = newton.solve(system, settings);
  newton_iterations += report.iterations;
  if (!report.converged)
    _folder.log(format("  %s: Newton failed after %d iterations: %s; residuals:%s",
                       where.c_str(), report.iterations, report.reason.c_str(),
                       history(report.residuals).c_str()));
  return report.converged;
}

void Stepper::ramp(solver::Newton& newton, const std::string& phase, int steps,
                   const solver::System& system,
                   const std::function<void(double)>& load,
                   const std::function<void(double, const solver::NewtonReport&)>& done)
{
  // The last two converged states: `saved` at `reached`, `before` at `f_before`.
  Saved saved(system), before(system);
  const double nominal = 1.0 / steps, floor = std::ldexp(nominal, -_max_cuts);
  double reached = 0, increment = nominal, f_before = -1;
  int successes = 0;
  while (reached < 1.0 - 1e-12)
  {
    const double target = std::min(1.0, reached + increment);
    load(target);
    if (f_before >= 0)
      saved.extrapolate(before, (target - reached) / (reached - f_before), system);
    solver::NewtonReport report;
    if (!attempt(newton, format("%s %.4f", phase.c_str(), target), system, report))
    {
      saved.restore(system);
      if (increment / 2 < floor * (1 - 1e-12))
        throw Diverged(format("phase '%s' diverged: load fraction %.6f (from %.6f) failed "
                              "with the increment cut %d times (solver.max_step_cuts); "
                              "last Newton: %s; residuals:%s",
                              phase.c_str(), target, reached, _max_cuts,
                              report.reason.c_str(), history(report.residuals).c_str()));
      ++cuts;
      increment /= 2;
      successes = 0;
      continue;
    }
    before.keep(saved);
    f_before = reached;
    reached = target;
    saved.keep(system);
    if (++successes >= 2 && increment < nominal)
      increment = std::min(2 * increment, nominal), successes = 0;
    done(reached, report);
  }
}

void Stepper::march(solver::Newton& newton, const std::string& phase, double t0,
                    double duration, const dynamics::TimeStep& nominal_step,
                    const Dynamics& problem, const solver::System& system,
                    const std::function<void(double)>& load,
                    const std::function<void(double, double, const solver::NewtonReport&)>& done)
{
  // The last two converged states: `saved` at t, `before` at t_before.
  Saved saved(system), before(system);
  const double nominal = nominal_step.dt;
  const double floor = std::ldexp(nominal, -_max_cuts), end = t0 + duration;
  double t = t0, dt = nominal, last_dt = -1, t_before = 0;
  bool two = false; // are there two states to extrapolate from?
  // The extrapolating predictor: the problem's own, else the secant
  // through the last two states (which only it needs to keep).
  const bool extrapolate = _predictor == Predictor::extrapolate;
  const bool secant = extrapolate && !problem.predict;
  const bool adaptive = control.tolerance > 0 && problem.error;
  int successes = 0, steps = 0, rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (resume)
  {
    t = resume->t, dt = resume->dt, successes = resume->successes, steps = resume->steps;
    resume.reset();
  }
  static const int kill_at = [] {
    const char* n = std::getenv("NCT_TEST_KILL_AT_STEP"); // tests/checkpoint.py
    return n ? std::atoi(n) : 0;
  }();
  static int taken = 0;
  while (t < end - 1e-9 * nominal)
  {
    const double step = std::min(dt, end - t);
    // Every step: multistep coefficients depend on the steps before.
    problem.set_time_step(nominal_step.with_dt(step));
    // The Jacobian depends on dt: a kept factorisation is stale, unless
    // it only preconditions the exact Jacobian (krylov).
    if (step != last_dt && settings.jacobian != solver::Jacobian::krylov)
      newton.reset();
    last_dt = step;
    load(t + problem.load_level() * step);
    if (extrapolate && !secant)
      problem.predict();
    else if (secant && two)
      saved.extrapolate(before, step / (t - t_before), system);
    solver::NewtonReport report;
    if (!attempt(newton, format("%s t = %.4f ms, dt = %.4g ms", phase.c_str(), t + step, step),
                 system, report))
    {
      saved.restore(system);
      if (step / 2 < floor * (1 - 1e-12))
        throw Diverged(format("phase '%s' diverged: the step from t = %.6f ms failed with "
                              "dt = %.4g ms, the time step cut %d times (solver.max_step_cuts "
                              "of the nominal %g ms); last Newton: %s; residuals:%s",
                              phase.c_str(), t, step, _max_cuts, nominal,
                              report.reason.c_str(), history(report.residuals).c_str()));
      ++cuts;
      dt = step / 2;
      successes = 0;
      continue;
    }
    if (adaptive)
    {
      // Lengths of dynamics.dt 2^k: a kept factorisation lasts until the
      // estimate leaves [tol / 16, 0.8 tol] (twice the step, 8 times the error).
      const double error = problem.error(), tol = control.tolerance;
      if (error > tol && step > floor * (1 + 1e-12))
      {
        saved.restore(system);
        ++rejections;
        dt = std::max(floor, step / (error > 8 * tol ? 4 : 2));
        _folder.log(format("  %s t = %.4f ms: local error %.3e mm > dynamics.tolerance %.3e mm, "
                           "dt %.4g -> %.4g ms", phase.c_str(), t + step, error, tol, step, dt));
        continue;
      }
      if (error > 0.8 * tol)
        dt = std::max(floor, step / 2);
      else if (error < tol / 16 && 2 * step <= control.dt_max * (1 + 1e-12))
        dt = 2 * step;
    }
    problem.advance();
    if (secant)
    {
      before.keep(saved);
      t_before = t;
      two = true;
    }
    t += step;
    saved.keep(system);
    if (!adaptive && ++successes >= 2 && dt < nominal)
      dt = std::min(2 * dt, nominal), successes = 0;
    done(t, step, report);
    ++steps;
    if (boundaries.every > 0 && steps % boundaries.every == 0)
    {
      newton.reset();
      two = false; // the next step's predictor starts afresh too
      if (boundaries.at)
        boundaries.at({steps, t, dt, successes});
    }
    // A test's interruption at a chosen step (a real kill, as a pre-empted job's).
    if (++taken == kill_at && rank == 0)
      std::raise(SIGKILL);
  }
}

} // namespace nct
