// Generalised-alpha elastodynamics (forms/dynamics.py) on the neo-Hookean
// cube: released from a stretched equilibrium by a smooth unload, it
// vibrates. Observed order of accuracy, energy conservation without
// damping, and the decay rate of mass-proportional damping.
#include <cmath>
#include <gtest/gtest.h>

#include <dolfinx/la/petsc.h>

#include "cavity/cavity.h"
#include "helpers.h"
#include "run/model.h"

namespace
{

using namespace nct::test;

struct Sample
{
  double t, u, energy; // time [ms], probe x-displacement [mm], total energy [mJ]
};

/// The cube stretched by a 150 mmHg pull on x = 1, then released over
/// `release` ms by a twice continuously differentiable ramp
/// p = p0 (1 - 10 s^3 + 15 s^4 - 6 s^5), s = t / release, and followed to
/// `end` ms with time step dt.
std::vector<Sample> vibrate(double dt, double end, double rho_inf, double damping,
                            double release)
{
  auto s = nct::scene::Scene::load(std::filesystem::path(NCT_SOURCE_DIR)
                                       / "tests/scenes/hgo_uniaxial.toml",
                                   {"material.tissue.model=\"neo_hookean\""});
  nct::Model model = nct::make_model(MPI_COMM_WORLD, s);
  auto& problem = *model.problem;
  dolfinx::la::petsc::Matrix A(problem.create_matrix(), false);
  nct::solver::set_petsc_options({}); // the defaults: MUMPS LU
  nct::solver::Newton newton(MPI_COMM_WORLD, A.mat());
  nct::cavity::Open open(problem);
  const nct::solver::NewtonSettings settings{25, 1e-10, 1e-12, true, false};
  const double p0 = -150 * mmHg;
  for (double f : {0.5, 1.0})
  {
    problem.set_surface_pressure(f * p0);
    EXPECT_TRUE(newton.solve(open.system(), settings).converged);
  }
  problem.start_dynamics({dt, rho_inf, damping});
  auto pressure = [&](double t)
  {
    const double x = std::min(t / release, 1.0);
    return p0 * (1 - x * x * x * (10 - 15 * x + 6 * x * x));
  };
  std::vector<Sample> samples;
  const int steps = static_cast<int>(std::lround(end / dt));
  for (int n = 0; n < steps; ++n)
  {
    problem.set_surface_pressure(pressure((n + problem.load_level()) * dt));
    auto report = newton.solve(open.system(), settings);
    if (!report.converged)
    {
      ADD_FAILURE() << "step " << n << ": " << report.reason << ", last residual "
                    << report.residuals.back();
      break;
    }
    problem.advance();
    const double u = problem.displacement_at({{1.0, 1.0, 1.0}})[0][0];
    samples.push_back({(n + 1) * dt, u, problem.strain_energy() + problem.kinetic_energy()});
  }
  return samples;
}

} // namespace

// Second order: the largest error of the probe's history (at the times
// every run shares) against a 4x finer run falls about 4x per halving of
// the step (rho_inf = 0.5, damped). A slow, smooth release keeps the
// mesh's highest modes, which these steps do not resolve, out of the
// comparison.
TEST(Dynamics, SecondOrderInTime)
{
  const double end = 0.32, release = 0.2, coarsest = 0.02, finest = coarsest / 16;
  const auto reference = vibrate(finest, end, 0.5, 0.1, release);
  std::vector<double> errors;
  for (double dt : {coarsest, coarsest / 2, coarsest / 4})
  {
    const auto run = vibrate(dt, end, 0.5, 0.1, release);
    const std::size_t stride = std::lround(coarsest / dt), ref_stride = std::lround(dt / finest);
    double worst = 0;
    for (std::size_t i = stride - 1; i < run.size(); i += stride)
      worst = std::max(worst, std::abs(run[i].u - reference[(i + 1) * ref_stride - 1].u));
    errors.push_back(worst);
  }
  const double order = std::log(errors[1] / errors[2]) / std::log(2.0);
  std::printf("generalised alpha: largest errors %.3e %.3e %.3e mm at dt %.4f, %.4f, %.4f ms; "
              "observed order %.2f, %.2f\n",
              errors[0], errors[1], errors[2], coarsest, coarsest / 2, coarsest / 4,
              std::log(errors[0] / errors[1]) / std::log(2.0), order);
  EXPECT_GT(order, 1.8);
  EXPECT_LT(order, 2.5);
}

// Without damping and numerical dissipation (rho_inf = 1) the free
// vibration keeps its energy; with mass-proportional damping c every mode
// decays as exp(-c t / 2) in amplitude, exp(-c t) in energy.
TEST(Dynamics, EnergyConservedOrDampedAtThePredictedRate)
{
  auto free = vibrate(0.01, 0.6, 1.0, 0.0, 0.05);
  double lo = 1e300, hi = 0;
  for (const auto& s : free)
    if (s.t > 0.05) // after the release: no external work
      lo = std::min(lo, s.energy), hi = std::max(hi, s.energy);
  std::printf("undamped: energy %.6e to %.6e mJ over 0.05-0.6 ms (spread %.2e relative)\n", lo, hi,
              (hi - lo) / hi);
  EXPECT_LT((hi - lo) / hi, 1e-3);

  const double c = 2.0; // 1/ms
  auto damped = vibrate(0.01, 0.6, 1.0, c, 0.05);
  // Energy averaged over two windows a whole number of samples apart.
  auto mean = [&](double from, double to)
  {
    double sum = 0;
    int n = 0;
    for (const auto& s : damped)
      if (s.t > from && s.t <= to)
        sum += s.energy, ++n;
    return sum / n;
  };
  const double rate = std::log(mean(0.1, 0.3) / mean(0.4, 0.6)) / 0.3;
  std::printf("damped (c = %.1f 1/ms): energy decays at %.4f 1/ms\n", c, rate);
  EXPECT_NEAR(rate, c, 0.05 * c);
}
