// Running a fit (cpp/fit/fit.h): one driver over either forward model
// (fit/model.h): the start checked, Levenberg-Marquardt with bounds
// (Ceres), an active set where the model gives one, the answer's
// covariance, and its results (fit/results.h).
#include "fit/fit.h"

#include <chrono>
#include <cmath>
#include <iostream>

#include <ceres/ceres.h>

#include "fit/model.h"
#include "fit/results.h"
#include "fit/solver.h"
#include "io/output.h"
#include "io/text.h"
#include "jobs/jobs.h"

namespace nct::fit
{

namespace
{

/// The fit's first line: its size and where its evaluations go.
void print_plan(const Fit& fit, const Options& o, const Model& model)
{
  std::cout << "fit " << fit.file.string()
            << (fit.patient ? " (patient " + fit.patient->id + ")" : std::string()) << ": "
            << fit.parameters.size() << " parameter(s), " << fit.residuals()
            << " weighted residual(s) from " << fit.observations.size() << " observation(s), "
            << model.plan() << " -> " << o.out.string() << std::endl;
}

/// Where Levenberg-Marquardt ends from theta (updated): the solver's
/// summary and its iterations, the variables held at a bound.
struct Minimum
{
  ceres::Solver::Summary summary;
  int iterations = 0;
  std::vector<int> held;
};

Minimum minimise(const Fit& fit, Model& model, ceres::Problem& problem,
                 std::vector<double>& theta, Progress& progress)
{
  add_bounded(problem, fit, model.cost(), theta);
  ceres::Solver::Options options = solver_options(fit);
  options.callbacks.push_back(&progress);
  Minimum m;
  ceres::Solve(options, &problem, &m.summary);
  m.iterations = int(m.summary.iterations.size()) - 1;
  if (jobs::interrupted())
    return m;
  // Ceres projects each step onto the bounds: along a valley that ends at
  // a bound its steps shrink to nothing. The variables at a bound whose
  // gradient pushes outwards are held there and the others solved again.
  m.held = model.held_at_bounds(theta);
  if (!m.held.empty() && m.held.size() < theta.size())
  {
    problem.SetManifold(theta.data(), new ceres::SubsetManifold(int(theta.size()), m.held));
    ceres::Solve(options, &problem, &m.summary);
    m.iterations += int(m.summary.iterations.size()) - 1;
  }
  return m;
}

} // namespace

int run(const Fit& fit, const Options& o)
{
  const auto start = std::chrono::steady_clock::now();
  claim_folder(fit, o.out, "fit");
  jobs::catch_interrupts();
  // Slurm must take the options before anything runs or is submitted.
  std::unique_ptr<Model> model = fit.emulator ? emulated(fit, o) : forward_runs(fit, o);
  std::vector<double> theta;
  for (const Parameter& p : fit.parameters)
    theta.push_back(p.variable(p.start));
  if (!model->check_start(theta))
    return 130;
  print_plan(fit, o, *model);
  if (o.dry_run)
  {
    std::cout << "fit: the fit file and " << model->checked() << " check out; nothing run "
              << "(--dry-run)" << std::endl;
    return 0;
  }
  io::write_atomic(o.out / "fit.toml", io::read_text(fit.file));

  ceres::Problem problem(problem_options());
  const auto progress = model->progress(theta.data(), o.out);
  const Minimum minimum = minimise(fit, *model, problem, theta, *progress);
  const ceres::Solver::Summary& summary = minimum.summary;
  if (jobs::interrupted())
  {
    std::cerr << "fit: interrupted" << model->interrupted() << "; the same command resumes it"
              << std::endl;
    return 130;
  }
  if (summary.termination_type == ceres::FAILURE || summary.termination_type == ceres::USER_FAILURE
      || !std::isfinite(summary.final_cost))
  {
    std::cerr << "fit: failed" << model->failure(summary) << std::endl;
    return 3;
  }

  Outcome outcome = model->answer(theta);
  outcome.covariance = covariance_at(problem, theta.data(), theta.size(), outcome.identifiable);
  outcome.status = summary.termination_type == ceres::CONVERGENCE ? "converged" : "max_iterations";
  outcome.message = summary.message;
  outcome.iterations = minimum.iterations;
  outcome.cost = summary.final_cost;
  outcome.sets = forward_sets(fit, theta);
  outcome.fallbacks = progress->fallbacks;
  outcome.held = minimum.held;
  model->finish(outcome, start);
  outcome.wall_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  report_answer(fit, outcome, o.out);
  return outcome.status == "converged" ? 0 : 3;
}

} // namespace nct::fit
