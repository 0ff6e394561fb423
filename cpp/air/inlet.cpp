#include "air/inlet.h"

#include <algorithm>
#include <cmath>
#include <stdexcept>

#include "io/csv.h"

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
  return io::read_csv<4>(file, "x_mm,y_mm,z_mm,u_m_s", "inlet table").values;
}

} // namespace nct::air
