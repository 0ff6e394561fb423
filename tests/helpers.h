// Shared by the scene test files: running scenes into test run folders.
#pragma once

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

} // namespace nct::test
