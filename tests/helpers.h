// Shared by the scene test files: running scenes into test run folders.
#pragma once

#include <array>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <string>
#include <vector>

#include "run/run.h"
#include "scene/scene.h"

namespace nct::test
{

constexpr double mmHg = 1.333224e-4; // MPa

inline std::filesystem::path out_dir(const std::string& name)
{
  const char* root = std::getenv("NCT_TEST_OUT");
  return std::filesystem::path(root ? root : "test-runs") / name;
}

inline nlohmann::json run_scene(const std::string& scene, const std::string& name,
                         const std::vector<std::string>& sets = {})
{
  auto s = nct::read(MPI_COMM_WORLD, std::filesystem::path(NCT_SOURCE_DIR) / scene, sets);
  return nct::run(MPI_COMM_WORLD, s, {out_dir(name), {}});
}

/// Root of f in [lo, hi] by bisection (f(lo) and f(hi) of opposite signs).
inline double bisect(const std::function<double(double)>& f, double lo, double hi)
{
  for (int i = 0; i < 200; ++i)
  {
    double mid = 0.5 * (lo + hi);
    (f(lo) * f(mid) <= 0 ? hi : lo) = mid;
  }
  return 0.5 * (lo + hi);
}

/// Incompressible neo-Hookean thick sphere: pressure at inner stretch la,
/// p = mu (1/(2 lb^4) + 2/lb - 1/(2 la^4) - 2/la), lb from volume conservation.
inline double sphere_pressure(double la, double A, double B, double mu)
{
  const double a = la * A, b = std::cbrt(a * a * a + B * B * B - A * A * A), lb = b / B;
  return mu * (0.5 / std::pow(lb, 4) + 2 / lb - 0.5 / std::pow(la, 4) - 2 / la);
}

/// A damped oscillation's angular frequency [rad/ms] and decay rate
/// sigma [1/ms] from a signal y(t) after `from`: its upward zero crossings
/// give the period, its maxima (each refined by a parabola through three
/// samples a step dt apart) the decay, by a least-squares line through
/// their logarithms.
struct Oscillation
{
  double omega = 0, sigma = 0;
  std::size_t periods = 0, peaks = 0;
};

inline Oscillation damped_oscillation(const std::vector<double>& t, const std::vector<double>& y,
                                      double from, double dt)
{
  std::vector<double> up, peak_t, peak_log;
  for (std::size_t i = 1; i + 1 < t.size(); ++i)
  {
    if (t[i] < from)
      continue;
    if (y[i - 1] < 0 && y[i] >= 0)
      up.push_back(t[i - 1] + dt * y[i - 1] / (y[i - 1] - y[i]));
    if (y[i] > y[i - 1] && y[i] >= y[i + 1] && y[i] > 0)
    {
      const double a = 0.5 * (y[i - 1] - 2 * y[i] + y[i + 1]), b = 0.5 * (y[i + 1] - y[i - 1]);
      peak_t.push_back(t[i] - dt * b / (2 * a));
      peak_log.push_back(std::log(y[i] - b * b / (4 * a)));
    }
  }
  Oscillation o;
  o.peaks = peak_t.size();
  if (up.size() < 2 || peak_t.size() < 2)
    return o;
  o.periods = up.size() - 1;
  o.omega = 2 * M_PI * (up.size() - 1) / (up.back() - up.front());
  double st = 0, sl = 0, stt = 0, stl = 0;
  const double np = static_cast<double>(peak_t.size());
  for (std::size_t i = 0; i < peak_t.size(); ++i)
    st += peak_t[i], sl += peak_log[i], stt += peak_t[i] * peak_t[i],
        stl += peak_t[i] * peak_log[i];
  o.sigma = -(np * stl - st * sl) / (np * stt - st * st);
  return o;
}

/// The angular frequency of the damped sinusoid e^{-sigma t} (A cos wt +
/// B sin wt) that fits y(t) for t >= from best in least squares (A, B by
/// the normal equations, w by golden section within 10 % of omega0): the
/// whole record weighs in, so another mode's small ringing averages out
/// where zero crossings (damped_oscillation) shift with it.
inline double fitted_frequency(const std::vector<double>& t, const std::vector<double>& y,
                               double from, double omega0, double sigma)
{
  auto misfit = [&](double w)
  {
    double cc = 0, cs = 0, ss = 0, cy = 0, sy = 0, yy = 0;
    for (std::size_t i = 0; i < t.size(); ++i)
    {
      if (t[i] < from)
        continue;
      const double e = std::exp(-sigma * (t[i] - from)), c = e * std::cos(w * t[i]),
                   s = e * std::sin(w * t[i]);
      cc += c * c, cs += c * s, ss += s * s, cy += c * y[i], sy += s * y[i], yy += y[i] * y[i];
    }
    const double det = cc * ss - cs * cs, A = (cy * ss - sy * cs) / det,
                 B = (sy * cc - cy * cs) / det;
    return yy - A * cy - B * sy;
  };
  const double g = 0.5 * (std::sqrt(5.0) - 1); // the golden ratio's inverse
  double lo = 0.9 * omega0, hi = 1.1 * omega0;
  double x1 = hi - g * (hi - lo), x2 = lo + g * (hi - lo), f1 = misfit(x1), f2 = misfit(x2);
  while (hi - lo > 1e-9 * omega0)
    if (f1 < f2)
      hi = x2, x2 = x1, f2 = f1, x1 = hi - g * (hi - lo), f1 = misfit(x1);
    else
      lo = x1, x1 = x2, f1 = f2, x2 = lo + g * (hi - lo), f2 = misfit(x2);
  return 0.5 * (lo + hi);
}

/// Parameters of forms/hgo.py's law with the volumetric kappa ln J / J.
struct HgoLaw
{
  double c10, k1, k2, kappa, dispersion = 0;
};

/// Principal Cauchy stresses of the HGO law under F = diag(l), with a
/// fibre family along each axis i where `along[i]`:
/// sigma = kappa ln J / J I + dev(tau_bar) / J,
/// tau_bar = 2 (C10 + sum_f kappa_f W'_f) b_bar + 2 sum_f (1 - 3 kappa_f) W'_f b_bar_ff e_f (x) e_f,
/// W'_f = k1 E_f exp(k2 E_f^2), E_f = kappa_f (Ibar1 - 3) + (1 - 3 kappa_f)(b_bar_ff - 1),
/// a family only where b_bar_ff > 1 (Gasser, Ogden & Holzapfel 2006).
inline std::array<double, 3> hgo_stress(std::array<double, 3> l, const HgoLaw& m,
                                        std::array<bool, 3> along)
{
  const double J = l[0] * l[1] * l[2];
  std::array<double, 3> b, tau;
  for (int i = 0; i < 3; ++i)
    b[i] = std::pow(J, -2.0 / 3) * l[i] * l[i];
  const double I1 = b[0] + b[1] + b[2], kf = m.dispersion;
  double psi1 = m.c10;
  std::array<double, 3> psi4{0, 0, 0};
  for (int i = 0; i < 3; ++i)
  {
    if (!along[i] || b[i] <= 1)
      continue;
    const double E = kf * (I1 - 3) + (1 - 3 * kf) * (b[i] - 1);
    const double w = m.k1 * E * std::exp(m.k2 * E * E);
    psi1 += kf * w;
    psi4[i] = (1 - 3 * kf) * w;
  }
  for (int i = 0; i < 3; ++i)
    tau[i] = 2 * psi1 * b[i] + 2 * psi4[i] * b[i];
  const double mean = (tau[0] + tau[1] + tau[2]) / 3, vol = m.kappa * std::log(J) / J;
  return {vol + (tau[0] - mean) / J, vol + (tau[1] - mean) / J, vol + (tau[2] - mean) / J};
}

/// Where the HGO law's fibres lie in a homogeneous uniaxial test.
enum class Fibres
{
  axial,     ///< one family along the load
  transverse ///< one family along each lateral axis
};

/// Cauchy stresses (axial, lateral) of the HGO law under F = diag(l1, l2, l2).
inline std::array<double, 2> hgo_uniaxial_stress(double l1, double l2, const HgoLaw& m,
                                                 Fibres fibres = Fibres::axial)
{
  const bool axial = fibres == Fibres::axial;
  auto s = hgo_stress({l1, l2, l2}, m, {axial, !axial, !axial});
  return {s[0], s[1]};
}

/// Stretches (l1, l2) under a uniaxial Cauchy stress T: sigma_22 = 0 is
/// solved for l2 inside a bisection on l1.
inline std::array<double, 2> hgo_uniaxial_stretches(double T, double c10, double k1, double k2,
                                                    double kappa,
                                                    Fibres fibres = Fibres::axial,
                                                    double dispersion = 0)
{
  const HgoLaw m{c10, k1, k2, kappa, dispersion};
  auto lateral = [&](double l1)
  {
    return bisect([&](double l2) { return hgo_uniaxial_stress(l1, l2, m, fibres)[1]; }, 0.5,
                  1.5);
  };
  const double l1 = bisect(
      [&](double l1) { return hgo_uniaxial_stress(l1, lateral(l1), m, fibres)[0] - T; }, 0.7,
      1.5);
  return {l1, lateral(l1)};
}

/// Stretches (l1, l2, l3) of the HGO law with one family along x under an
/// equibiaxial Cauchy stress T in x and y (sigma_33 = 0): l3 by bisection
/// inside a Newton iteration on (l1, l2) with a finite-difference Jacobian.
inline std::array<double, 3> hgo_equibiaxial_stretches(double T, const HgoLaw& m)
{
  auto thickness = [&](double l1, double l2)
  { return bisect([&](double l3) { return hgo_stress({l1, l2, l3}, m, {true, false, false})[2]; },
                  0.3, 1.5); };
  auto residual = [&](double l1, double l2) -> std::array<double, 2>
  {
    auto s = hgo_stress({l1, l2, thickness(l1, l2)}, m, {true, false, false});
    return {s[0] - T, s[1] - T};
  };
  double l1 = 1, l2 = 1;
  const double h = 1e-7;
  for (int it = 0; it < 50; ++it)
  {
    auto r = residual(l1, l2), r1 = residual(l1 + h, l2), r2 = residual(l1, l2 + h);
    const double a = (r1[0] - r[0]) / h, b = (r2[0] - r[0]) / h, c = (r1[1] - r[1]) / h,
                 d = (r2[1] - r[1]) / h, det = a * d - b * c;
    const double d1 = (d * r[0] - b * r[1]) / det, d2 = (a * r[1] - c * r[0]) / det;
    l1 -= d1, l2 -= d2;
    if (std::abs(d1) + std::abs(d2) < 1e-14)
      break;
  }
  return {l1, l2, thickness(l1, l2)};
}

} // namespace nct::test
