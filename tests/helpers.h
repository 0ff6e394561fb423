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

/// Where the HGO law's fibres lie in a homogeneous uniaxial test.
enum class Fibres
{
  axial,     ///< one family along the load
  transverse ///< one family along each lateral axis
};

/// Cauchy stresses (axial, lateral) of the HGO law of forms/hgo.py under
/// F = diag(l1, l2, l2):
/// sigma = kappa ln J / J I + dev(tau_bar) / J,
/// tau_bar = 2 C10 b_bar + 2 psi4' (F_bar a) (x) (F_bar a) per family.
inline std::array<double, 2> hgo_uniaxial_stress(double l1, double l2, double c10, double k1,
                                                 double k2, double kappa,
                                                 Fibres fibres = Fibres::axial)
{
  const double J = l1 * l2 * l2;
  const double b1 = std::pow(J, -2.0 / 3) * l1 * l1, b2 = std::pow(J, -2.0 / 3) * l2 * l2;
  // psi4' (Ibar4 - 1 = E) times Ibar4, zero in compression
  auto fibre = [&](double b)
  { return b > 1 ? k1 * (b - 1) * std::exp(k2 * (b - 1) * (b - 1)) * b : 0.0; };
  const bool axial = fibres == Fibres::axial;
  const double t1 = 2 * c10 * b1 + (axial ? 2 * fibre(b1) : 0.0);
  const double t2 = 2 * c10 * b2 + (axial ? 0.0 : 2 * fibre(b2));
  const double mean = (t1 + 2 * t2) / 3;
  const double vol = kappa * std::log(J) / J;
  return {vol + (t1 - mean) / J, vol + (t2 - mean) / J};
}

/// Stretches (l1, l2) under a uniaxial Cauchy stress T: sigma_22 = 0 is
/// solved for l2 inside a bisection on l1.
inline std::array<double, 2> hgo_uniaxial_stretches(double T, double c10, double k1, double k2,
                                                    double kappa,
                                                    Fibres fibres = Fibres::axial)
{
  auto lateral = [&](double l1)
  {
    return bisect([&](double l2)
                  { return hgo_uniaxial_stress(l1, l2, c10, k1, k2, kappa, fibres)[1]; },
                  0.5, 1.5);
  };
  const double l1 = bisect(
      [&](double l1)
      { return hgo_uniaxial_stress(l1, lateral(l1), c10, k1, k2, kappa, fibres)[0] - T; },
      0.7, 1.5);
  return {l1, lateral(l1)};
}

} // namespace nct::test
