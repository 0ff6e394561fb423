#include "air/inlet.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <sstream>
#include <stdexcept>

namespace nct::air
{
namespace
{
double dot(const std::array<double, 3>& a, const std::array<double, 3>& b)
{
  return a[0] * b[0] + a[1] * b[1] + a[2] * b[2];
}
} // namespace

std::array<double, 3> Inlet::velocity(const std::array<double, 3>& x) const
{
  const std::array<double, 3> d{x[0] - center[0], x[1] - center[1], x[2] - center[2]};
  double f = 1;
  switch (profile)
  {
  case Profile::uniform:
    break;
  case Profile::rectangle:
    for (int i = 0; i < 2; ++i)
      if (std::isfinite(half_widths[i]))
      {
        const double s = dot(d, axes[i]) / half_widths[i];
        f *= std::max(0.0, 1 - s * s);
      }
    break;
  case Profile::circle:
  {
    const double a = dot(d, direction);
    const double r2 = dot(d, d) - a * a;
    f = std::max(0.0, 1 - r2 / (radius * radius));
    break;
  }
  case Profile::table:
  {
    double sum = 0, weights = 0;
    for (const auto& p : points)
    {
      const double r2 = (x[0] - p[0]) * (x[0] - p[0]) + (x[1] - p[1]) * (x[1] - p[1])
                        + (x[2] - p[2]) * (x[2] - p[2]);
      if (r2 < 1e-24)
      {
        sum = p[3], weights = 1;
        break;
      }
      sum += p[3] / r2;
      weights += 1 / r2;
    }
    f = weights > 0 ? sum / weights : 0.0;
    break;
  }
  }
  return {speed * f * direction[0], speed * f * direction[1], speed * f * direction[2]};
}

double Inlet::ramp(double t) const
{
  if (t < 0)
    return 0;
  if (t >= ramp_time)
    return 1;
  return (1 - std::cos(M_PI * t / ramp_time)) / 2;
}

double Inlet::mean_factor() const
{
  switch (profile)
  {
  case Profile::uniform:
    return 1;
  case Profile::rectangle:
    return (std::isfinite(half_widths[0]) ? 2.0 / 3 : 1.0)
           * (std::isfinite(half_widths[1]) ? 2.0 / 3 : 1.0);
  case Profile::circle:
    return 0.5;
  case Profile::table:
    return 1;
  }
  return 1;
}

std::vector<std::array<double, 4>> Inlet::read_table(const std::filesystem::path& file)
{
  std::ifstream in(file);
  if (!in)
    throw std::invalid_argument(file.string() + ": cannot open the inlet table");
  auto fail = [&](int line, const std::string& what)
  { throw std::invalid_argument(file.string() + ":" + std::to_string(line) + ": " + what); };
  const std::string header = "x_mm,y_mm,z_mm,u_m_s";
  std::string text;
  if (!std::getline(in, text))
    fail(1, "empty file; expected the header " + header);
  text.erase(std::remove_if(text.begin(), text.end(), ::isspace), text.end());
  if (text != header)
    fail(1, "header '" + text + "'; expected " + header);
  std::vector<std::array<double, 4>> points;
  for (int line = 2; std::getline(in, text); ++line)
  {
    if (std::all_of(text.begin(), text.end(), ::isspace))
      continue;
    std::array<double, 4> p;
    std::istringstream row(text);
    bool ok = true;
    for (int i = 0; i < 4 && ok; ++i)
    {
      std::string cell;
      ok = static_cast<bool>(std::getline(row, cell, ','));
      std::size_t end = 0;
      try
      {
        p[i] = std::stod(cell, &end);
      }
      catch (const std::exception&)
      {
        ok = false;
      }
      ok = ok && std::isfinite(p[i])
           && std::all_of(cell.begin() + static_cast<std::ptrdiff_t>(end), cell.end(), ::isspace);
    }
    std::string rest;
    if (!ok || std::getline(row, rest))
      fail(line, "'" + text + "' is not four finite numbers");
    points.push_back(p);
  }
  if (points.empty())
    fail(2, "no points");
  return points;
}

} // namespace nct::air
