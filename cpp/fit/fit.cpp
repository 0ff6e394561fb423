// Running a fit (cpp/fit/fit.h): the start checked, the Levenberg-Marquardt
// iterations (Ceres) over the forward runs (fit/forward.h, fit/cost.h),
// the answer's uncertainty, and its results (fit/results.h).
#include "fit/fit.h"

#include <chrono>
#include <cmath>
#include <iostream>

#include <ceres/ceres.h>

#include "fit/cost.h"
#include "fit/emulated.h"
#include "fit/forward.h"
#include "fit/readings.h"
#include "fit/results.h"
#include "fit/solver.h"
#include "io/format.h"
#include "io/output.h"
#include "io/text.h"
#include "jobs/jobs.h"
#include "jobs/launcher_input.h"
#include "scene/scene.h"

namespace nct::fit
{
namespace fs = std::filesystem;
using io::nan;

namespace
{

/// The start's scene must pass nct check (the eye's geometry...) before
/// any run: a scene::Error saying why not. False when interrupted.
bool check_start(const Fit& fit, const Options& o, const std::vector<std::string>& sets)
{
  const fs::path log = o.out / "check.log";
  int code = 0;
  jobs::run({{jobs::nct_command(o.program, "check", fit.scene, sets, {}), log, 1, fit.mpiexec,
              nullptr}},
            1, [&](std::size_t, int c) { code = c; });
  if (jobs::interrupted())
    return false;
  if (code != 0)
  {
    std::string why = jobs::tail(io::read_text(log), 3);
    throw scene::Error(fit.file.string() + ": the start's scene: " + why);
  }
  fs::remove(log);
  return true;
}

/// The fit's first line: its size and where its forward runs go.
void print_plan(const Fit& fit, const Options& o, const Forward& forward)
{
  std::cout << "fit " << fit.file.string()
            << (fit.patient ? " (patient " + fit.patient->id + ")" : std::string()) << ": "
            << fit.parameters.size() << " parameter(s), " << fit.residuals()
            << " weighted residual(s) from " << fit.observations.size() << " observation(s), "
            << (o.jobs > 0 ? o.jobs : fit.jobs) << " run(s) at once on " << fit.ranks
            << " rank(s) each -> " << o.out.string() << " (" << forward.reusable()
            << " forward runs on disk)" << std::endl;
}

/// The answer at the final point theta: residuals, covariance, the run.
Outcome outcome_at(const Fit& fit, ceres::Problem& problem, const Cost& cost,
                   std::vector<double>& theta)
{
  Outcome out;
  out.residuals.resize(fit.residuals());
  const double* blocks[] = {theta.data()};
  if (!cost.Evaluate(blocks, out.residuals.data(), nullptr))
    throw std::runtime_error("the forward run at the fitted values failed");
  out.best_run = cost.last_run;
  out.model = model_values(fit, out.best_run);
  out.covariance = covariance_at(problem, theta.data(), theta.size(), out.identifiable);
  out.theta = theta;
  return out;
}

} // namespace

int run(const Fit& fit, const Options& o)
{
  if (fit.emulator)
    return run_emulated(fit, o);
  const auto start = std::chrono::steady_clock::now();
  claim_folder(fit, o.out, "fit");
  jobs::catch_interrupts();
  // Slurm must take the options before anything runs or is submitted.
  Forward forward(fit, o, jobs::launcher_for(fit.launcher, o.launcher, o.out, fit.ranks, "fit",
                                             fit.file));
  std::vector<double> theta;
  for (const Parameter& p : fit.parameters)
    theta.push_back(p.variable(p.start));
  if (!check_start(fit, o, forward.sets(theta)))
    return 130;
  print_plan(fit, o, forward);
  if (o.dry_run)
  {
    std::cout << "fit: the fit file and the start's scene check out; nothing run (--dry-run)"
              << std::endl;
    return 0;
  }
  io::write_atomic(o.out / "fit.toml", io::read_text(fit.file));

  ceres::Problem problem(problem_options());
  Cost cost(fit, forward, o.jobs > 0 ? o.jobs : fit.jobs);
  add_bounded(problem, fit, cost, theta);
  ceres::Solver::Options options = solver_options(fit);
  Progress progress(fit, &forward, &cost, theta.data(), o.out);
  options.callbacks.push_back(&progress);
  ceres::Solver::Summary summary;
  ceres::Solve(options, &problem, &summary);
  if (jobs::interrupted())
  {
    std::cerr << "fit: interrupted after " << forward.total() << " forward runs; the same "
              << "command resumes it" << std::endl;
    return 130;
  }
  if (summary.termination_type == ceres::FAILURE || summary.termination_type == ceres::USER_FAILURE
      || !std::isfinite(summary.final_cost))
  {
    std::cerr << "fit: failed: " << summary.message << " ("
              << (cost.notes.empty() ? "a forward run at the start failed"
                                     : "the finite differences: " + cost.notes.back())
              << "; see " << (o.out / "runs").string() << ")" << std::endl;
    return 3;
  }

  Outcome outcome = outcome_at(fit, problem, cost, theta);
  const bool converged = summary.termination_type == ceres::CONVERGENCE;
  outcome.status = converged ? "converged" : "max_iterations";
  outcome.message = summary.message;
  outcome.iterations = int(summary.iterations.size()) - 1;
  outcome.cost = summary.final_cost;
  outcome.sets = forward.sets(theta);
  outcome.forward_runs = forward.total();
  outcome.reused = forward.reusable();
  outcome.fallbacks = progress.fallbacks;
  outcome.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report_answer(fit, outcome, o.out);
  return converged ? 0 : 3;
}

} // namespace nct::fit
