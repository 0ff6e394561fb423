#include "puff/load.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "io/csv.h"

namespace nct::puff
{
namespace
{

/// Index i with x[i] <= v < x[i+1] and the weight of x[i+1], clamped.
std::pair<std::size_t, double> locate(const std::vector<double>& x, double v)
{
  if (x.size() == 1 || v <= x.front())
    return {0, 0.0};
  if (v >= x.back())
    return {x.size() - 2, 1.0};
  const std::size_t i
      = static_cast<std::size_t>(std::upper_bound(x.begin(), x.end(), v) - x.begin()) - 1;
  return {i, (v - x[i]) / (x[i + 1] - x[i])};
}

} // namespace

double Gaussian::operator()(double r, double t) const
{
  const double s = (t - _peak_time) / _width_t;
  return _peak * std::exp(-0.5 * s * s) * std::exp(-0.5 * r * r / (_width_r * _width_r));
}

PulseShape::PulseShape(double rise_time, double hold_time, double fall_time)
    : _rise(rise_time), _hold(hold_time), _fall(fall_time)
{
  if (!(rise_time > 0 && hold_time >= 0 && fall_time > 0))
    throw std::invalid_argument("pulse: the rise and fall times must be positive and the "
                                "hold time not negative");
}

PulseShape PulseShape::from_descriptors(double rise, double fall, double duration)
{
  // Each edge's rate is the peak over the edge's length; what the edges
  // leave of the duration is the hold.
  if (!(rise > 0 && fall > 0 && duration > 0))
    throw std::invalid_argument("pulse: the edges' rates and the duration must be positive");
  const double hold = duration - 1 / rise - 1 / fall;
  if (hold < 0)
    throw std::invalid_argument("pulse: edges this slow take " + std::to_string(duration - hold)
                                + " ms, longer than the duration " + std::to_string(duration)
                                + " ms; raise the rates or the duration");
  return PulseShape(1 / rise, hold, 1 / fall);
}

double PulseShape::operator()(double t) const
{
  if (t <= 0 || t >= end())
    return 0.0;
  if (t < _rise)
    return 0.5 * (1 - std::cos(M_PI * t / _rise));
  if (t <= _rise + _hold)
    return 1.0;
  return 0.5 * (1 + std::cos(M_PI * (t - _rise - _hold) / _fall));
}

RadialProfile::RadialProfile(std::vector<double> r, std::vector<double> f)
    : _r(std::move(r)), _f(std::move(f))
{
  if (_r.empty() || _r.size() != _f.size())
    throw std::invalid_argument("radial profile: as many values as radii, at least one");
}

RadialProfile RadialProfile::read(const std::filesystem::path& file)
{
  const auto [rows, lines] = io::read_csv<2>(file, "r_mm,p_mmHg", "radial profile");
  auto fail = [&](int line, const std::string& what) { io::csv_error(file, line, what); };
  if (rows[0][0] != 0)
    fail(lines[0], "the first radius must be 0 (the axis), not " + std::to_string(rows[0][0]));
  if (!(rows[0][1] > 0))
    fail(lines[0], "the pressure on the axis must be positive: the profile is normalised "
                   "by it");
  std::vector<double> r, f;
  for (std::size_t k = 0; k < rows.size(); ++k)
  {
    if (k > 0 && rows[k][0] <= r.back())
      fail(lines[k], "radius " + std::to_string(rows[k][0]) + " mm does not increase");
    r.push_back(rows[k][0]);
    f.push_back(rows[k][1] / rows[0][1]);
  }
  return RadialProfile(std::move(r), std::move(f));
}

double RadialProfile::operator()(double r) const
{
  if (_r.size() == 1)
    return _f[0];
  const auto [i, w] = locate(_r, r);
  return (1 - w) * _f[i] + w * _f[i + 1];
}

Table::Table(std::vector<double> times, std::vector<double> radii, std::vector<double> p)
    : _t(std::move(times)), _r(std::move(radii)), _p(std::move(p))
{
  if (_t.empty() || _r.empty() || _p.size() != _t.size() * _r.size())
    throw std::invalid_argument("puff table: the values do not fill the grid of times "
                                "and radii");
}

Table Table::read(const std::filesystem::path& file)
{
  const auto [rows, lines] = io::read_csv<3>(file, "t_ms,r_mm,p_mmHg", "puff table");
  auto fail = [&](int line, const std::string& what) { io::csv_error(file, line, what); };
  for (std::size_t k = 0; k < rows.size(); ++k)
    if (rows[k][1] < 0)
      fail(lines[k], "radius " + std::to_string(rows[k][1]) + " mm is negative");

  // The grid: the radii of the first time, repeated for every time.
  std::vector<double> t, r, p;
  for (std::size_t k = 0; k < rows.size() && rows[k][0] == rows[0][0]; ++k)
  {
    if (!r.empty() && rows[k][1] <= r.back())
      fail(lines[k], "radius " + std::to_string(rows[k][1]) + " mm does not increase");
    r.push_back(rows[k][1]);
  }
  for (std::size_t k = 0; k < rows.size(); ++k)
  {
    const std::size_t j = k % r.size();
    if (j == 0)
    {
      if (!t.empty() && rows[k][0] <= t.back())
        fail(lines[k], "time " + std::to_string(rows[k][0]) + " ms does not increase "
                       "(or the time before it lacks radii of the first time)");
      t.push_back(rows[k][0]);
    }
    if (rows[k][0] != t.back() || rows[k][1] != r[j])
      fail(lines[k], "every time needs the radii of the first time, in the same order");
    p.push_back(rows[k][2]);
  }
  if (p.size() != t.size() * r.size())
    fail(lines.back(), "the last time has fewer radii than the first");
  return Table(std::move(t), std::move(r), std::move(p));
}

double Table::operator()(double r, double t) const
{
  if (t < _t.front() || t > _t.back())
    return 0.0;
  const auto [i, s] = locate(_t, t);
  const auto [j, w] = locate(_r, r);
  const std::size_t n = _r.size();
  auto at = [&](std::size_t a, std::size_t b)
  { return _p[std::min(a, _t.size() - 1) * n + std::min(b, n - 1)]; };
  return (1 - s) * ((1 - w) * at(i, j) + w * at(i, j + 1))
         + s * ((1 - w) * at(i + 1, j) + w * at(i + 1, j + 1));
}

} // namespace nct::puff
