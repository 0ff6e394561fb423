#include "puff/load.h"

#include <algorithm>
#include <array>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>
#include <string>

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

Table::Table(std::vector<double> times, std::vector<double> radii, std::vector<double> p)
    : _t(std::move(times)), _r(std::move(radii)), _p(std::move(p))
{
  if (_t.empty() || _r.empty() || _p.size() != _t.size() * _r.size())
    throw std::invalid_argument("puff table: the values do not fill the grid of times "
                                "and radii");
}

Table Table::read(const std::filesystem::path& file)
{
  std::ifstream in(file);
  if (!in)
    throw std::invalid_argument(file.string() + ": cannot open the puff table");
  auto fail = [&](int line, const std::string& what)
  { throw std::invalid_argument(file.string() + ":" + std::to_string(line) + ": " + what); };
  std::string text;
  if (!std::getline(in, text))
    fail(1, "empty file; expected the header t_ms,r_mm,p_mmHg");
  text.erase(std::remove_if(text.begin(), text.end(), ::isspace), text.end());
  if (text != "t_ms,r_mm,p_mmHg")
    fail(1, "header '" + text + "'; expected t_ms,r_mm,p_mmHg");

  // Rows (t, r, p) with their line numbers.
  std::vector<std::array<double, 3>> rows;
  std::vector<int> lines;
  for (int line = 2; std::getline(in, text); ++line)
  {
    if (text.find_first_not_of(" \t\r") == std::string::npos)
      continue;
    std::istringstream row(text);
    std::array<double, 3> v;
    char c1 = 0, c2 = 0;
    row >> v[0] >> c1 >> v[1] >> c2 >> v[2];
    const bool read = static_cast<bool>(row);
    row >> std::ws; // nothing may follow
    if (!read || !row.eof() || c1 != ',' || c2 != ',' || !std::isfinite(v[0])
        || !std::isfinite(v[1]) || !std::isfinite(v[2]))
      fail(line, "'" + text + "' is not three finite numbers t_ms,r_mm,p_mmHg");
    if (v[1] < 0)
      fail(line, "radius " + std::to_string(v[1]) + " mm is negative");
    rows.push_back(v);
    lines.push_back(line);
  }
  if (rows.empty())
    fail(2, "no rows after the header");

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
