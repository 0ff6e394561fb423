// Load ramps and time marching with step cutting, over one Newton solver.
#pragma once

#include <functional>
#include <optional>
#include <string>

#include "dynamics/time_step.h"
#include "io/output.h"
#include "solid/problem.h"
#include "solver/newton.h"

namespace nct
{

/// Quasi-static load ramps and dynamic time marching, each on a Newton
/// solver of the system's Jacobian. A failed step is retried at half the
/// increment, down to a floor of 2^-max_cuts of the nominal one; after
/// two successes in a row the increment doubles back towards the nominal
/// one. Failing at the floor throws Diverged.
class Stepper
{
public:
  /// A step's first Newton iterate: the last converged state, or its
  /// extrapolation: a ramp's secant through the last two converged states,
  /// a time step's Dynamics::predict (else the secant).
  enum class Predictor
  {
    previous,
    extrapolate
  };

  Stepper(const solver::NewtonSettings& settings, int max_cuts, Predictor predictor,
          io::RunFolder& folder)
      : settings(settings), _max_cuts(max_cuts), _predictor(predictor), _folder(folder)
  {
  }

  /// Take the loads from fraction 0 (the current state) to 1 in `steps`
  /// steps: `load(f)` sets them, `done(f, report)` sees every converged step.
  void ramp(solver::Newton& newton, const std::string& phase, int steps,
            const solver::System& system,
            const std::function<void(double)>& load,
            const std::function<void(double, const solver::NewtonReport&)>& done);

  /// What marching needs of a time-dependent problem.
  struct Dynamics
  {
    /// Before every step: the step (the nominal one, or a cut of it).
    std::function<void(const dynamics::TimeStep& step)> set_time_step;
    std::function<double()> load_level; ///< where in the step the loads act, in [0, 1]
    std::function<void()> advance;      ///< the converged step becomes the old state
    /// The step's first iterate from the old state (e.g. its velocity and
    /// acceleration), for Predictor::extrapolate; null: the secant.
    std::function<void()> predict = nullptr;
    /// After a converged step, before advance: its local error estimate
    /// [mm], for adaptive steps; null: none (the steps stay fixed).
    std::function<double()> error = nullptr;
  };

  /// March a problem from time t0 for `duration` [ms] with the nominal
  /// step (cut steps keep its integrator): `load(t)` sets the loads at the
  /// problem's load level within each step, `done(t, dt, report)` sees every
  /// converged step after the problem advanced. With `control.tolerance`
  /// and the problem's error estimate e the steps adapt, their lengths the
  /// nominal one times 2^k (a new length costs the kept factorisation): a
  /// step with e above the tolerance is taken again at half the length (a
  /// quarter above 8 times it); the next step is half as long after e above
  /// 0.8 of it, twice as long (up to control.dt_max) after e below 1/16 of
  /// it (a second-order integrator's local error grows as h^3).
  void march(solver::Newton& newton, const std::string& phase, double t0, double duration,
             const dynamics::TimeStep& nominal,
             const Dynamics& problem, const solver::System& system,
             const std::function<void(double)>& load,
             const std::function<void(double, double, const solver::NewtonReport&)>& done);

  /// Where a march is after a converged step: steps taken, time [ms],
  /// the next step's length [ms] and the successes in a row since a cut.
  struct MarchState
  {
    int steps = 0;
    double t = 0, dt = 0;
    int successes = 0;
  };
  /// Every `every`-th step of a march is a checkpoint boundary (0: none):
  /// the Newton solver drops its kept factorisation there and the secant
  /// predictor its history, so that a run resumed at a boundary continues
  /// exactly as the uninterrupted one, and `at` sees the march's state (to
  /// write a checkpoint).
  struct Boundaries
  {
    int every = 0;
    std::function<void(const MarchState&)> at;
  };
  Boundaries boundaries;
  /// A march resumed from a checkpoint: the next march() starts from this
  /// state (its t0 and first step ignored) and clears it.
  std::optional<MarchState> resume;

  /// How the march chooses its steps ([dynamics]).
  dynamics::StepControl control;

  int newton_iterations = 0;
  int cuts = 0;
  int rejections = 0; ///< adaptive steps taken again for their error
  /// Each Newton solve's stopping and globalisation.
  solver::NewtonSettings settings;

private:
  /// One Newton solve; false when it failed.
  bool attempt(solver::Newton& newton, const std::string& where, const solver::System& system,
               solver::NewtonReport& report);

  int _max_cuts;
  Predictor _predictor;
  io::RunFolder& _folder;
};

} // namespace nct
