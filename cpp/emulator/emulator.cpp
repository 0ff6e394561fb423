#include "emulator/emulator.h"

#include <cmath>
#include <fstream>
#include <stdexcept>

#include <nlohmann/json.hpp>

#include "io/format.h"

namespace nct::emulator
{
namespace
{

Process read_process(const nlohmann::json& g)
{
  Process p;
  g.at("X").get_to(p.X);
  g.at("alpha").get_to(p.alpha);
  g.at("L").get_to(p.L);
  g.at("length_scale").get_to(p.length_scale);
  p.constant = g.at("constant"), p.noise = g.at("noise");
  p.y_mean = g.at("y_mean"), p.y_std = g.at("y_std");
  if (p.alpha.size() != p.X.size() || p.L.size() != p.X.size())
    throw std::invalid_argument("a process' X, alpha and L disagree in size");
  return p;
}

/// A process at the unit-cube point u: mean, variance and, with
/// `derivatives`, their gradients with respect to u.
Value evaluate(const Process& p, const std::vector<double>& u, bool derivatives = true)
{
  const std::size_t n = p.X.size(), d = u.size();
  std::vector<double> k(n), dk(derivatives ? n * d : 0); // k*, and dk*_i/du_j at i * d + j
  Value v;
  v.gradient.assign(d, 0.0);
  v.variance_gradient.assign(d, 0.0);
  double sum = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    double r2 = 0;
    for (std::size_t j = 0; j < d; ++j)
    {
      const double s = (u[j] - p.X[i][j]) / p.length_scale[j];
      r2 += s * s;
    }
    const double r = std::sqrt(r2), e = std::exp(-std::sqrt(5.0) * r);
    k[i] = p.constant * (1 + std::sqrt(5.0) * r + 5 * r2 / 3) * e;
    sum += k[i] * p.alpha[i];
    if (!derivatives)
      continue;
    // dk/du_j = -(5/3) c (1 + sqrt5 r) exp(-sqrt5 r) (u_j - X_ij) / l_j^2
    const double f = -(5.0 / 3.0) * p.constant * (1 + std::sqrt(5.0) * r) * e;
    for (std::size_t j = 0; j < d; ++j)
    {
      dk[i * d + j] = f * (u[j] - p.X[i][j]) / (p.length_scale[j] * p.length_scale[j]);
      v.gradient[j] += dk[i * d + j] * p.alpha[i];
    }
  }
  v.mean = p.y_mean + p.y_std * sum;
  for (auto& g : v.gradient)
    g *= p.y_std;
  // w = L^-1 k by forward substitution; var = c + noise - |w|^2.
  std::vector<double> w(n);
  double ww = 0;
  for (std::size_t i = 0; i < n; ++i)
  {
    double s = k[i];
    for (std::size_t m = 0; m < i; ++m)
      s -= p.L[i][m] * w[m];
    w[i] = s / p.L[i][i];
    ww += w[i] * w[i];
  }
  const double y2 = p.y_std * p.y_std, raw = p.constant + p.noise - ww;
  v.variance = y2 * std::max(raw, 0.0);
  if (!derivatives)
    return v;
  // d(var)/du = -2 y_std^2 (L^-T w)^T dk/du, by back substitution.
  for (std::size_t i = n; i-- > 0;)
  {
    double s = w[i];
    for (std::size_t m = i + 1; m < n; ++m)
      s -= p.L[m][i] * w[m];
    w[i] = s / p.L[i][i];
  }
  if (raw > 0)
    for (std::size_t i = 0; i < n; ++i)
      for (std::size_t j = 0; j < d; ++j)
        v.variance_gradient[j] -= 2 * y2 * w[i] * dk[i * d + j];
  return v;
}

/// From gradients with respect to the unit cube to the natural inputs.
void chain(Value& v, const std::vector<double>& du)
{
  for (std::size_t j = 0; j < du.size(); ++j)
    v.gradient[j] *= du[j], v.variance_gradient[j] *= du[j];
}

} // namespace

Emulator::Emulator(const std::filesystem::path& file)
{
  std::ifstream in(file);
  if (!in)
    throw std::invalid_argument(file.string() + ": emulator file not found");
  try
  {
    const nlohmann::json e = nlohmann::json::parse(in);
    if (e.at("format") != "nct-emulator-1")
      throw std::invalid_argument("format is not nct-emulator-1");
    for (const auto& b : e.at("box"))
      _inputs.push_back({b.at("input"), b.at("range").at(0), b.at("range").at(1),
                         b.at("scale") == "log", b.at("keys")});
    _noise_mm = e.at("noise_mm");
    e.at("t_ms").get_to(_t_ms);
    e.at("profile_t_ms").get_to(_profile_t_ms);
    e.at("profile_x_mm").get_to(_profile_x_mm);
    const auto& c = e.at("curves");
    for (const auto& b : c.at("blocks"))
      _blocks.emplace_back(b.at(0).get<std::string>(), b.at(1).get<std::size_t>());
    c.at("mean").get_to(_mean);
    c.at("basis").get_to(_basis);
    c.at("truncation").get_to(_truncation);
    for (const auto& g : c.at("components"))
      _components.push_back(read_process(g));
    std::size_t outputs = 0;
    for (const auto& [name, size] : _blocks)
      outputs += size;
    if (_mean.size() != outputs || _truncation.size() != outputs || _basis.size() != outputs
        || _blocks.at(0).second != _t_ms.size()
        || _blocks.back().second != _profile_t_ms.size() * _profile_x_mm.size())
      throw std::invalid_argument("its curves' blocks, clock, mean and basis disagree in size");
    for (const auto& row : _basis)
      if (row.size() != _components.size())
        throw std::invalid_argument("its basis has not one column per component");
    for (const auto& [key, g] : e.at("readings").items())
    {
      _readings.emplace(key, read_process(g));
      _reading_ranges[key] = {g.at("range").at(0), g.at("range").at(1)};
    }
  }
  catch (const nlohmann::json::exception& x)
  {
    throw std::invalid_argument(file.string() + ": not an emulator file: " + x.what());
  }
  catch (const std::invalid_argument& x)
  {
    throw std::invalid_argument(file.string() + ": " + x.what());
  }
}

std::pair<std::vector<double>, std::vector<double>>
Emulator::unit(const std::vector<double>& x) const
{
  if (x.size() != _inputs.size())
    throw std::out_of_range(io::format("%zu inputs for an emulator of %zu", x.size(),
                                       _inputs.size()));
  std::vector<double> u(x.size()), du(x.size());
  for (std::size_t j = 0; j < x.size(); ++j)
  {
    const Input& in = _inputs[j];
    if (!(x[j] >= in.low && x[j] <= in.high))
      throw std::out_of_range(io::format("%s = %g is outside the emulator's box [%g, %g]",
                                         in.name.c_str(), x[j], in.low, in.high));
    const auto t = [&](double v) { return in.log ? std::log(v) : v; };
    const double span = t(in.high) - t(in.low);
    u[j] = (t(x[j]) - t(in.low)) / span;
    du[j] = in.log ? 1 / (x[j] * span) : 1 / span;
  }
  return {u, du};
}

std::vector<Value> Emulator::curves(const std::vector<double>& x) const
{
  const std::vector<Value> w = components(x);
  std::vector<Value> out(_mean.size());
  for (std::size_t o = 0; o < _mean.size(); ++o)
  {
    Value& v = out[o];
    v.mean = _mean[o];
    v.variance = _truncation[o];
    v.gradient.assign(x.size(), 0.0);
    v.variance_gradient.assign(x.size(), 0.0);
    for (std::size_t c = 0; c < w.size(); ++c)
    {
      const double b = _basis[o][c];
      v.mean += b * w[c].mean;
      v.variance += b * b * w[c].variance;
      for (std::size_t j = 0; j < x.size(); ++j)
      {
        v.gradient[j] += b * w[c].gradient[j];
        v.variance_gradient[j] += b * b * w[c].variance_gradient[j];
      }
    }
    v.mean *= _noise_mm;
    v.variance *= _noise_mm * _noise_mm;
    for (std::size_t j = 0; j < x.size(); ++j)
    {
      v.gradient[j] *= _noise_mm;
      v.variance_gradient[j] *= _noise_mm * _noise_mm;
    }
  }
  return out;
}

Projection Emulator::project(const std::vector<Functional>& functionals) const
{
  const std::size_t k = _components.size();
  Projection p;
  for (const Functional& f : functionals)
  {
    double offset = 0, truncation = 0;
    std::vector<double> factor(k, 0.0);
    for (const auto& [o, a] : f)
    {
      if (o >= _mean.size())
        throw std::out_of_range(io::format("output %zu of an emulator of %zu", o, _mean.size()));
      offset += a * _mean[o];
      truncation += a * a * _truncation[o];
      for (std::size_t c = 0; c < k; ++c)
        factor[c] += a * _basis[o][c];
    }
    for (auto& b : factor)
      b *= _noise_mm;
    p.offset.push_back(offset * _noise_mm);
    p.factor.push_back(factor);
    p.truncation.push_back(truncation * _noise_mm * _noise_mm);
  }
  return p;
}

std::vector<Value> Emulator::components(const std::vector<double>& x, bool derivatives) const
{
  const auto [u, du] = unit(x);
  std::vector<Value> w;
  for (const Process& g : _components)
  {
    w.push_back(evaluate(g, u, derivatives));
    chain(w.back(), du);
  }
  return w;
}

Value Emulator::reading(const std::string& key, const std::vector<double>& x,
                        bool derivatives) const
{
  const auto at = _readings.find(key);
  if (at == _readings.end())
    throw std::out_of_range("the emulator has no reading '" + key + "'");
  const auto [u, du] = unit(x);
  Value v = evaluate(at->second, u, derivatives);
  chain(v, du);
  return v;
}

std::pair<double, double> Emulator::reading_range(const std::string& key) const
{
  const auto at = _reading_ranges.find(key);
  if (at == _reading_ranges.end())
    throw std::out_of_range("the emulator has no reading '" + key + "'");
  return at->second;
}

std::vector<std::string> Emulator::readings() const
{
  std::vector<std::string> keys;
  for (const auto& [key, p] : _readings)
    keys.push_back(key);
  return keys;
}

} // namespace nct::emulator
