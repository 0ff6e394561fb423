// Viscoelasticity of the matrix (forms/viscoelasticity.py) on the cube of
// tests/scenes/hgo_uniaxial.toml, pulled on x = 1 through the dynamics with
// a negligible mass: creep and relaxation against the standard linear
// solid's closed forms at small strain, the instantaneous and long-time
// limits at large strain, and the work on the viscous branches.
#include <cmath>
#include <filesystem>
#include <functional>
#include <gtest/gtest.h>

#include <dolfinx/la/petsc.h>

#include "cavity/cavity.h"
#include "helpers.h"
#include "run/model.h"
#include "run/solid_block.h"

namespace
{

using namespace nct::test;

/// The cube of one law through a load history; `pressure(t)` is the press
/// on x = 1 [MPa] (negative: a pull).
class Cube
{
public:
  Cube(std::vector<std::string> sets)
  {
    // Homogeneous strain: linear elements are exact, and cheap.
    sets.push_back("material.tissue.density=1e-9");
    sets.push_back("fem.degree=1");
    auto s = nct::read(MPI_COMM_WORLD,
                       std::filesystem::path(NCT_SOURCE_DIR) / "tests/scenes/hgo_uniaxial.toml",
                       sets);
    _model = std::make_unique<nct::Model>(nct::make_model(MPI_COMM_WORLD, s));
    _A.emplace(problem().create_matrix(), false);
    nct::solver::set_petsc_options({});
    _newton = std::make_unique<nct::solver::Newton>(MPI_COMM_WORLD, _A->mat());
    _open = std::make_unique<nct::cavity::Open>(problem());
    _probe = std::make_unique<nct::solid::Probes>(problem(), std::vector<std::array<double, 3>>{
                                                                 {1.0, 1.0, 1.0}});
  }
  nct::solid::Problem& problem() { return _model->solid->problem; }
  /// Dynamics from rest with steps dt (rho_inf = 0: the balance at t_{n+1}).
  void start(double dt)
  {
    _dt = dt;
    problem().start_dynamics({dt, 0.0, 0.0});
  }
  void set_dt(double dt)
  {
    _dt = dt;
    problem().set_time_step({dt, 0.0, 0.0});
  }
  /// One step under the press p [MPa]; the probe's x-displacement [mm].
  double step(double p)
  {
    problem().set_press(p);
    solve();
    problem().advance();
    _t += _dt;
    return _probe->displacement()[0][0];
  }
  /// One step at the press that holds the probe's x-displacement at `u`
  /// (secant iterations on the press, which is near linear in u here).
  double step_to(double u, double p_guess)
  {
    double p0 = p_guess, u0 = trial(p0);
    double p1 = p0 * (1 + 1e-3), u1 = trial(p1);
    for (int i = 0; i < 20 && std::abs(u1 - u) > 1e-14; ++i)
    {
      const double p2 = p1 + (u - u1) * (p1 - p0) / (u1 - u0);
      p0 = p1, u0 = u1, p1 = p2, u1 = trial(p1);
    }
    problem().advance();
    _t += _dt;
    return p1;
  }
  double t() const { return _t; }

private:
  double trial(double p)
  {
    problem().set_press(p);
    solve();
    return _probe->displacement()[0][0];
  }
  void solve()
  {
    const nct::solver::NewtonSettings settings{25, 1e-10, 1e-15, 0, false};
    const auto report = _newton->solve(_open->system(), settings);
    if (!report.converged)
      throw std::runtime_error("step at t = " + std::to_string(_t) + ": " + report.reason);
  }
  std::unique_ptr<nct::Model> _model;
  std::optional<dolfinx::la::petsc::Matrix> _A;
  std::unique_ptr<nct::solver::Newton> _newton;
  std::unique_ptr<nct::cavity::Open> _open;
  std::unique_ptr<nct::solid::Probes> _probe;
  double _dt = 0, _t = 0;
};

/// The standard linear solid of a neo-Hookean matrix at small strain:
/// long-time shear modulus mu = 2 C10, instantaneous (1 + beta) mu, bulk K.
struct Sls
{
  double mu, beta, tau, K;
  double mu0() const { return (1 + beta) * mu; }
  /// Uniaxial creep under a stress ramped from 0 to T over tr, for t >= tr:
  /// the compliance 1/(9K) + (1/(3mu) - (1/(3mu) - 1/(3mu0)) exp(-t/tc)),
  /// tc = tau (1 + beta), convolved with the ramp.
  double creep(double T, double tr, double t) const
  {
    const double tc = tau * (1 + beta);
    return T * (1 / (9 * K) + 1 / (3 * mu))
           - T * (1 / (3 * mu) - 1 / (3 * mu0())) * tc / tr * std::exp(-t / tc)
                 * (std::exp(tr / tc) - 1);
  }
  /// Uniaxial relaxation after a strain ramped from 0 to e over tr:
  /// E(t) = E_inf + (E_0 - E_inf) exp(-t/tE), E = 9 K mu / (3 K + mu),
  /// tE = tau (3 K + mu0) / (3 K + mu), convolved with the ramp.
  double relaxation(double e, double tr, double t) const
  {
    auto E = [&](double m) { return 9 * K * m / (3 * K + m); };
    const double tE = tau * (3 * K + mu0()) / (3 * K + mu);
    return e * (E(mu) + (E(mu0()) - E(mu)) * tE / tr * std::exp(-t / tE)
                            * (std::exp(tr / tE) - 1));
  }
};

const std::vector<std::string> neo_hookean = {
    "material.tissue.model=\"neo_hookean\"", "material.tissue.c10=0.05",
    "material.tissue.kappa=5.0", "material.tissue.viscoelasticity.relative_moduli=[0.5]",
    "material.tissue.viscoelasticity.relaxation_times=[10.0]"};

/// The largest relative error of the creep history (ramp 1 ms, to 40 ms)
/// with steps dt.
double creep_error(double dt)
{
  const Sls sls{0.1, 0.5, 10.0, 5.0};
  const double T = 1e-6, tr = 1.0; // MPa (a strain of 3e-6), ms
  Cube cube(neo_hookean);
  cube.start(dt);
  double worst = 0;
  while (cube.t() < 40 - 1e-9)
  {
    const double t = cube.t() + dt;
    const double u = cube.step(-T * std::min(t / tr, 1.0));
    if (t >= tr - 1e-9)
      worst = std::max(worst, std::abs(u / sls.creep(T, tr, t) - 1));
  }
  return worst;
}

} // namespace

// Creep of the standard linear solid: the strain under a held stress
// rises from the instantaneous compliance to the long-time one with the
// retardation time tau (1 + beta); second order in the step.
TEST(Viscoelasticity, CreepOfTheStandardLinearSolid)
{
  const double coarse = creep_error(0.5), fine = creep_error(0.25);
  std::printf("creep: largest relative error %.3e (dt 0.5 ms), %.3e (dt 0.25 ms), order %.2f\n",
              coarse, fine, std::log(coarse / fine) / std::log(2.0));
  EXPECT_LT(fine, 2e-5);
  EXPECT_GT(std::log(coarse / fine) / std::log(2.0), 1.7);
}

// Relaxation: the stress that holds a strain falls from the instantaneous
// modulus to the long-time one with the relaxation time of uniaxial stress.
TEST(Viscoelasticity, RelaxationOfTheStandardLinearSolid)
{
  const Sls sls{0.1, 0.5, 10.0, 5.0};
  const double e = 3e-6, tr = 1.0, dt = 0.5;
  Cube cube(neo_hookean);
  cube.start(dt);
  double p = -e * 0.3, worst = 0, first = 0, last = 0;
  while (cube.t() < 40 - 1e-9)
  {
    const double t = cube.t() + dt;
    p = cube.step_to(e * std::min(t / tr, 1.0), p);
    // The pull is the Cauchy stress on the deformed face; at this strain
    // the nominal stress differs by 1e-6 relative.
    if (t >= tr - 1e-9)
    {
      const double sigma = -p, exact = sls.relaxation(e, tr, t);
      worst = std::max(worst, std::abs(sigma / exact - 1));
      first = first ? first : sigma, last = sigma;
    }
  }
  std::printf("relaxation: stress %.5e to %.5e MPa, largest relative error %.3e\n", first, last,
              worst);
  EXPECT_LT(worst, 1e-5);
  EXPECT_GT(first / last, 1.2); // it relaxes
}

// At large strain, a pull much faster than tau meets the law with its
// matrix stiffened (1 + beta) times, the fibres unchanged; held for many
// tau, the cube creeps to the elastic law. Both against the closed form
// of the HGO cube; the viscous work stays positive and is what the cube
// dissipated once it has relaxed.
TEST(Viscoelasticity, InstantaneousAndLongTimeLimitsAtLargeStrain)
{
  const double beta = 1.0, T = 150 * mmHg;
  Cube cube({"material.tissue.viscoelasticity.relative_moduli=[1.0]",
             "material.tissue.viscoelasticity.relaxation_times=[10.0]"});
  const double tr = 0.02;
  cube.start(tr / 10);
  double u = 0, smallest_work = 0;
  while (cube.t() < tr - 1e-12)
  {
    u = cube.step(-T * std::min((cube.t() + tr / 10) / tr, 1.0));
    smallest_work = std::min(smallest_work, cube.problem().viscous_work());
  }
  const auto instantaneous = hgo_uniaxial_stretches(T, 0.05 * (1 + beta), 0.010, 100, 5.0);
  const auto long_time = hgo_uniaxial_stretches(T, 0.05, 0.010, 100, 5.0);
  std::printf("large strain: stretch %.6f after the pull (instantaneous law %.6f, elastic %.6f)\n",
              1 + u, instantaneous[0], long_time[0]);
  EXPECT_GT(long_time[0] - instantaneous[0], 1e-2);
  EXPECT_NEAR(1 + u, instantaneous[0], 5e-5);
  // Held for 30 retardation times tau (1 + beta) in growing steps, then
  // released and left as long.
  auto hold = [&](double p)
  {
    for (auto [dt, steps] : {std::pair{0.1, 20}, {1.0, 20}, {10.0, 60}})
    {
      cube.set_dt(dt);
      for (int i = 0; i < steps; ++i)
      {
        u = cube.step(p);
        smallest_work = std::min(smallest_work, cube.problem().viscous_work());
      }
    }
  };
  hold(-T);
  std::printf("large strain: stretch %.8f after %.0f ms held (elastic %.8f)\n", 1 + u, cube.t(),
              long_time[0]);
  EXPECT_NEAR(1 + u, long_time[0], 1e-7);
  hold(0.0);
  const double dissipated = cube.problem().viscous_work();
  std::printf("large strain: back to %.2e mm; viscous work %.4e mJ at the end, smallest %.2e mJ; "
              "strain energy %.2e mJ\n",
              u, dissipated, smallest_work, cube.problem().strain_energy());
  EXPECT_NEAR(u, 0.0, 1e-7);
  EXPECT_GE(smallest_work, -1e-12);
  EXPECT_GT(dissipated, 1e-6);
}
