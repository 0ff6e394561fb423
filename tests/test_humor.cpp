// The humors' mass (forms/humor_inertia.py) against closed forms: a
// closed, fluid-filled body on springs vibrates at sqrt(K / (m_wall +
// m_humor)); run serially and on 2 ranks.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include <dolfinx/la/petsc.h>
#include <gtest/gtest.h>

#include "cavity/cavity.h"
#include "helpers.h"
#include "run/model.h"
#include "run/solid_block.h"

namespace
{

using namespace nct::test;

/// What one free vibration of a closed body on springs gave.
struct Vibration
{
  Oscillation oscillation;
  double volume_change = 0; ///< the largest |V / V_0 - 1| of the cavity
  int newton_iterations = 0;
};

/// The scene's body, stiff (c10 = 1000 MPa), its cavity closed at rest,
/// on springs K [N/mm] and dashpots C [N ms/mm] from the start of the
/// dynamics; pushed by a sin^2 pulse of 100 mmHg on its outer surface for
/// 0.1 ms, then free until `end` [ms]. Samples the axial displacement at
/// `point`.
Vibration vibrate(const std::string& scene, const std::vector<std::string>& sets, double K,
                  double C, double dt, double end, const std::array<double, 3>& point)
{
  std::vector<std::string> all
      = {"fem.degree=1", "material.wall.c10=1000.0", "material.wall.kappa=10000.0",
         "material.wall.density=1e-3", "support.model=\"springs\"",
         "support.stiffness=" + std::to_string(K), "support.damping=" + std::to_string(C)};
  all.insert(all.end(), sets.begin(), sets.end());
  auto s = nct::read(MPI_COMM_WORLD, std::filesystem::path(NCT_SOURCE_DIR) / scene, all);
  nct::Model model = nct::make_model(MPI_COMM_WORLD, s);
  auto& problem = model.solid->problem;
  dolfinx::la::petsc::Matrix A(problem.create_matrix(), false);
  nct::solver::set_petsc_options({});
  nct::solver::Newton newton(MPI_COMM_WORLD, A.mat());
  nct::cavity::Closed closed(problem, {0.0});
  const nct::solver::NewtonSettings settings{25, 1e-10, 1e-10, 0, false};
  problem.start_dynamics({dt, 0.8, 0.0});
  const double push = 0.1, held = closed.targets()[0];
  Vibration v;
  std::vector<double> t, y;
  for (int n = 0; (n + 1) * dt <= end + 1e-12; ++n)
  {
    const double tn = (n + problem.load_level()) * dt, x = std::min(tn / push, 1.0);
    problem.set_press(tn < push ? 100 * mmHg * std::pow(std::sin(M_PI * x), 2) : 0.0);
    const auto report = newton.solve(closed.system(), settings);
    if (!report.converged)
    {
      ADD_FAILURE() << "step " << n << ": " << report.reason;
      return v;
    }
    v.newton_iterations += report.iterations;
    problem.advance();
    v.volume_change
        = std::max(v.volume_change, std::abs(problem.cavity_volumes()[0] / held - 1));
    t.push_back((n + 1) * dt);
    y.push_back(problem.displacement_at({point})[0][1]);
  }
  v.oscillation = damped_oscillation(t, y, 2 * push, dt);
  return v;
}

/// The body vibrates at the closed form of a mass m on a spring K and a
/// dashpot C, with and without its humor's mass.
void expect_closed_form(const std::string& name, const Vibration& v, double K, double C,
                        double m)
{
  const Oscillation& o = v.oscillation;
  ASSERT_GE(o.periods, 3u);
  ASSERT_GE(o.peaks, 4u);
  const double sigma = 0.5 * C / m, omega = std::sqrt(K / m - sigma * sigma);
  std::printf("%s: omega_d %.5f rad/ms (closed form %.5f), decay %.5f 1/ms (closed form "
              "%.5f), %zu periods; cavity volume held to %.1e; %d Newton iterations\n",
              name.c_str(), o.omega, omega, o.sigma, sigma, o.periods, v.volume_change,
              v.newton_iterations);
  // Generalised alpha at omega dt < 0.1: period error O((omega dt)^2) < 1e-3.
  EXPECT_NEAR(o.omega, omega, 3e-3 * omega);
  EXPECT_NEAR(o.sigma, sigma, 2e-2 * sigma);
  EXPECT_LT(v.volume_change, 1e-9);
}

} // namespace

// The closed can as an axisymmetric section: the wall's 11 pi mm^3 at
// 1e-3 g/mm^3 and the humor's pi mm^3 at 5e-3 g/mm^3 (heavy, so that the
// humor's mass moves the frequency by 19 %). Massless, the can vibrates
// at the wall's mass alone.
TEST(HumorInertia, AxisymmetricCanOnSpringsCarriesItsHumor)
{
  const double K = 1.0, C = 0.004, rho_f = 5e-3, dt = 0.02, end = 7.0;
  const double m_wall = 11 * M_PI * 1e-3, m_humor = M_PI * rho_f;
  const std::string scene = "tests/scenes/closed_can_section.toml";
  const std::array<double, 3> top = {1.0, 3.0, 0.0};
  const auto with = vibrate(scene, {"cavity.humor_inertia=\"translation\"",
                                    "cavity.humor_density=" + std::to_string(rho_f)},
                            K, C, dt, end, top);
  expect_closed_form("axisymmetric can with its humor", with, K, C, m_wall + m_humor);
  const auto without = vibrate(scene, {}, K, C, dt, end, top);
  expect_closed_form("axisymmetric can, massless humor", without, K, C, m_wall);
}

// The closed box, a quarter with two mirror planes: the humor moves along
// y only; the wall's 44 mm^3 at 1e-3 g/mm^3, the humor's 4 mm^3 at
// 5e-3 g/mm^3.
TEST(HumorInertia, BoxOnSpringsCarriesItsHumor)
{
  const double K = 1.0, C = 0.004, rho_f = 5e-3, dt = 0.02, end = 7.0;
  const auto v = vibrate("tests/scenes/closed_box.toml",
                         {"cavity.humor_inertia=\"translation\"",
                          "cavity.humor_density=" + std::to_string(rho_f)},
                         K, C, dt, end, {1.0, 3.0, 1.0});
  expect_closed_form("box with its humor", v, K, C, 44e-3 + 4 * rho_f);
}
