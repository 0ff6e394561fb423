// A fit's results (cpp/fit/results.h).
#include "fit/results.h"

#include <cmath>
#include <iostream>

#include <nlohmann/json.hpp>

#include "io/format.h"
#include "io/output.h"
#include "io/text.h"
#include "io/toml_input.h"
#include "jobs/jobs.h"
#include "scene/scene.h"

namespace nct::fit
{
namespace fs = std::filesystem;
using io::format;
using io::nan;

Progress::Progress(const Fit& fit, const Forward* forward, const Cost* cost, const double* theta,
                   const fs::path& out)
    : _fit(fit), _forward(forward), _cost(cost), _theta(theta), _out(out),
      _start(std::chrono::steady_clock::now())
{
  _csv << "iteration,cost,step_norm,trust_radius,accepted";
  for (auto& p : fit.parameters)
    _csv << "," << p.label;
  _csv << ",forward_runs,wall_s\n";
}

ceres::CallbackReturnType Progress::operator()(const ceres::IterationSummary& s)
{
  if (jobs::interrupted())
    return ceres::SOLVER_ABORT;
  const double wall
      = std::chrono::duration<double>(std::chrono::steady_clock::now() - _start).count();
  std::string line = format("iteration %2d of at most %d  cost %.6e  ", s.iteration,
                            _fit.max_iterations, s.cost);
  _csv << s.iteration << "," << io::literal(s.cost) << "," << io::literal(s.step_norm) << ","
       << io::literal(s.trust_region_radius) << "," << (s.step_is_successful ? 1 : 0);
  for (std::size_t i = 0; i < _fit.parameters.size(); ++i)
  {
    const double v = _fit.parameters[i].value(_theta[i]);
    line += format("%s %.6g  ", _fit.parameters[i].label.c_str(), v);
    _csv << "," << io::literal(v);
  }
  const int runs = _forward ? _forward->total() : 0;
  _csv << "," << runs << "," << format("%.3f", wall) << "\n";
  line += format("step %.2e %s  ", s.step_norm,
                 s.iteration == 0 ? "start" : s.step_is_successful ? "taken" : "refused");
  if (_forward)
    line += format("runs %d (%d reused)  ", runs, _forward->reusable());
  line += format(wall < 10 ? "%.2f s" : "%.0f s", wall);
  // What the Jacobian's finite differences fell back to since the last line.
  if (_cost)
  {
    for (const auto& note : _cost->notes)
      line += "; " + note;
    fallbacks.insert(fallbacks.end(), _cost->notes.begin(), _cost->notes.end());
    _cost->notes.clear();
  }
  std::cout << line << std::endl;
  io::write_atomic(_out / "iterations.csv", _csv.str());
  return ceres::SOLVER_CONTINUE;
}

namespace
{

/// A JSON number, or null for NaN and infinities (JSON has neither).
nlohmann::json json_number(double x)
{
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json();
}

/// Per parameter: start, value, standard error, 95 % interval, bounds,
/// prior; warnings for one that ends at a bound.
nlohmann::json describe_parameters(const Fit& fit, const Outcome& o,
                                   std::vector<std::string>& warnings)
{
  const std::vector<double>& theta = o.theta;
  const std::vector<double>& covariance = o.covariance;
  const std::size_t n = fit.parameters.size();
  nlohmann::json parameters = nlohmann::json::array();
  for (std::size_t i = 0; i < n; ++i)
  {
    const Parameter& p = fit.parameters[i];
    const double v = p.value(theta[i]), se_theta = std::sqrt(covariance[i * n + i]);
    nlohmann::json j = {{"label", p.label}, {"keys", p.keys},   {"start", p.start},
                        {"value", v},       {"lower", p.lower}, {"upper", p.upper},
                        {"log", p.log}};
    // Standard error of the value (on a log scale by the delta method);
    // the 95 % interval on the fitted variable's scale.
    j["se"] = json_number(p.log ? v * se_theta : se_theta);
    j["ci95"] = {json_number(p.value(theta[i] - 1.959964 * se_theta)),
                 json_number(p.value(theta[i] + 1.959964 * se_theta))};
    if (!o.intervals.empty()) // the posterior's samples
    {
      j["se"] = json_number(o.se[i]);
      j["ci95"] = {json_number(o.intervals[i][0]), json_number(o.intervals[i][1])};
    }
    const double span = p.variable(p.upper) - p.variable(p.lower);
    j["at_bound"] = std::min(theta[i] - p.variable(p.lower), p.variable(p.upper) - theta[i])
                    < 1e-6 * span;
    if (j["at_bound"])
      warnings.push_back(p.label + " ended at a bound: widen it, or the data push it there "
                         + (o.intervals.empty() ? "(its interval does not hold)"
                                                : "(its interval is the posterior's, cut there)"));
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
           << io::literal(p.value(theta[i])) << "," << io::literal(p.prior_sd) << ","
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
            << format(out["wall_s"].get<double>() < 10 ? "%.2f s; chi2 %.4g for %d dof"
                                                       : "%.0f s; chi2 %.4g for %d dof",
                      out["wall_s"].get<double>(),
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
  std::cout << "fit.json, iterations.csv, observations.csv in " << folder.string() << std::endl;
}

/// fit.json's object: the fit, its outcome, the parameters, their
/// correlations, the observations' fit (its rows into `csv`) and warnings.
nlohmann::json answer(const Fit& fit, const Outcome& o, std::string& csv)
{
  const std::size_t n = fit.parameters.size(), m = o.residuals.size();
  nlohmann::json out;
  std::vector<std::string> warnings;
  if (!o.identifiable)
    warnings.push_back("the Jacobian is rank-deficient: the observations cannot determine every "
                       "parameter (no standard errors)");
  out["fit"] = fs::absolute(fit.file).string();
  if (fit.patient)
    out["patient"] = fit.patient->id;
  out["scene"] = fs::absolute(fit.scene).string();
  out["status"] = o.status;
  out["message"] = o.message;
  out["iterations"] = o.iterations;
  out["forward_runs"] = o.forward_runs;
  out["difference_fallbacks"] = o.fallbacks;
  out["forward_runs_reused"] = o.reused;
  out["cost"] = o.cost;
  double chi2 = o.chi2;
  if (std::isnan(chi2))
  {
    chi2 = 0;
    for (double x : o.residuals)
      chi2 += x * x;
  }
  out["chi2"] = chi2;
  out["residuals"] = m;
  out["dof"] = int(m) - int(n);
  out["reduced_chi2"] = m > n ? chi2 / double(m - n) : nan;
  out["parameters"] = describe_parameters(fit, o, warnings);
  out["correlation"] = correlation(fit, o.covariance, warnings);
  out["observations"] = describe_observations(fit, o.theta, o.residuals, o.model, csv);
  out["warnings"] = warnings;
  out["best_run"] = o.best_run.empty() ? nlohmann::json() : nlohmann::json(fs::absolute(o.best_run).string());
  std::string command = "nct run " + fs::absolute(fit.scene).string();
  for (auto& s : o.sets)
    if (s != "output.fields=false")
      command += " --set " + s;
  out["command"] = command;
  out["wall_s"] = o.wall_s;
  out.update(o.extra);
  return out;
}

} // namespace

void report_answer(const Fit& fit, const Outcome& outcome, const fs::path& folder)
{
  std::string csv;
  const nlohmann::json out = answer(fit, outcome, csv);
  io::write_atomic(folder / "observations.csv", csv);
  io::write_atomic(folder / "fit.json", out.dump(2) + "\n");
  print_answer(out, folder);
}

void claim_folder(const Fit& fit, const std::filesystem::path& out, const char* what)
{
  std::filesystem::create_directories(out);
  if (std::filesystem::exists(out / "fit.toml")
      && io::read_text(out / "fit.toml") != io::read_text(fit.file))
    throw scene::Error(fit.file.string() + ": " + out.string() + " holds another " + what
                       + " (its fit.toml differs); give a new --out or remove it");
}

} // namespace nct::fit
