// Running a fit (cpp/fit/fit.h): the forward runs, the residuals, the
// Levenberg-Marquardt iterations (Ceres) and the answer's uncertainty.
#include "fit/fit.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <map>
#include <set>
#include <sstream>

#include <ceres/ceres.h>
#include <glog/logging.h>
#include <nlohmann/json.hpp>

#include "io/format.h"
#include "io/output.h"
#include "io/toml_input.h"
#include "jobs/jobs.h"
#include "jobs/launcher_input.h"
#include "jobs/run_cache.h"
#include "scene/scene.h"

namespace nct::fit
{
namespace fs = std::filesystem;
using io::format;
using io::nan;

namespace
{

/// A fitted parameter's value from its fitted variable, and back: on a
/// log scale the variable is log(value / start), so that the start's
/// value is exact (0.05, not 0.05000000000000001).
double value(const Parameter& p, double theta) { return p.log ? p.start * std::exp(theta) : theta; }
double variable(const Parameter& p, double v) { return p.log ? std::log(v / p.start) : v; }

/// A column of a CSV table with a header, by name.
std::map<std::string, std::vector<double>> read_table(const fs::path& file,
                                                      const std::vector<std::string>& wanted)
{
  std::istringstream in(jobs::read_text(file));
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  {
    std::istringstream h(line);
    for (std::string c; std::getline(h, c, ',');)
      names.push_back(c);
  }
  std::map<std::string, std::vector<double>> out;
  std::vector<int> index;
  for (auto& w : wanted)
  {
    auto it = std::find(names.begin(), names.end(), w);
    if (it == names.end())
      throw std::runtime_error(file.string() + " has no column " + w);
    index.push_back(int(it - names.begin()));
    out[w];
  }
  while (std::getline(in, line))
  {
    std::vector<std::string> cells;
    std::istringstream row(line);
    for (std::string c; std::getline(row, c, ',');)
      cells.push_back(c);
    for (std::size_t k = 0; k < wanted.size(); ++k)
    {
      const auto i = std::size_t(index[k]);
      out[wanted[k]].push_back(i < cells.size() && !cells[i].empty() && cells[i] != "nan"
                                   ? std::stod(cells[i]) // non-numeric cells: profiles' surface
                                   : nan);
    }
  }
  return out;
}

/// Linear interpolation of y(x) on ascending x; NaN outside, beyond 1e-3
/// (ms or mm: the rounding of measured data in a CSV).
double interpolate(const std::vector<double>& x, const std::vector<double>& y, double at)
{
  if (x.empty())
    return nan;
  const double slack = 1e-3;
  if (at < x.front() - slack || at > x.back() + slack)
    return nan;
  at = std::clamp(at, x.front(), x.back());
  auto hi = std::lower_bound(x.begin(), x.end(), at);
  const std::size_t j = std::size_t(hi - x.begin());
  if (j == 0)
    return y[0];
  const double w = (at - x[j - 1]) / (x[j] - x[j - 1]);
  return (1 - w) * y[j - 1] + w * y[j];
}

/// A run's corneal profiles: per frame, the surface's x (ascending) and y.
struct Profiles
{
  std::vector<double> t;
  std::map<std::string, std::vector<std::pair<std::vector<double>, std::vector<double>>>> surface;
};

Profiles read_profiles(const fs::path& file)
{
  std::istringstream in(jobs::read_text(file));
  std::string line;
  std::getline(in, line);
  if (line != "frame,t_ms,surface,x_mm,y_mm")
    throw std::runtime_error(file.string() + ": unexpected header " + line);
  Profiles p;
  while (std::getline(in, line))
  {
    std::istringstream row(line);
    std::string frame, t, surface, x, y;
    std::getline(row, frame, ',');
    std::getline(row, t, ',');
    std::getline(row, surface, ',');
    std::getline(row, x, ',');
    std::getline(row, y, ',');
    const std::size_t f = std::stoul(frame);
    if (f >= p.t.size())
      p.t.resize(f + 1, std::stod(t));
    auto& frames = p.surface[surface];
    frames.resize(p.t.size());
    frames[f].first.push_back(std::stod(x));
    frames[f].second.push_back(std::stod(y));
  }
  for (auto& [name, frames] : p.surface)
    for (auto& [x, y] : frames)
    {
      std::vector<std::size_t> order(x.size());
      for (std::size_t i = 0; i < order.size(); ++i)
        order[i] = i;
      std::sort(order.begin(), order.end(), [&](auto a, auto b) { return x[a] < x[b]; });
      std::vector<double> xs, ys;
      for (auto i : order)
        xs.push_back(x[i]), ys.push_back(y[i]);
      x = xs, y = ys;
    }
  return p;
}

/// The model's value at each observation point of a converged run;
/// throws scene::Error when an observation lies outside what it computed.
std::vector<double> model_values(const Fit& fit, const fs::path& run)
{
  std::vector<double> out;
  const auto summary = nlohmann::json::parse(jobs::read_text(run / "summary.json"));
  std::map<std::string, std::vector<double>> frames;
  std::unique_ptr<Profiles> profiles;
  for (std::size_t k = 0; k < fit.observations.size(); ++k)
  {
    const Observation& o = fit.observations[k];
    const std::string where = fit.file.string() + ": observation[" + std::to_string(k + 1)
                              + "] (" + o.label + "): ";
    if (o.kind == Kind::biomarker)
    {
      if (!summary.contains(o.quantity) || !summary[o.quantity].is_number())
        throw scene::Error(where + "the run " + run.string() + " gives no " + o.quantity
                           + " (the puff did not reach it: e.g. no second applanation)");
      out.push_back(summary[o.quantity].get<double>());
    }
    else if (o.kind == Kind::curve)
    {
      if (frames.empty())
        frames = read_table(run / "frames.csv", {"t_ms", "apex_displacement_mm",
                                                 "whole_eye_motion_mm"});
      for (double t : o.t)
      {
        out.push_back(interpolate(frames["t_ms"], frames[o.quantity], t));
        if (std::isnan(out.back()))
          throw scene::Error(where + format("t = %g ms is outside the run's frames [%g, %g] ms",
                                            t, frames["t_ms"].front(), frames["t_ms"].back()));
      }
    }
    else
    {
      if (!profiles)
        profiles = std::make_unique<Profiles>(read_profiles(run / "profiles.csv"));
      const auto& frames_ = profiles->surface.at(o.quantity);
      const auto& ts = profiles->t;
      for (std::size_t i = 0; i < o.t.size(); ++i)
      {
        auto y_at = [&](std::size_t f)
        {
          const double y = interpolate(frames_[f].first, frames_[f].second, o.x[i]);
          if (std::isnan(y))
            throw scene::Error(where + format("x = %g mm is outside the model's %s profile "
                                              "[%g, %g] mm",
                                              o.x[i], o.quantity.c_str(),
                                              frames_[f].first.front(),
                                              frames_[f].first.back()));
          return o.relative ? y - interpolate(frames_[0].first, frames_[0].second, o.x[i]) : y;
        };
        auto hi = std::lower_bound(ts.begin(), ts.end(), o.t[i] - 1e-3);
        if (hi == ts.end())
          throw scene::Error(where + format("t = %g ms is after the run's last frame", o.t[i]));
        const std::size_t j = std::size_t(hi - ts.begin());
        if (j == 0)
          out.push_back(y_at(0));
        else
        {
          const double w = std::clamp((o.t[i] - ts[j - 1]) / (ts[j] - ts[j - 1]), 0.0, 1.0);
          out.push_back((1 - w) * y_at(j - 1) + w * y_at(j));
        }
      }
    }
  }
  return out;
}

/// The forward runs of a fit, each in out/runs/run-NNNN, found again by
/// their overrides: a resumed fit reads the runs it had finished.
class Forward
{
public:
  Forward(const Fit& fit, const Options& options, jobs::Launcher launcher)
      : _fit(fit), _options(options), _launcher(std::move(launcher)),
        _runs(options.out / "runs", "run.json", "summary.json")
  {
    // A run a driver killed before it left on a cluster's queue is followed;
    // an interrupted one runs again when needed.
    const std::set<std::string> followed = _runs.clean(_launcher);
    for (const std::string& name : _runs.names())
    {
      const auto sets = _runs.recorded(name).at("sets").get<std::vector<std::string>>();
      (followed.count(name) ? _pending : _cache)[sets] = name;
      _next = std::max(_next, std::stoi(name.substr(4)) + 1);
    }
    _reusable = int(_cache.size());
  }

  /// The overrides of a forward run at the fitted variables theta.
  std::vector<std::string> sets(const std::vector<double>& theta) const
  {
    std::vector<std::string> out = {"output.fields=false"};
    out.insert(out.end(), _fit.sets.begin(), _fit.sets.end());
    for (std::size_t i = 0; i < theta.size(); ++i)
      for (auto& k : _fit.parameters[i].keys)
        out.push_back(k + "=" + io::literal(value(_fit.parameters[i], theta[i])));
    return out;
  }

  /// The run folders at these points (run the missing ones, jobs at a
  /// time); an empty path for a run that failed. Throws Interrupted.
  std::vector<fs::path> runs(const std::vector<std::vector<double>>& points)
  {
    std::vector<std::vector<std::string>> wanted, todo_sets;
    std::vector<jobs::Job> todo;
    std::vector<std::string> todo_names;
    for (auto& p : points)
    {
      auto s = sets(p);
      wanted.push_back(s);
      if (_cache.count(s) || std::count(todo_sets.begin(), todo_sets.end(), s))
        continue;
      auto pending = _pending.find(s);
      const std::string name
          = pending != _pending.end() ? pending->second : format("run-%04d", _next++);
      if (pending != _pending.end())
        _pending.erase(pending);
      todo_sets.push_back(s);
      todo_names.push_back(name);
      todo.push_back(_runs.nct_run(name, _options.program, _fit.scene, s, _fit.ranks,
                                   _fit.mpiexec));
    }
    const int at_once = _options.jobs > 0 ? _options.jobs : _fit.jobs;
    const bool complete = jobs::run(_launcher, todo, at_once, [](std::size_t, int) {});
    if (!complete)
      throw Interrupted();
    for (std::size_t i = 0; i < todo.size(); ++i)
      if (_runs.finished(todo_names[i]))
      {
        _cache[todo_sets[i]] = todo_names[i];
        ++_done;
      }
      else
        std::cerr << "fit: forward run " << todo_names[i] << " stopped without a summary; "
                  << (_runs.path(todo_names[i]) / "console.log").string() << " ends:\n"
                  << jobs::tail(jobs::read_text(_runs.path(todo_names[i]) / "console.log"), 4);
    std::vector<fs::path> out;
    for (auto& s : wanted)
    {
      auto it = _cache.find(s);
      const bool ok = it != _cache.end()
                      && nlohmann::json::parse(
                             jobs::read_text(_runs.path(it->second) / "summary.json"))
                                 .value("status", "")
                             == "converged";
      out.push_back(ok ? _runs.path(it->second) : fs::path());
    }
    return out;
  }

  int done() const { return _done; }          ///< runs finished by this process
  int reusable() const { return _reusable; }  ///< runs found on disk at the start
  int total() const { return int(_cache.size()); }

  struct Interrupted
  {
  };

private:
  const Fit& _fit;
  const Options& _options;
  jobs::Launcher _launcher;
  jobs::RunCache _runs;
  /// Finished runs by their overrides: their names.
  std::map<std::vector<std::string>, std::string> _cache;
  /// Runs still on a cluster's queue from a driver that was killed.
  std::map<std::vector<std::string>, std::string> _pending;
  int _next = 1, _done = 0, _reusable = 0;
};

/// The weighted residuals (model - measured) / sd of the observations
/// (model values given), then the priors' (value - mean) / sd.
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
      r.push_back((value(p, theta[i]) - p.prior_mean) / p.prior_sd);
  return r;
}

/// The fit's residuals for Ceres: each evaluation one batch of forward
/// runs (the point, and with the Jacobian its finite-difference
/// neighbours, in parallel).
class Cost : public ceres::CostFunction
{
public:
  /// `at_once`: forward runs at once; when a point and its neighbours fit
  /// in one batch, a point's residuals come with its neighbours' runs
  /// (the Jacobian, if the step is taken, then costs no wait).
  Cost(const Fit& fit, Forward& forward, int at_once)
      : _fit(fit), _forward(forward),
        _speculate(int(fit.parameters.size()) * (fit.central ? 2 : 1) + 1 <= at_once)
  {
    set_num_residuals(int(fit.residuals()));
    mutable_parameter_block_sizes()->push_back(int(fit.parameters.size()));
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override
  {
    const std::size_t n = _fit.parameters.size(), m = _fit.residuals();
    const std::vector<double> theta(parameters[0], parameters[0] + n);
    std::vector<std::vector<double>> points = {theta};
    const bool jacobian = jacobians && jacobians[0];
    std::vector<std::array<double, 2>> pairs(n); // each parameter's two points
    if (jacobian || _speculate)
      for (std::size_t i = 0; i < n; ++i)
      {
        // Two points per parameter: theta + h and theta (forward) or
        // theta - h (central); one-sided backwards at the upper bound,
        // forwards at the lower.
        const Parameter& p = _fit.parameters[i];
        const double h = step(i, theta);
        double a = theta[i] + h, b = _fit.central ? theta[i] - h : theta[i];
        if (a > variable(p, p.upper))
          a = theta[i], b = theta[i] - h;
        else if (b < variable(p, p.lower))
          b = theta[i];
        pairs[i] = {a, b};
        for (double x : {a, b})
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

  /// What the last Jacobian's differences fell back to, for the progress
  /// line (taken by it).
  mutable std::vector<std::string> notes;
  mutable fs::path last_run; ///< the run of the last point evaluated

private:
  /// Parameter i's finite-difference step at theta: relative on a log
  /// scale, else relative to the value (or to the bounds' span near 0).
  double step(std::size_t i, const std::vector<double>& theta) const
  {
    const Parameter& p = _fit.parameters[i];
    return _fit.step * (p.log ? 1.0 : std::max(std::abs(theta[i]), 1e-3 * (p.upper - p.lower)));
  }
  static std::vector<double> moved(std::vector<double> theta, std::size_t i, double x)
  {
    theta[i] = x;
    return theta;
  }
  /// A neighbour of parameter i did not converge: the difference on the
  /// other side of theta, else a quarter of the step on either side (a
  /// one-sided difference with theta's run, `run0`). True with the points
  /// (a, b) and their runs of the first that converged; each try noted.
  bool fall_back(std::size_t i, const std::vector<double>& theta, const fs::path& run0,
                 double& a, double& b, fs::path& run_a, fs::path& run_b) const
  {
    const Parameter& p = _fit.parameters[i];
    const double h = step(i, theta), lo = variable(p, p.lower), hi = variable(p, p.upper);
    const std::string failed = run_a.empty() && run_b.empty() ? "both neighbours"
                               : run_a.empty() ? format("the run at %.6g", value(p, a))
                                               : format("the run at %.6g", value(p, b));
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

  const Fit& _fit;
  Forward& _forward;
  bool _speculate;
};

/// A progress line and a row of iterations.csv per iteration; stops the
/// solver when interrupted.
class Progress : public ceres::IterationCallback
{
public:
  Progress(const Fit& fit, const Forward& forward, const Cost& cost, const double* theta,
           const fs::path& out)
      : _fit(fit), _forward(forward), _cost(cost), _theta(theta), _out(out),
        _start(std::chrono::steady_clock::now())
  {
    _csv << "iteration,cost,step_norm,trust_radius,accepted";
    for (auto& p : fit.parameters)
      _csv << "," << p.label;
    _csv << ",forward_runs,wall_s\n";
  }

  ceres::CallbackReturnType operator()(const ceres::IterationSummary& s) override
  {
    if (jobs::interrupted())
      return ceres::SOLVER_ABORT;
    const double wall
        = std::chrono::duration<double>(std::chrono::steady_clock::now() - _start).count();
    std::string line = format("iteration %2d  cost %.6e  ", s.iteration, s.cost);
    _csv << s.iteration << "," << io::literal(s.cost) << "," << io::literal(s.step_norm) << ","
         << io::literal(s.trust_region_radius) << "," << (s.step_is_successful ? 1 : 0);
    for (std::size_t i = 0; i < _fit.parameters.size(); ++i)
    {
      const double v = value(_fit.parameters[i], _theta[i]);
      line += format("%s %.6g  ", _fit.parameters[i].label.c_str(), v);
      _csv << "," << io::literal(v);
    }
    _csv << "," << _forward.total() << "," << format("%.1f", wall) << "\n";
    line += format("step %.2e %s  runs %d (%d reused)  %.0f s", s.step_norm,
                   s.iteration == 0 ? "start" : s.step_is_successful ? "taken" : "refused",
                   _forward.total(), _forward.reusable(), wall);
    // What the Jacobian's finite differences fell back to since the last line.
    for (const auto& note : _cost.notes)
      line += "; " + note;
    fallbacks.insert(fallbacks.end(), _cost.notes.begin(), _cost.notes.end());
    _cost.notes.clear();
    std::cout << line << std::endl;
    io::write_atomic(_out / "iterations.csv", _csv.str());
    return ceres::SOLVER_CONTINUE;
  }

  /// Every fallback of the differences so far.
  std::vector<std::string> fallbacks;

private:
  const Fit& _fit;
  const Forward& _forward;
  const Cost& _cost;
  const double* _theta;
  fs::path _out;
  std::chrono::steady_clock::time_point _start;
  std::ostringstream _csv;
};

/// Per parameter: start, value, standard error, 95 % interval, bounds,
/// prior; warnings for one that ends at a bound.
nlohmann::json describe_parameters(const Fit& fit, const std::vector<double>& theta,
                                   const std::vector<double>& covariance,
                                   std::vector<std::string>& warnings)
{
  const std::size_t n = fit.parameters.size();
  auto number = [](double x) { return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(); };
  nlohmann::json parameters = nlohmann::json::array();
  for (std::size_t i = 0; i < n; ++i)
  {
    const Parameter& p = fit.parameters[i];
    const double v = value(p, theta[i]), se_theta = std::sqrt(covariance[i * n + i]);
    nlohmann::json j = {{"label", p.label}, {"keys", p.keys},   {"start", p.start},
                        {"value", v},       {"lower", p.lower}, {"upper", p.upper},
                        {"log", p.log}};
    // Standard error of the value (on a log scale by the delta method);
    // the 95 % interval on the fitted variable's scale.
    j["se"] = number(p.log ? v * se_theta : se_theta);
    j["ci95"] = {number(value(p, theta[i] - 1.959964 * se_theta)),
                 number(value(p, theta[i] + 1.959964 * se_theta))};
    const double span = variable(p, p.upper) - variable(p, p.lower);
    j["at_bound"] = std::min(theta[i] - variable(p, p.lower), variable(p, p.upper) - theta[i])
                    < 1e-6 * span;
    if (j["at_bound"])
      warnings.push_back(p.label + " ended at a bound: widen it, or the data push it there "
                         "(its interval does not hold)");
    if (p.prior)
      j["prior"] = {{"mean", p.prior_mean}, {"sd", p.prior_sd}};
    parameters.push_back(j);
  }
  return parameters;
}

/// The parameters' correlation matrix (null where unknown); a warning for
/// every pair beyond |0.95|.
nlohmann::json correlation(const Fit& fit, const std::vector<double>& covariance,
                           std::vector<std::string>& warnings)
{
  const std::size_t n = fit.parameters.size();
  nlohmann::json correlation = nlohmann::json::array();
  for (std::size_t i = 0; i < n; ++i)
  {
    nlohmann::json row = nlohmann::json::array();
    for (std::size_t j = 0; j < n; ++j)
    {
      const double c = covariance[i * n + j]
                       / std::sqrt(covariance[i * n + i] * covariance[j * n + j]);
      row.push_back(std::isfinite(c) ? nlohmann::json(c) : nlohmann::json());
      if (j > i && std::abs(c) > 0.95)
        warnings.push_back(format("%s and %s correlate at %.3f: the data cannot separate them",
                                  fit.parameters[i].label.c_str(),
                                  fit.parameters[j].label.c_str(), c));
    }
    correlation.push_back(row);
  }
  return correlation;
}

/// Each observation's fit (its weighted RMS residual; a biomarker's
/// values), and every measured point and prior as a row of `csv`.
nlohmann::json describe_observations(const Fit& fit, const std::vector<double>& theta,
                                     const std::vector<double>& r,
                                     const std::vector<double>& model, std::string& csv)
{
  std::ostringstream rows;
  rows << "observation,kind,t_ms,x_mm,measured,model,sd,residual\n";
  nlohmann::json observations = nlohmann::json::array();
  std::size_t j = 0;
  static const char* kinds[] = {"biomarker", "curve", "profile"};
  auto literal_or_blank = [](double x) { return std::isnan(x) ? std::string() : io::literal(x); };
  for (auto& ob : fit.observations)
  {
    double sum2 = 0;
    for (std::size_t i = 0; i < ob.value.size(); ++i, ++j)
    {
      sum2 += r[j] * r[j];
      rows << ob.label << "," << kinds[int(ob.kind)] << "," << literal_or_blank(ob.t[i]) << ","
           << literal_or_blank(ob.x[i]) << "," << io::literal(ob.value[i]) << ","
           << io::literal(model[j]) << "," << io::literal(ob.sd[i]) << "," << io::literal(r[j])
           << "\n";
    }
    nlohmann::json e = {{"label", ob.label}, {"kind", kinds[int(ob.kind)]},
                        {"quantity", ob.quantity}, {"points", ob.value.size()},
                        {"rms_weighted_residual", std::sqrt(sum2 / double(ob.value.size()))}};
    if (ob.kind == Kind::biomarker)
      e.update({{"measured", ob.value[0]}, {"model", model[j - 1]}, {"sd", ob.sd[0]},
                {"residual", r[j - 1]}});
    else
      e["file"] = fs::absolute(ob.file).string();
    if (ob.kind == Kind::profile)
      e["reference"] = ob.relative ? "rest" : "absolute";
    observations.push_back(e);
  }
  for (std::size_t i = 0; i < fit.parameters.size(); ++i)
    if (const auto& p = fit.parameters[i]; p.prior)
      rows << "prior_" << p.label << ",prior,,," << io::literal(p.prior_mean) << ","
           << io::literal(value(p, theta[i])) << "," << io::literal(p.prior_sd) << ","
           << io::literal(r[j++]) << "\n";
  csv = rows.str();
  return observations;
}

/// The answer's summary on stdout.
void print_answer(const nlohmann::json& out, const fs::path& folder)
{
  std::cout << "\nfit: " << out["status"].get<std::string>() << " after "
            << out["iterations"].get<int>() << " iterations, " << out["forward_runs"].get<int>()
            << " forward runs (" << out["forward_runs_reused"].get<int>() << " reused), "
            << format("%.0f s; chi2 %.4g for %d dof", out["wall_s"].get<double>(),
                      out["chi2"].get<double>(), out["dof"].get<int>())
            << "\n";
  auto bound = [](const nlohmann::json& x)
  { return x.is_null() ? std::string("?") : format("%.4g", x.get<double>()); };
  for (auto& p : out["parameters"])
    std::cout << format("  %-16s %.6g  95%% [%s, %s]\n", p["label"].get<std::string>().c_str(),
                        p["value"].get<double>(), bound(p["ci95"][0]).c_str(),
                        bound(p["ci95"][1]).c_str());
  for (auto& w : out["warnings"])
    std::cout << "  warning: " << w.get<std::string>() << "\n";
  std::cout << "fit.json, iterations.csv, observations.csv in " << folder.string()
            << "; plots: /usr/bin/python3 scripts/plot-fit.py " << folder.string() << std::endl;
}

} // namespace

int run(const Fit& fit, const Options& o)
{
  const auto start = std::chrono::steady_clock::now();
  const std::size_t n = fit.parameters.size(), m = fit.residuals();
  fs::create_directories(o.out);
  if (fs::exists(o.out / "fit.toml")
      && jobs::read_text(o.out / "fit.toml") != jobs::read_text(fit.file))
    throw scene::Error(fit.file.string() + ": " + o.out.string() + " holds another fit (its "
                       "fit.toml differs); give a new --out or remove it");
  jobs::catch_interrupts();
  // Slurm must take the options before anything runs or is submitted.
  Forward forward(fit, o, jobs::launcher_for(fit.launcher, o.launcher, o.out, fit.ranks, "fit",
                                             fit.file));
  std::vector<double> theta(n);
  for (std::size_t i = 0; i < n; ++i)
    theta[i] = variable(fit.parameters[i], fit.parameters[i].start);

  // The start's scene must pass nct check (the eye's geometry...) before
  // any run.
  {
    const fs::path log = o.out / "check.log";
    int code = 0;
    jobs::run({{jobs::nct_command(o.program, "check", fit.scene, forward.sets(theta), {}), log, 1,
                fit.mpiexec, nullptr}},
              1, [&](std::size_t, int c) { code = c; });
    if (jobs::interrupted())
      return 130;
    if (code != 0)
    {
      std::string why = jobs::tail(jobs::read_text(log), 3);
      throw scene::Error(fit.file.string() + ": the start's scene: " + why);
    }
    fs::remove(log);
  }
  std::cout << "fit " << fit.file.string()
            << (fit.patient ? " (patient " + fit.patient->id + ")" : std::string()) << ": " << n << " parameter(s), " << m
            << " weighted residual(s) from " << fit.observations.size() << " observation(s), "
            << (o.jobs > 0 ? o.jobs : fit.jobs) << " run(s) at once on " << fit.ranks
            << " rank(s) each -> " << o.out.string() << " (" << forward.reusable()
            << " forward runs on disk)" << std::endl;
  if (o.dry_run)
  {
    std::cout << "fit: the fit file and the start's scene check out; nothing run (--dry-run)"
              << std::endl;
    return 0;
  }
  io::write_atomic(o.out / "fit.toml", jobs::read_text(fit.file));

  // Ceres' own log (glog) only for fatal errors: the fit reports itself.
  FLAGS_minloglevel = 3;
  FLAGS_logtostderr = true;
  ceres::Problem::Options problem_options;
  problem_options.cost_function_ownership = ceres::DO_NOT_TAKE_OWNERSHIP;
  ceres::Problem problem(problem_options);
  Cost cost(fit, forward, o.jobs > 0 ? o.jobs : fit.jobs);
  problem.AddResidualBlock(&cost, nullptr, theta.data());
  for (std::size_t i = 0; i < n; ++i)
  {
    const Parameter& p = fit.parameters[i];
    problem.SetParameterLowerBound(theta.data(), int(i), variable(p, p.lower));
    problem.SetParameterUpperBound(theta.data(), int(i), variable(p, p.upper));
  }
  ceres::Solver::Options options;
  options.minimizer_type = ceres::TRUST_REGION;
  options.trust_region_strategy_type = ceres::LEVENBERG_MARQUARDT;
  options.linear_solver_type = ceres::DENSE_QR;
  options.max_num_iterations = fit.max_iterations;
  options.function_tolerance = fit.tolerance;
  options.parameter_tolerance = fit.tolerance;
  options.gradient_tolerance = 1e-10;
  options.num_threads = 1;
  options.logging_type = ceres::SILENT;
  options.update_state_every_iteration = true;
  Progress progress(fit, forward, cost, theta.data(), o.out);
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

  // The answer at the final point: residuals, covariance, correlations.
  std::vector<double> r(m);
  {
    const double* blocks[] = {theta.data()};
    if (!cost.Evaluate(blocks, r.data(), nullptr))
      throw std::runtime_error("the forward run at the fitted values failed");
  }
  const fs::path best = cost.last_run;
  const std::vector<double> model = model_values(fit, best);
  std::vector<double> covariance(n * n, nan);
  ceres::Covariance::Options covariance_options;
  covariance_options.algorithm_type = ceres::DENSE_SVD;
  covariance_options.num_threads = 1;
  ceres::Covariance cov(covariance_options);
  const bool identifiable
      = cov.Compute(std::vector<std::pair<const double*, const double*>>{
                        {theta.data(), theta.data()}},
                    &problem)
        && cov.GetCovarianceBlock(theta.data(), theta.data(), covariance.data());
  if (!identifiable)
    std::fill(covariance.begin(), covariance.end(), nan);

  nlohmann::json out;
  std::vector<std::string> warnings;
  if (!identifiable)
    warnings.push_back("the Jacobian is rank-deficient: the observations cannot determine every "
                       "parameter (no standard errors)");
  out["fit"] = fs::absolute(fit.file).string();
  if (fit.patient)
    out["patient"] = fit.patient->id;
  out["scene"] = fs::absolute(fit.scene).string();
  out["status"] = summary.termination_type == ceres::CONVERGENCE ? "converged"
                                                                 : "max_iterations";
  out["message"] = summary.message;
  out["iterations"] = summary.iterations.size() - 1;
  out["forward_runs"] = forward.total();
  out["difference_fallbacks"] = progress.fallbacks;
  out["forward_runs_reused"] = forward.reusable();
  out["cost"] = summary.final_cost;
  double chi2 = 0;
  for (double x : r)
    chi2 += x * x;
  out["chi2"] = chi2;
  out["residuals"] = m;
  out["dof"] = int(m) - int(n);
  out["reduced_chi2"] = m > n ? chi2 / double(m - n) : nan;
  out["parameters"] = describe_parameters(fit, theta, covariance, warnings);
  out["correlation"] = correlation(fit, covariance, warnings);

  std::string csv;
  out["observations"] = describe_observations(fit, theta, r, model, csv);
  out["warnings"] = warnings;
  out["best_run"] = fs::absolute(best).string();
  std::string command = "nct run " + fs::absolute(fit.scene).string();
  for (auto& s : forward.sets(theta))
    if (s != "output.fields=false")
      command += " --set " + s;
  out["command"] = command;
  out["wall_s"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  io::write_atomic(o.out / "observations.csv", csv);
  io::write_atomic(o.out / "fit.json", out.dump(2) + "\n");

  print_answer(out, o.out);
  return summary.termination_type == ceres::CONVERGENCE ? 0 : 3;
}

} // namespace nct::fit
