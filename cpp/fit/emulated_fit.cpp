// The fit's forward model of an emulator (fit/model.h): its likelihood
// (fit/emulated.h) for the minimiser, the posterior by MCMC where the
// Laplace interval does not hold, the confirming forward run at the answer
// and the corrected fit where it disagrees.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <limits>
#include <random>
#include <sstream>

#include <ceres/ceres.h>
#include <nlohmann/json.hpp>

#include "fit/emulated.h"
#include "fit/forward.h"
#include "fit/mcmc.h"
#include "fit/model.h"
#include "fit/readings.h"
#include "fit/results.h"
#include "io/format.h"
#include "io/output.h"
#include "io/text.h"
#include "jobs/launcher_input.h"

namespace nct::fit
{
namespace fs = std::filesystem;
using io::format;

namespace
{

/// The likelihood's residuals for Ceres, with their exact Jacobian.
class EmulatedCost : public ceres::CostFunction
{
public:
  explicit EmulatedCost(const EmulatedLikelihood& l, std::size_t n) : _l(l)
  {
    set_num_residuals(int(l.residuals()));
    mutable_parameter_block_sizes()->push_back(int(n));
  }

  bool Evaluate(double const* const* parameters, double* residuals,
                double** jacobians) const override
  {
    const std::size_t n = std::size_t(parameter_block_sizes()[0]);
    const std::vector<double> theta(parameters[0], parameters[0] + n);
    const bool jacobian = jacobians && jacobians[0];
    const auto e = _l.evaluate(theta, jacobian);
    if (!e.r.allFinite() || (jacobian && !e.jacobian.allFinite()))
      return false;
    Eigen::Map<Eigen::VectorXd>(residuals, e.r.size()) = e.r;
    if (jacobian) // Ceres: row-major
      Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor>>(
          jacobians[0], e.jacobian.rows(), e.jacobian.cols())
          = e.jacobian;
    return true;
  }

private:
  const EmulatedLikelihood& _l;
};

/// The variables at a bound (within 1e-9 of the bounds' span) whose
/// cost's gradient points out of the box.
std::vector<int> pushed_to_bounds(const Fit& fit, const EmulatedLikelihood& l,
                                  const std::vector<double>& theta)
{
  const auto e = l.evaluate(theta, true);
  const Eigen::VectorXd g = e.jacobian.transpose() * e.r;
  std::vector<int> held;
  for (std::size_t i = 0; i < theta.size(); ++i)
  {
    const Parameter& p = fit.parameters[i];
    const double lo = p.variable(p.lower), hi = p.variable(p.upper), tol = 1e-9 * (hi - lo);
    if ((theta[i] <= lo + tol && g(Eigen::Index(i)) > 0)
        || (theta[i] >= hi - tol && g(Eigen::Index(i)) < 0))
      held.push_back(int(i));
  }
  return held;
}

/// The largest |correlation| of a covariance (NaN when unknown).
double largest_correlation(const std::vector<double>& c, std::size_t n)
{
  double most = 0;
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = i + 1; j < n; ++j)
      most = std::max(most, std::abs(c[i * n + j] / std::sqrt(c[i * n + i] * c[j * n + j])));
  return most;
}

/// The posterior by the ensemble sampler, its walkers started about the
/// answer (the Laplace covariance's draws, or a hundredth of the bounds);
/// into the outcome: the intervals, SEs and covariance of the samples;
/// posterior.csv (every fifth step) into out.
nlohmann::json sample_posterior(const Fit& fit, const EmulatedLikelihood& l, Outcome& o,
                                const fs::path& out)
{
  const std::size_t n = o.theta.size();
  std::mt19937_64 rng{static_cast<std::uint64_t>(fit.seed) + 7};
  std::normal_distribution<double> normal;
  Eigen::MatrixXd chol = Eigen::MatrixXd::Zero(Eigen::Index(n), Eigen::Index(n));
  bool spread = o.identifiable;
  if (spread)
  {
    Eigen::Map<const Eigen::MatrixXd> c(o.covariance.data(), Eigen::Index(n), Eigen::Index(n));
    const Eigen::LLT<Eigen::MatrixXd> llt(c);
    spread = llt.info() == Eigen::Success && c.diagonal().minCoeff() > 0;
    if (spread)
      chol = llt.matrixL();
  }
  if (!spread) // a variable held at a bound, or none determined: a hundredth of the bounds
    for (std::size_t i = 0; i < n; ++i)
      chol(Eigen::Index(i), Eigen::Index(i)) = 0.01 * (fit.parameters[i].variable(
                                                           fit.parameters[i].upper)
                                                       - fit.parameters[i].variable(
                                                           fit.parameters[i].lower));
  auto log_p = [&](const std::vector<double>& t) { return l.log_posterior(t); };
  std::vector<std::vector<double>> start;
  for (int w = 0; w < fit.walkers; ++w)
    for (int tries = 0;; ++tries)
    {
      Eigen::VectorXd z(n);
      for (auto& zi : z)
        zi = normal(rng) * (tries < 50 ? 0.5 : 0.01);
      const Eigen::VectorXd d = chol * z;
      std::vector<double> t = o.theta;
      for (std::size_t i = 0; i < n; ++i)
        t[i] += d(Eigen::Index(i));
      if (std::isfinite(log_p(t)) || tries > 100)
      {
        start.push_back(std::isfinite(log_p(t)) ? t : o.theta);
        break;
      }
    }
  const int burn = fit.steps / 3;
  const Chain chain = sample(log_p, start, fit.steps, burn, fit.seed);

  // Intervals, SEs and correlations of the samples.
  const std::size_t s = chain.samples.size();
  Eigen::MatrixXd X(static_cast<Eigen::Index>(s), static_cast<Eigen::Index>(n));
  for (std::size_t k = 0; k < s; ++k)
    for (std::size_t i = 0; i < n; ++i)
      X(Eigen::Index(k), Eigen::Index(i)) = chain.samples[k][i];
  const Eigen::RowVectorXd mean = X.colwise().mean();
  const Eigen::MatrixXd centred = X.rowwise() - mean;
  const Eigen::MatrixXd cov = centred.transpose() * centred / double(s - 1);
  o.covariance.assign(n * n, 0.0);
  for (std::size_t i = 0; i < n; ++i)
    for (std::size_t j = 0; j < n; ++j)
      o.covariance[i * n + j] = cov(Eigen::Index(i), Eigen::Index(j));
  o.intervals.clear(), o.se.clear();
  nlohmann::json median = nlohmann::json::array();
  for (std::size_t i = 0; i < n; ++i)
  {
    const Parameter& p = fit.parameters[i];
    std::vector<double> values(s);
    double sum = 0, sum2 = 0;
    for (std::size_t k = 0; k < s; ++k)
    {
      values[k] = p.value(chain.samples[k][i]);
      sum += values[k], sum2 += values[k] * values[k];
    }
    o.intervals.push_back({quantile(values, 0.025), quantile(values, 0.975)});
    o.se.push_back(std::sqrt(std::max(sum2 / double(s) - std::pow(sum / double(s), 2), 0.0)));
    median.push_back(quantile(values, 0.5));
  }
  std::ostringstream csv;
  for (const Parameter& p : fit.parameters)
    csv << p.label << ",";
  csv << "log_posterior\n";
  for (std::size_t k = 0; k < s; k += 5 * std::size_t(chain.walkers))
    for (std::size_t w = 0; w < std::size_t(chain.walkers) && k + w < s; ++w)
    {
      for (std::size_t i = 0; i < n; ++i)
        csv << io::literal(fit.parameters[i].value(chain.samples[k + w][i])) << ",";
      csv << io::literal(chain.log_p[k + w]) << "\n";
    }
  io::write_atomic(out / "posterior.csv", csv.str());
  double tau = 0;
  for (double t : chain.autocorrelation)
    tau = std::max(tau, t);
  return {{"method", "affine-invariant ensemble sampler (stretch move)"},
          {"walkers", chain.walkers},
          {"steps", chain.steps},
          {"burn_in", chain.burn_in},
          {"acceptance", chain.acceptance},
          {"autocorrelation_steps", chain.autocorrelation},
          {"effective_samples", double(s) / std::max(tau, 1.0)},
          {"median", median},
          {"samples", "posterior.csv (every fifth step)"}};
}

/// The forward run at the answer against the emulator's prediction there:
/// each point's difference in the emulator's SDs, and the shift of the
/// answer the differences cause (a Gauss-Newton step of the likelihood with
/// the run's values in place of the emulator's). The verdict: they agree
/// when at least 90 % of the points lie within 2 of the emulator's SDs
/// (its error as stated) and no parameter moves by more than half its
/// standard error (the answer stands).
nlohmann::json confirm(const Fit& fit, const Options& o, const EmulatedLikelihood& l,
                       const Outcome& outcome, fs::path& run)
{
  Forward forward(fit, o, jobs::launcher_for(fit.launcher, o.launcher, o.out, fit.ranks, "fit",
                                             fit.file));
  const auto start = std::chrono::steady_clock::now();
  run = forward.runs({outcome.theta})[0];
  const double wall = std::chrono::duration<double>(std::chrono::steady_clock::now() - start)
                          .count();
  if (run.empty())
    return {{"verdict", "failed"}, {"wall_s", wall},
            {"why", "the forward run at the answer did not converge: see "
                        + (o.out / "runs").string()}};
  // The run's values, with the discrepancy's mean where the fit carries one
  // (the model it fits is the emulated one plus the discrepancy).
  std::vector<double> truth = model_values(fit, run);
  for (std::size_t i = 0; i < truth.size(); ++i)
    truth[i] += l.discrepancy_mean()(Eigen::Index(i));
  const auto e = l.evaluate(outcome.theta, false);
  const std::size_t m = truth.size(), n = outcome.theta.size();
  double chi2_run = 0, largest = 0;
  std::string where;
  std::size_t within = 0, j = 0;
  for (const Observation& ob : fit.observations)
    for (std::size_t i = 0; i < ob.value.size(); ++i, ++j)
    {
      const double z = (truth[j] - e.model(Eigen::Index(j))) / e.model_sd(Eigen::Index(j));
      within += std::abs(z) <= 2;
      if (std::abs(z) > std::abs(largest))
      {
        largest = z;
        where = ob.label + (ob.kind == Kind::biomarker ? std::string()
                                                       : format(" at t = %g ms", ob.t[i]))
                + (ob.kind == Kind::profile ? format(", x = %g mm", ob.x[i]) : std::string());
      }
      chi2_run += std::pow((truth[j] - ob.value[i]) / ob.sd[i], 2);
    }
  const Eigen::VectorXd shift = l.shift(outcome.theta, truth);
  const double share = double(within) / double(m);
  bool agree = share >= 0.9; // the emulator's error as it states it
  nlohmann::json shifts = nlohmann::json::object();
  for (std::size_t i = 0; i < n; ++i)
  {
    const double se = std::sqrt(outcome.covariance[i * n + i]);
    const double in_se = shift(Eigen::Index(i)) / se;
    agree = agree && std::abs(in_se) <= 0.5;
    const Parameter& p = fit.parameters[i];
    shifts[p.label] = {{"value", p.value(outcome.theta[i] + shift(Eigen::Index(i)))
                                     - p.value(outcome.theta[i])},
                       {"in_se", std::isfinite(in_se) ? nlohmann::json(in_se)
                                                      : nlohmann::json()}};
  }
  return {{"verdict", agree ? "agrees" : "disagrees"},
          {"run", fs::absolute(run).string()},
          {"points", m},
          {"largest_standardised_difference", largest},
          {"largest_where", where},
          {"share_within_2sd", share},
          {"shift", shifts},
          {"chi2_of_the_run", chi2_run},
          {"chi2_of_the_emulator", e.chi2},
          {"wall_s", wall}};
}

/// Where the confirming run disagrees: the fit again with forward runs
/// (at most fit.corrected_iterations iterations), from the emulator's answer (each bound's side kept a thousandth of the
/// span inside), into out/corrected; its answer.
nlohmann::json correct(const Fit& fit, const Options& o, const Outcome& outcome)
{
  Fit forward = fit;
  forward.emulator.reset();
  forward.max_iterations = fit.corrected_iterations;
  for (std::size_t i = 0; i < forward.parameters.size(); ++i)
  {
    Parameter& p = forward.parameters[i];
    const double lo = p.variable(p.lower), hi = p.variable(p.upper), margin = 1e-3 * (hi - lo);
    p.start = p.value(std::clamp(outcome.theta[i], lo + margin, hi - margin));
  }
  Options options = o;
  options.out = o.out / "corrected";
  std::cout << "\nfit: the confirming run disagrees with the emulator: corrected steps with "
               "forward runs from its answer -> " << options.out.string() << std::endl;
  const int code = run(forward, options);
  nlohmann::json out = {{"folder", fs::absolute(options.out).string()}, {"exit_code", code}};
  if (fs::exists(options.out / "fit.json"))
  {
    const auto answer = nlohmann::json::parse(io::read_text(options.out / "fit.json"));
    out["status"] = answer["status"];
    out["forward_runs"] = answer["forward_runs"];
    out["parameters"] = nlohmann::json::array();
    for (const auto& p : answer["parameters"])
      out["parameters"].push_back({{"label", p["label"]}, {"value", p["value"]},
                                   {"ci95", p["ci95"]}});
  }
  return out;
}

/// The answer's values at theta: the model, each point's residual
/// standardised by the noise and the emulator's SD, chi2 = e^T S^-1 e with
/// the priors.
Outcome answer_at(const Fit& fit, const EmulatedLikelihood& l, const std::vector<double>& theta)
{
  Outcome outcome;
  outcome.theta = theta;
  const auto e = l.evaluate(theta, false);
  outcome.model.assign(e.model.data(), e.model.data() + e.model.size());
  std::size_t j = 0;
  for (const Observation& ob : fit.observations)
    for (std::size_t i = 0; i < ob.value.size(); ++i, ++j)
      outcome.residuals.push_back((outcome.model[j] - ob.value[i])
                                  / std::hypot(ob.sd[i], e.model_sd(Eigen::Index(j))));
  double chi2 = e.chi2;
  for (Eigen::Index r = Eigen::Index(j) + 1; r < e.r.size(); ++r) // the priors
  {
    outcome.residuals.push_back(e.r(r));
    chi2 += e.r(r) * e.r(r);
  }
  outcome.chi2 = chi2;
  return outcome;
}

/// The fit's emulator: its likelihood's residuals with their exact
/// Jacobian, the active set, and after the answer its posterior where the
/// Laplace interval does not hold and the confirming forward run.
class Emulated : public Model
{
public:
  Emulated(const Fit& fit, const Options& o)
      : _fit(fit), _options(o), _l(fit), _cost(_l, fit.parameters.size())
  {
  }

  std::string plan() const override { return "on the emulator " + _fit.emulator_file.string(); }
  std::string checked() const override { return "its emulator"; }
  /// Nothing to run: the emulator and the fit were checked together as
  /// the fit file was read (attach_emulator).
  bool check_start(const std::vector<double>&) override { return true; }
  ceres::CostFunction& cost() override { return _cost; }
  std::unique_ptr<Progress> progress(const double* theta, const fs::path& out) override
  {
    return std::make_unique<Progress>(_fit, nullptr, nullptr, theta, out);
  }
  std::vector<int> held_at_bounds(const std::vector<double>& theta) const override
  {
    return pushed_to_bounds(_fit, _l, theta);
  }
  std::string failure(const ceres::Solver::Summary& summary) const override
  {
    return " on the emulator: " + summary.message;
  }
  std::string interrupted() const override { return ""; }
  Outcome answer(const std::vector<double>& theta) override { return answer_at(_fit, _l, theta); }

  /// The emulator's figures at the answer, its posterior by MCMC where the
  /// parameters correlate or a bound holds one (fit.posterior), then the
  /// confirming run and, where it disagrees, the corrected fit.
  void finish(Outcome& outcome, std::chrono::steady_clock::time_point start) override
  {
    const std::vector<double>& theta = outcome.theta;
    const auto e = _l.evaluate(theta, false);
    nlohmann::json& extra = outcome.extra;
    const std::vector<double> model_sd(e.model_sd.data(), e.model_sd.data() + e.model_sd.size());
    const double most = outcome.identifiable
                            ? largest_correlation(outcome.covariance, theta.size())
                            : std::numeric_limits<double>::infinity();
    extra["forward_model"] = {
        {"emulator", fs::absolute(_fit.emulator_file).string()},
        {"discrepancy", _fit.discrepancy_file.empty()
                            ? nlohmann::json()
                            : nlohmann::json(fs::absolute(_fit.discrepancy_file).string())},
        {"inputs", _l.inputs(theta)},
        {"model_sd", model_sd},
        {"log_det_residual", e.r(Eigen::Index(outcome.model.size()))}};
    extra["laplace"] = {{"largest_correlation", std::isfinite(most) ? nlohmann::json(most)
                                                                    : nlohmann::json()},
                        {"held_at_bounds", outcome.held.size()}};
    // Sampled where the Laplace interval does not hold: correlated, held at
    // a bound, or undetermined.
    const bool mcmc = _fit.posterior == "mcmc"
                      || (_fit.posterior == "auto" && (!(most <= 0.9) || !outcome.held.empty()));
    if (mcmc)
      extra["posterior"] = sample_posterior(_fit, _l, outcome, _options.out);
    extra["emulator_fit_wall_s"]
        = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    if (!_fit.confirm)
      return;
    fs::path run;
    const nlohmann::json c = confirm(_fit, _options, _l, outcome, run);
    extra["confirmation"] = c;
    outcome.best_run = run;
    outcome.forward_runs = run.empty() ? 0 : 1;
    std::cout << "confirming run: " << c["verdict"].get<std::string>() << " with the emulator"
              << (c.contains("share_within_2sd")
                      ? format(" (%.0f %% of its values within 2 of the emulator's SDs, 90 %% "
                               "needed; the answer's shift at most half an SE)",
                               100 * c["share_within_2sd"].get<double>())
                      : std::string())
              << std::endl;
    if (c["verdict"] != "agrees")
      extra["corrected"] = correct(_fit, _options, outcome);
  }

private:
  const Fit& _fit;
  const Options& _options;
  const EmulatedLikelihood _l;
  EmulatedCost _cost;
};

} // namespace

std::unique_ptr<Model> emulated(const Fit& fit, const Options& options)
{
  return std::make_unique<Emulated>(fit, options);
}

} // namespace nct::fit
