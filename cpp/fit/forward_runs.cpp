// The fit's forward model of forward runs (fit/model.h): the start's scene
// checked by nct check, the residuals and their finite differences by
// runs (fit/cost.h), the answer at the last run.
#include "fit/cost.h"
#include "fit/forward.h"
#include "fit/model.h"
#include "fit/readings.h"
#include "io/text.h"
#include "jobs/jobs.h"
#include "jobs/launcher_input.h"
#include "scene/scene.h"

namespace nct::fit
{
namespace
{
namespace fs = std::filesystem;

class ForwardRuns : public Model
{
public:
  ForwardRuns(const Fit& fit, const Options& o)
      : _fit(fit), _options(o),
        _forward(fit, o,
                 jobs::launcher_for(fit.launcher, o.launcher, o.out, fit.ranks, "fit", fit.file)),
        _cost(fit, _forward, o.jobs > 0 ? o.jobs : fit.jobs)
  {
  }

  std::string plan() const override
  {
    return std::to_string(_options.jobs > 0 ? _options.jobs : _fit.jobs) + " run(s) at once on "
           + std::to_string(_fit.ranks) + " rank(s) each (" + std::to_string(_forward.reusable())
           + " forward runs on disk)";
  }

  std::string checked() const override { return "the start's scene"; }

  /// The start's scene must pass nct check (the eye's geometry...) before
  /// any run.
  bool check_start(const std::vector<double>& theta) override
  {
    const fs::path log = _options.out / "check.log";
    int code = 0;
    jobs::run({{jobs::nct_command(_options.program, "check", _fit.scene, _forward.sets(theta), {}),
                log, 1, _fit.mpiexec, nullptr}},
              1, [&](std::size_t, int c) { code = c; });
    if (jobs::interrupted())
      return false;
    if (code != 0)
    {
      const std::string why = jobs::tail(io::read_text(log), 3);
      throw scene::Error(_fit.file.string() + ": the start's scene: " + why);
    }
    fs::remove(log);
    return true;
  }

  ceres::CostFunction& cost() override { return _cost; }

  std::unique_ptr<Progress> progress(const double* theta, const fs::path& out) override
  {
    return std::make_unique<Progress>(_fit, &_forward, &_cost, theta, out);
  }

  /// None: each evaluation of the gradient is a batch of runs.
  std::vector<int> held_at_bounds(const std::vector<double>&) const override { return {}; }

  std::string failure(const ceres::Solver::Summary& summary) const override
  {
    return ": " + summary.message + " ("
           + (_cost.notes.empty() ? "a forward run at the start failed"
                                  : "the finite differences: " + _cost.notes.back())
           + "; see " + (_options.out / "runs").string() + ")";
  }

  std::string interrupted() const override
  {
    return " after " + std::to_string(_forward.total()) + " forward runs";
  }

  Outcome answer(const std::vector<double>& theta) override
  {
    Outcome out;
    out.theta = theta;
    out.residuals.resize(_fit.residuals());
    const double* blocks[] = {theta.data()};
    if (!_cost.Evaluate(blocks, out.residuals.data(), nullptr))
      throw std::runtime_error("the forward run at the fitted values failed");
    out.best_run = _cost.last_run;
    out.model = model_values(_fit, out.best_run);
    return out;
  }

  void finish(Outcome& outcome, std::chrono::steady_clock::time_point) override
  {
    outcome.forward_runs = _forward.total();
    outcome.reused = _forward.reusable();
  }

private:
  const Fit& _fit;
  const Options& _options;
  Forward _forward;
  Cost _cost;
};

} // namespace

std::unique_ptr<Model> forward_runs(const Fit& fit, const Options& options)
{
  return std::make_unique<ForwardRuns>(fit, options);
}

} // namespace nct::fit
