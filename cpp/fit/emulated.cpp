// A fit file's emulator checked against it, and the likelihood of its
// readings there (cpp/fit/emulated.h).
#include "fit/emulated.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <set>

#include <nlohmann/json.hpp>

#include "fit/readings.h"
#include "io/format.h"
#include "io/text.h"
#include "io/toml_input.h"
#include "scene/scene.h"

namespace nct::fit
{
namespace fs = std::filesystem;
using io::format;
using io::nan;

namespace
{

/// The emulator's curve block holding an observation's quantity.
std::string block_of(const Observation& o)
{
  if (o.kind == Kind::curve)
    return o.quantity == "apex_displacement_mm" ? "apex_mm"
           : o.quantity == "whole_eye_motion_mm" ? "whole_eye_mm"
                                                  : "";
  return o.quantity == "anterior" && o.relative ? "profiles_mm" : "";
}

/// Where a block starts among the curves' outputs.
std::size_t offset_of(const emulator::Emulator& e, const std::string& block)
{
  std::size_t at = 0;
  for (const auto& [name, size] : e.blocks())
  {
    if (name == block)
      return at;
    at += size;
  }
  throw std::out_of_range("the emulator has no block " + block);
}

/// The linear functional of an observation's i-th point: the curve
/// between the frames around t, or the profile at its frame and place;
/// an empty one when the emulator does not hold it.
emulator::Functional functional(const emulator::Emulator& e, const Observation& o, std::size_t i)
{
  const std::size_t start = offset_of(e, block_of(o));
  if (o.kind == Kind::curve)
  {
    const auto& t = e.t_ms();
    const double at = o.t[i];
    if (at < t.front() - 1e-3 || at > t.back() + 1e-3)
      return {};
    const auto hi = std::lower_bound(t.begin(), t.end(), std::clamp(at, t.front(), t.back()));
    const std::size_t j = std::size_t(hi - t.begin());
    if (j == 0)
      return {{start, 1.0}};
    const double w = std::clamp((at - t[j - 1]) / (t[j] - t[j - 1]), 0.0, 1.0);
    return {{start + j - 1, 1 - w}, {start + j, w}};
  }
  // A profile point: at the emulator's frame within half a frame of t, at its place x.
  const auto& ft = e.profile_t_ms();
  const auto& fx = e.profile_x_mm();
  const double half_frame = 0.5 * (e.t_ms().at(1) - e.t_ms().at(0));
  for (std::size_t f = 0; f < ft.size(); ++f)
    for (std::size_t p = 0; p < fx.size(); ++p)
      if (std::abs(o.t[i] - ft[f]) <= half_frame && std::abs(o.x[i] - fx[p]) <= 1e-3)
        return {{start + f * fx.size() + p, 1.0}};
  return {};
}

/// A model discrepancy per curve output (python/nct/discrepancy.py):
/// mean [mm] and a factor [mm] whose outer product is its covariance.
struct Discrepancy
{
  std::vector<double> mean;
  std::vector<std::vector<double>> factor;
};

/// The fit's discrepancy file, if any, checked against its emulator.
Discrepancy read_discrepancy(const Fit& fit)
{
  Discrepancy d;
  if (fit.discrepancy_file.empty())
    return d;
  const std::string where = fit.discrepancy_file.string() + ": ";
  try
  {
    const auto j = nlohmann::json::parse(io::read_text(fit.discrepancy_file));
    if (j.at("format") != "nct-discrepancy-1")
      throw std::invalid_argument("format is not nct-discrepancy-1");
    j.at("mean_mm").get_to(d.mean);
    j.at("factor_mm").get_to(d.factor);
  }
  catch (const std::exception& e)
  {
    throw scene::Error(where + "not a discrepancy file: " + e.what());
  }
  std::size_t outputs = 0;
  for (const auto& [name, size] : fit.emulator->blocks())
    outputs += size;
  if (d.mean.size() != outputs || d.factor.size() != outputs
      || (!d.factor.empty() && d.factor[0].empty()))
    throw scene::Error(where + io::format("%zu outputs, the emulator has %zu", d.mean.size(),
                                          outputs));
  for (const auto& row : d.factor)
    if (row.size() != d.factor[0].size())
      throw scene::Error(where + "its factor's rows differ in length");
  return d;
}

std::string join(const std::vector<std::string>& v, const std::string& between)
{
  std::string s;
  for (const auto& x : v)
    s += (s.empty() ? "" : between) + x;
  return s;
}

std::string list(const std::vector<double>& v)
{
  std::string s;
  for (double x : v)
    s += (s.empty() ? "" : ", ") + format("%g", x);
  return s;
}

} // namespace

void attach_emulator(Fit& fit, const scene::Scene& scene)
{
  const std::string file = fit.file.string() + ": ";
  try
  {
    fit.emulator = std::make_shared<const emulator::Emulator>(fit.emulator_file);
  }
  catch (const std::invalid_argument& e)
  {
    throw io::key_error(fit.file, "fit.emulator", e.what());
  }
  const emulator::Emulator& em = *fit.emulator;
  auto box = [](const emulator::Input& in) { return format("[%g, %g]", in.low, in.high); };
  fit.emulator_inputs.clear();
  std::set<std::size_t> used;
  for (const emulator::Input& in : em.inputs())
  {
    const std::set<std::string> keys(in.keys.begin(), in.keys.end());
    int index = -1;
    for (std::size_t i = 0; i < fit.parameters.size(); ++i)
    {
      const Parameter& p = fit.parameters[i];
      const std::set<std::string> pk(p.keys.begin(), p.keys.end());
      if (pk == keys)
        index = int(i);
      else
        for (const auto& k : p.keys)
          if (keys.count(k))
            throw scene::Error(file + "parameter '" + p.label + "' sets " + k + " but not "
                               "exactly the keys of the emulator's input " + in.name + " ("
                               + join(in.keys, ", ") + "): set them together");
    }
    if (index >= 0)
    {
      const Parameter& p = fit.parameters[std::size_t(index)];
      if (p.lower < in.low || p.upper > in.high)
        throw scene::Error(file + format("parameter '%s': its bounds [%g, %g] reach outside "
                                         "the emulator's box for %s %s",
                                         p.label.c_str(), p.lower, p.upper, in.name.c_str(),
                                         box(in).c_str()));
      if (p.prior && (p.prior_mean < in.low - 3 * p.prior_sd
                      || p.prior_mean > in.high + 3 * p.prior_sd))
        throw scene::Error(file + format("the measured %s = %g (the prior's mean) is outside "
                                         "the emulator's box %s by more than 3 sd",
                                         p.label.c_str(), p.prior_mean, box(in).c_str()));
      used.insert(std::size_t(index));
      fit.emulator_inputs.emplace_back(index, nan);
      continue;
    }
    // Fixed by the scene (the patient's geometry...): every key alike, inside the box.
    const double value = scene.real(in.keys.at(0));
    for (const auto& k : in.keys)
      if (scene.real(k) != value)
        throw scene::Error(file + format("the emulator's input %s sets %s together, but the "
                                         "scene gives %s = %g and %s = %g",
                                         in.name.c_str(), join(in.keys, ", ").c_str(),
                                         in.keys[0].c_str(), value, k.c_str(), scene.real(k)));
    if (value < in.low || value > in.high)
      throw scene::Error(file + format("%s = %g (%s, the scene's with the fit's and the "
                                       "patient's settings) is outside the emulator's box %s",
                                       in.name.c_str(), value, in.keys[0].c_str(),
                                       box(in).c_str()));
    fit.emulator_inputs.emplace_back(-1, value);
  }
  read_discrepancy(fit); // its errors before any work
  for (std::size_t i = 0; i < fit.parameters.size(); ++i)
    if (!used.count(i))
      throw scene::Error(file + "parameter '" + fit.parameters[i].label + "' ("
                         + join(fit.parameters[i].keys, ", ") + ") is none of the "
                         "emulator's inputs");

  for (std::size_t k = 0; k < fit.observations.size(); ++k)
  {
    const Observation& o = fit.observations[k];
    const std::string where = file + "observation[" + std::to_string(k + 1) + "] (" + o.label
                              + "): ";
    if (o.kind == Kind::biomarker)
    {
      const auto readings = em.readings();
      if (std::find(readings.begin(), readings.end(), o.quantity) == readings.end())
        throw scene::Error(where + "the emulator holds no reading " + o.quantity + "; it holds "
                           + join(readings, ", "));
      const auto [lo, hi] = em.reading_range(o.quantity);
      const double slack = 3 * o.sd[0];
      if (o.value[0] < lo - slack || o.value[0] > hi + slack)
        throw scene::Error(where + format("%s = %g is outside what the emulator's training "
                                          "runs gave, [%g, %g], by more than 3 sd",
                                          o.quantity.c_str(), o.value[0], lo, hi));
      continue;
    }
    if (block_of(o).empty())
      throw scene::Error(where + "the emulator holds the apex displacement, the whole eye's "
                                 "motion and the anterior profile relative to its rest shape; "
                                 "not " + o.quantity + (o.relative ? "" : " (absolute)"));
    for (std::size_t i = 0; i < o.value.size(); ++i)
      if (functional(em, o, i).empty())
        throw scene::Error(where + (o.kind == Kind::curve
                                        ? format("t = %g ms is outside the emulator's frames "
                                                 "[%g, %g] ms",
                                                 o.t[i], em.t_ms().front(), em.t_ms().back())
                                        : format("(t, x) = (%g ms, %g mm) is not one of the "
                                                 "emulator's profile points: frames %s ms, "
                                                 "places %s mm",
                                                 o.t[i], o.x[i],
                                                 list(em.profile_t_ms()).c_str(),
                                                 list(em.profile_x_mm()).c_str())));
  }
}

EmulatedLikelihood::EmulatedLikelihood(const Fit& fit) : _fit(fit)
{
  std::vector<double> y, sd2;
  std::vector<emulator::Functional> functionals;
  for (const Observation& o : fit.observations)
    for (std::size_t i = 0; i < o.value.size(); ++i)
    {
      if (o.kind == Kind::biomarker)
        _reading_rows.emplace_back(y.size(), o.quantity);
      else
      {
        _curve_rows.push_back(y.size());
        functionals.push_back(functional(*fit.emulator, o, i));
      }
      y.push_back(o.value[i]);
      sd2.push_back(o.sd[i] * o.sd[i]);
    }
  const Eigen::Index m = Eigen::Index(y.size());
  _y = Eigen::Map<Eigen::VectorXd>(y.data(), m);
  _sd2 = Eigen::Map<Eigen::VectorXd>(sd2.data(), m);
  const emulator::Projection p = fit.emulator->project(functionals);
  const Eigen::Index k = Eigen::Index(fit.emulator->component_count());
  const Discrepancy delta = read_discrepancy(fit);
  const Eigen::Index r = Eigen::Index(delta.factor.empty() ? 0 : delta.factor[0].size());
  _offset.setZero(m), _truncation.setZero(m), _factor.setZero(m, k + r), _delta.setZero(m);
  for (std::size_t q = 0; q < _curve_rows.size(); ++q)
  {
    const Eigen::Index row = Eigen::Index(_curve_rows[q]);
    _offset(row) = p.offset[q];
    _truncation(row) = p.truncation[q];
    for (Eigen::Index c = 0; c < k; ++c)
      _factor(row, c) = p.factor[q][std::size_t(c)];
    // The discrepancy's mean and factor at the point, by the same weights.
    for (const auto& [o, a] : functionals[q])
    {
      if (delta.mean.empty())
        break;
      _offset(row) += a * delta.mean.at(o);
      _delta(row) += a * delta.mean.at(o);
      for (Eigen::Index c = 0; c < r; ++c)
        _factor(row, k + c) += a * delta.factor.at(o)[std::size_t(c)];
    }
  }
  for (const Parameter& par : fit.parameters)
    _priors += par.prior;
}

std::vector<double> EmulatedLikelihood::inputs(const std::vector<double>& theta) const
{
  std::vector<double> x;
  for (const auto& [index, value] : _fit.emulator_inputs)
    x.push_back(index >= 0 ? _fit.parameters[std::size_t(index)].value(theta[std::size_t(index)])
                           : value);
  return x;
}

EmulatedLikelihood::Parts EmulatedLikelihood::parts(const std::vector<double>& theta,
                                                     bool derivatives) const
{
  const emulator::Emulator& em = *_fit.emulator;
  const std::vector<double> x = inputs(theta);
  const Eigen::Index m = _y.size(), n = Eigen::Index(theta.size());
  // d(input)/d(theta_j): the parameter's input only.
  std::vector<std::pair<std::size_t, double>> chain(theta.size());
  for (std::size_t i = 0; i < _fit.emulator_inputs.size(); ++i)
    if (const int j = _fit.emulator_inputs[i].first; j >= 0)
    {
      const Parameter& p = _fit.parameters[std::size_t(j)];
      chain[std::size_t(j)] = {i, p.log ? x[i] : 1.0};
    }
  const std::vector<emulator::Value> w = em.components(x, derivatives);
  const Eigen::Index k = Eigen::Index(w.size());
  Parts s;
  s.v.resize(k), s.dv.setZero(k, n);
  Eigen::VectorXd mean_w(k);
  Eigen::MatrixXd dw = Eigen::MatrixXd::Zero(k, n);
  for (Eigen::Index c = 0; c < k; ++c)
  {
    const emulator::Value& wc = w[std::size_t(c)];
    mean_w(c) = wc.mean, s.v(c) = wc.variance;
    if (derivatives)
      for (Eigen::Index j = 0; j < n; ++j)
      {
        const auto [input, dx] = chain[std::size_t(j)];
        dw(c, j) = wc.gradient[input] * dx;
        s.dv(c, j) = wc.variance_gradient[input] * dx;
      }
  }
  // The discrepancy's columns follow the components', each of unit variance.
  const Eigen::Index r = _factor.cols() - k;
  s.v.conservativeResize(k + r);
  s.v.tail(r).setOnes();
  s.dv.conservativeResize(k + r, n);
  s.dv.bottomRows(r).setZero();
  s.mean = _offset + _factor.leftCols(k) * mean_w;
  s.gradient = _factor.leftCols(k) * dw;
  s.F = _factor;
  s.d = _sd2 + _truncation;
  s.dd.setZero(m, n);
  for (const auto& [r, key] : _reading_rows)
  {
    const emulator::Value v = em.reading(key, x, derivatives);
    const Eigen::Index row = Eigen::Index(r);
    s.mean(row) = v.mean;
    s.d(row) += v.variance;
    for (Eigen::Index j = 0; j < n; ++j)
    {
      s.gradient(row, j) = v.gradient[chain[std::size_t(j)].first] * chain[std::size_t(j)].second;
      s.dd(row, j) = v.variance_gradient[chain[std::size_t(j)].first]
                     * chain[std::size_t(j)].second;
    }
  }
  return s;
}

EmulatedLikelihood::Evaluation EmulatedLikelihood::evaluate(const std::vector<double>& theta,
                                                            bool jacobian) const
{
  const Parts s = parts(theta, jacobian);
  const Eigen::Index m = _y.size(), n = Eigen::Index(theta.size());
  const Eigen::MatrixXd S = Eigen::MatrixXd(s.d.asDiagonal())
                            + s.F * s.v.asDiagonal() * s.F.transpose();
  const Eigen::LLT<Eigen::MatrixXd> llt(S);
  if (llt.info() != Eigen::Success)
    throw std::runtime_error("the likelihood's covariance is not positive definite");
  const auto L = llt.matrixL();
  const Eigen::VectorXd e = s.mean - _y;
  const Eigen::VectorXd r = L.solve(e);
  double log_det = -_sd2.array().log().sum();
  for (Eigen::Index i = 0; i < m; ++i)
    log_det += 2 * std::log(llt.matrixLLT()(i, i));
  const double r_det = std::sqrt(std::max(log_det, 0.0));

  Evaluation out;
  out.r.resize(Eigen::Index(residuals()));
  out.r.head(m) = r;
  out.r(m) = r_det;
  out.chi2 = r.squaredNorm();
  out.model = s.mean;
  out.model_sd = (s.d - _sd2 + (s.F.array().square().matrix() * s.v)).cwiseMax(0.0).cwiseSqrt();
  Eigen::Index row = m + 1;
  for (std::size_t i = 0; i < _fit.parameters.size(); ++i)
    if (const Parameter& p = _fit.parameters[i]; p.prior)
      out.r(row++) = (p.value(theta[i]) - p.prior_mean) / p.prior_sd;
  if (!jacobian)
    return out;

  out.jacobian.setZero(Eigen::Index(residuals()), n);
  for (Eigen::Index j = 0; j < n; ++j)
  {
    // M = L^-1 dS/dtheta_j L^-T; dr = L^-1 de - Phi(M) r; d(log det) = tr M.
    const Eigen::MatrixXd dS = s.F * s.dv.col(j).asDiagonal() * s.F.transpose()
                               + Eigen::MatrixXd(s.dd.col(j).asDiagonal());
    const Eigen::MatrixXd A = L.solve(dS);
    const Eigen::MatrixXd M = L.solve(A.transpose());
    const Eigen::VectorXd phi_r = M.triangularView<Eigen::StrictlyLower>() * r
                                  + 0.5 * M.diagonal().cwiseProduct(r);
    out.jacobian.col(j).head(m) = L.solve(s.gradient.col(j)) - phi_r;
    out.jacobian(m, j) = r_det > 1e-12 ? M.trace() / (2 * r_det) : 0.0;
  }
  row = m + 1;
  for (std::size_t i = 0; i < _fit.parameters.size(); ++i)
    if (const Parameter& p = _fit.parameters[i]; p.prior)
      out.jacobian(row++, Eigen::Index(i)) = (p.log ? p.value(theta[i]) : 1.0) / p.prior_sd;
  return out;
}

double EmulatedLikelihood::log_posterior(const std::vector<double>& theta) const
{
  for (std::size_t i = 0; i < theta.size(); ++i)
  {
    const Parameter& p = _fit.parameters[i];
    if (!(theta[i] >= p.variable(p.lower) && theta[i] <= p.variable(p.upper)))
      return -std::numeric_limits<double>::infinity();
  }
  const Parts s = parts(theta, false);
  // S = D + F V F^T: with W = D^-1/2 F V^1/2, B = I + W^T W,
  // e^T S^-1 e = |D^-1/2 e|^2 - b^T B^-1 b (b = W^T D^-1/2 e) and
  // log det S = log det D + log det B.
  const Eigen::VectorXd inv_sqrt_d = s.d.cwiseSqrt().cwiseInverse();
  const Eigen::VectorXd e = (s.mean - _y).cwiseProduct(inv_sqrt_d);
  const Eigen::MatrixXd W = inv_sqrt_d.asDiagonal() * s.F * s.v.cwiseSqrt().asDiagonal();
  const Eigen::MatrixXd B = Eigen::MatrixXd::Identity(W.cols(), W.cols()) + W.transpose() * W;
  const Eigen::LLT<Eigen::MatrixXd> llt(B);
  const Eigen::VectorXd b = W.transpose() * e;
  double minus_2_log = e.squaredNorm() - b.dot(llt.solve(b)) + s.d.array().log().sum()
                       - _sd2.array().log().sum();
  for (Eigen::Index i = 0; i < B.rows(); ++i)
    minus_2_log += 2 * std::log(llt.matrixLLT()(i, i));
  for (std::size_t i = 0; i < _fit.parameters.size(); ++i)
    if (const Parameter& p = _fit.parameters[i]; p.prior)
      minus_2_log += std::pow((p.value(theta[i]) - p.prior_mean) / p.prior_sd, 2);
  return -0.5 * minus_2_log;
}

Eigen::VectorXd EmulatedLikelihood::shift(const std::vector<double>& theta,
                                          const std::vector<double>& values) const
{
  const Parts s = parts(theta);
  const Eigen::MatrixXd S = Eigen::MatrixXd(s.d.asDiagonal())
                            + s.F * s.v.asDiagonal() * s.F.transpose();
  const Eigen::LLT<Eigen::MatrixXd> llt(S);
  Eigen::VectorXd d = Eigen::VectorXd::Zero(static_cast<Eigen::Index>(residuals()));
  for (Eigen::Index i = 0; i < _y.size(); ++i)
    d(i) = values.at(std::size_t(i)) - s.mean(i);
  d.head(_y.size()) = llt.matrixL().solve(d.head(_y.size()));
  const Eigen::MatrixXd J = evaluate(theta, true).jacobian;
  return -(J.transpose() * J).ldlt().solve(J.transpose() * d);
}

} // namespace nct::fit
