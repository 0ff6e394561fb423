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

/// A pulse in time with a slower rise than fall (Oehring et al., Appl.
/// Sci. 11 (2021) 2499, measured the Corvis ST's so): a raised-cosine rise
/// over rise_time, a hold at 1 over hold_time, a raised-cosine fall over
/// fall_time, 0 before t = 0 and after the fall:
///   s(t) = (1 - cos(pi t / T_r)) / 2,              0 <= t <= T_r,
///   s(t) = 1,                                      T_r <= t <= T_r + T_h,
///   s(t) = (1 + cos(pi (t - T_r - T_h) / T_f)) / 2, then for T_f.
/// Smooth (C^1) everywhere, so the time steps see no kink.
class PulseShape
{
public:
  PulseShape(double rise_time, double hold_time, double fall_time);
  /// The shape that rises to the peak at the mean rate `rise` and falls
  /// from it at `fall` (both > 0) [peak/ms], each over its whole edge, and
  /// lasts `duration` [ms] from onset to end: T_r = 1 / rise, T_f = 1 /
  /// fall, T_h = duration - T_r - T_f. Throws std::invalid_argument if
  /// the edges alone outlast the duration.
  static PulseShape from_descriptors(double rise, double fall, double duration);
  /// s(t) in [0, 1], t [ms] from the pulse's onset.
  double operator()(double t) const;
  double rise_time() const { return _rise; }
  double hold_time() const { return _hold; }
  double fall_time() const { return _fall; }
  /// The time [ms] at which the pulse ends (s = 0 afterwards).
  double end() const { return _rise + _hold + _fall; }

private:
  double _rise, _hold, _fall;
};

/// A radial profile f(r), linear between samples, held at its last value
/// beyond the last radius.
class RadialProfile
{
public:
  RadialProfile(std::vector<double> r, std::vector<double> f);
  /// Read a CSV file with the header "r_mm,p_mmHg" (e.g. a CFD run's
  /// corneal pressure at its peak), radii increasing from 0, normalised
  /// by its value at r = 0 (which must be positive). Throws
  /// std::invalid_argument naming the file and line.
  static RadialProfile read(const std::filesystem::path& file);
  double operator()(double r) const;

private:
  std::vector<double> _r, _f;
};

/// The measured pulse on a radial profile: p = peak s(t) f(r).
class Pulse : public Load
{
public:
  Pulse(double peak, PulseShape shape, RadialProfile profile)
      : _peak(peak), _shape(shape), _profile(std::move(profile))
  {
  }
  double operator()(double r, double t) const override
  {
    return _peak * _shape(t) * _profile(r);
  }

private:
  double _peak;
  PulseShape _shape;
  RadialProfile _profile;
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
