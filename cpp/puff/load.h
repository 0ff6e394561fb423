// The air puff as a prescribed pressure on the anterior cornea: a
// space-time profile p(r, t), r the distance from the eye's axis.
#pragma once

#include <filesystem>
#include <memory>
#include <vector>

namespace nct::puff
{

/// Air pressure p(r, t) [mmHg] on the anterior cornea; r [mm] from the
/// axis, t [ms] from the start of the puff.
class Load
{
public:
  virtual ~Load() = default;
  virtual double operator()(double r, double t) const = 0;
};

/// Gaussian in time and in r:
/// p = peak exp(-(t - peak_time)^2 / (2 width_t^2)) exp(-r^2 / (2 width_r^2)).
class Gaussian : public Load
{
public:
  Gaussian(double peak, double peak_time, double width_t, double width_r)
      : _peak(peak), _peak_time(peak_time), _width_t(width_t), _width_r(width_r)
  {
  }
  double operator()(double r, double t) const override;

private:
  double _peak, _peak_time, _width_t, _width_r;
};

/// A table on a grid of times and radii, bilinear in between: zero before
/// the first and after the last time (the puff is off), the last radius'
/// value beyond it.
class Table : public Load
{
public:
  /// `p` holds times.size() rows of radii.size() values.
  Table(std::vector<double> times, std::vector<double> radii, std::vector<double> p);
  /// Read a CSV file with the header "t_ms,r_mm,p_mmHg" and one row per
  /// (t, r): times in increasing order, each with the same increasing
  /// radii. Throws std::invalid_argument naming the file and line.
  static Table read(const std::filesystem::path& file);
  double operator()(double r, double t) const override;

  const std::vector<double>& times() const { return _t; }
  const std::vector<double>& radii() const { return _r; }

private:
  std::vector<double> _t, _r, _p;
};

} // namespace nct::puff
