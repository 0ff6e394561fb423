// Closed cavities (volume-constraint multipliers) and the zero-pressure
// geometry; run serially and on 2 ranks (tests/CMakeLists.txt). The
// cavity's algebra does not depend on the dimension: the eye's cases run on
// its axisymmetric section (3D: Puff.ClosedEyeThroughThePuff, the whole
// timeline on the quarter eye).
#include <cmath>
#include <gtest/gtest.h>

#include "settings/settings.h"

#include <dolfinx/la/petsc.h>

#include "cavity/cavity.h"
#include "eye/geometry.h"
#include "helpers.h"
#include "run/air_block.h"
#include "run/model.h"
#include "run/solid_block.h"

namespace
{

using namespace nct::test;

/// The eye's section closed at 15 mmHg and pressed on the cornea (a
/// gaussian patch).
const std::vector<std::string> press_case
    = {"mesh.dimension=\"axisymmetric\"", "zero_pressure.enabled=false", "mesh.layers=3",
       "inflate.steps=3",  "press.pressure=60.0", "press.steps=2", "output.fields=false"};

std::vector<std::string> with(std::vector<std::string> sets,
                              const std::vector<std::string>& more)
{
  sets.insert(sets.end(), more.begin(), more.end());
  return sets;
}

/// Observed order of convergence from the last three residuals above the
/// round-off floor: log(r2/r1) / log(r1/r0). The floor, 1e-11 N, is ten
/// times the smallest residual the section's solves reach.
double observed_rate(const nlohmann::json& residuals)
{
  std::vector<double> r;
  const double floor = 1e-11;
  for (const auto& v : residuals)
    if (v.get<double>() > floor)
      r.push_back(v.get<double>());
  if (r.size() < 3)
    return 0;
  const std::size_t n = r.size();
  return std::log(r[n - 1] / r[n - 2]) / std::log(r[n - 2] / r[n - 3]);
}

} // namespace

// (a) + (b): the closed cavity holds its volume to 1e-10 while the press
// raises its pressure, and full Newton on the bordered system converges
// quadratically.
TEST(Cavity, ClosedCavityHoldsVolumeUnderPress)
{
  auto summary = run_scene("scenes/cavity-press.toml", "cavity_closed",
                           with(press_case, {"solver.jacobian=every_iteration"}));
  ASSERT_EQ(summary["status"], "converged");
  const double held = summary["cavity_volume_closed_mm3"].get<double>();
  double previous = 15.0;
  for (const auto& step : summary["steps"])
  {
    if (step["phase"] != "press")
      continue;
    const double V = step["cavity_volume_mm3"].get<double>();
    const double p = step["cavity_pressure_mmHg"].get<double>();
    const double rate = observed_rate(step["newton_residuals"]);
    std::printf("press %.2f: IOP %.4f mmHg, volume %.10f mm3 (relative change %.2e), "
                "Newton rate %.2f over %zu iterations\n",
                step["load_fraction"].get<double>(), p, V, V / held - 1, rate,
                step["newton_residuals"].size() - 1);
    EXPECT_LT(std::abs(V / held - 1), 1e-10);
    EXPECT_GT(p, previous + 0.5); // the push raises the IOP
    EXPECT_GT(rate, 1.8);
    previous = p;
  }
}

// The multiplier is the pressure: an open cavity held at the closed run's
// final pressure, under the same press, reaches the same state (the solid
// is hyperelastic, so the path does not matter) and the closed volume.
TEST(Cavity, ClosedPressureIsTheOpenEquilibrium)
{
  auto closed = run_scene("scenes/cavity-press.toml", "cavity_closed_reuse", press_case);
  const double p = closed["cavity_pressure_mmHg"].get<double>();
  const double held = closed["cavity_volume_closed_mm3"].get<double>();
  auto open = run_scene("scenes/cavity-press.toml", "cavity_open_at_closed_pressure",
                        with(press_case, {"cavity.model=\"constant_pressure\"",
                                          "inflate.iop=" + std::to_string(p)}));
  ASSERT_EQ(open["status"], "converged");
  const double apex_closed = closed["apex_displacement_mm"].get<double>();
  const double apex_open = open["apex_displacement_mm"].get<double>();
  std::printf("closed: IOP 15 -> %.6f mmHg, apex %.8f mm; open at that IOP: apex %.8f mm, "
              "volume %.6f vs held %.6f mm3\n",
              p, apex_closed, apex_open, open["cavity_volume_mm3"].get<double>(), held);
  // std::to_string keeps 6 decimals of the pressure: 1e-6 mmHg.
  EXPECT_NEAR(apex_open, apex_closed, 1e-6);
  EXPECT_NEAR(open["cavity_volume_mm3"].get<double>() / held, 1.0, 1e-8);
  // The same press on the constant-IOP eye pushes the apex farther in.
  auto at_15 = run_scene("scenes/cavity-press.toml", "cavity_open",
                         with(press_case, {"cavity.model=\"constant_pressure\""}));
  std::printf("constant IOP: apex %.5f mm, closed: %.5f mm\n",
              at_15["apex_displacement_mm"].get<double>(), apex_closed);
  EXPECT_LT(at_15["apex_displacement_mm"].get<double>(), apex_closed - 0.01);
}

namespace
{

/// The bordered Jacobian [K B; C D] of `system` at its current (x, y)
/// against central differences of (R, G) along (w, q), at eps = 1e-2, 1e-3
/// and 1e-4: per eps the relative errors of the displacement rows and of
/// each constraint row. They fall as eps^2 until round-off if and only if
/// the Jacobian is consistent: expect_second_order() checks that.
std::vector<std::vector<double>> bordered_errors(nct::solid::Problem& problem, nct::solver::System& system,
                                    const dolfinx::la::Vector<double>& w,
                                    const std::vector<double>& q)
{
  auto& u = *problem.u->x();
  const std::size_t ny = q.size();
  // J [w; q] = [K w + B q; C . w + D q]
  dolfinx::la::petsc::Matrix K(problem.create_matrix(), false);
  system.jacobian(K.mat());
  dolfinx::la::Vector<double> Jw(u.map(), 3);
  Vec w_petsc = dolfinx::la::petsc::create_vector_wrap(w);
  Vec Jw_petsc = dolfinx::la::petsc::create_vector_wrap(Jw);
  MatMult(K.mat(), w_petsc, Jw_petsc);
  VecDestroy(&w_petsc);
  VecDestroy(&Jw_petsc);
  std::vector<dolfinx::la::Vector<double>> B(ny, w), C(ny, w);
  std::vector<double> D(ny * ny, 0.0);
  system.border(B, C, D);
  const std::int32_t owned = u.map()->size_local() * 3;
  // |K w|^2, then per unknown |B_i q_i|^2 and C_i . w
  std::vector<double> sums(1 + 2 * ny, 0.0);
  for (std::int32_t i = 0; i < owned; ++i)
  {
    sums[0] += std::pow(Jw.array()[i], 2);
    for (std::size_t k = 0; k < ny; ++k)
    {
      sums[1 + k] += std::pow(B[k].array()[i] * q[k], 2);
      Jw.mutable_array()[i] += B[k].array()[i] * q[k];
      sums[1 + ny + k] += C[k].array()[i] * w.array()[i];
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, sums.data(), static_cast<int>(sums.size()), MPI_DOUBLE, MPI_SUM,
                MPI_COMM_WORLD);
  std::vector<double> Jg(ny);
  for (std::size_t k = 0; k < ny; ++k)
  {
    Jg[k] = sums[1 + ny + k];
    for (std::size_t j = 0; j < ny; ++j)
      Jg[k] += D[k * ny + j] * q[j];
    // Each border is a real part of the product checked below.
    std::printf("unknown %zu: |B q| / |K w| = %.3e\n", k, std::sqrt(sums[1 + k] / sums[0]));
    EXPECT_GT(std::sqrt(sums[1 + k] / sums[0]), 0.1);
  }

  const dolfinx::la::Vector<double> u0(u);
  const std::vector<double> y0 = *system.y;
  auto residual_at = [&](double t, dolfinx::la::Vector<double>& b, std::vector<double>& g)
  {
    for (std::size_t i = 0; i < u.array().size(); ++i)
      u.mutable_array()[i] = u0.array()[i] + t * w.array()[i];
    for (std::size_t k = 0; k < ny; ++k)
      (*system.y)[k] = y0[k] + t * q[k];
    system.residual(b, g);
  };
  dolfinx::la::Vector<double> bp(u.map(), 3), bm(u.map(), 3);
  std::vector<double> gp(ny), gm(ny);
  std::vector<std::vector<double>> errors;
  for (double eps : {1e-2, 1e-3, 1e-4})
  {
    residual_at(eps, bp, gp);
    residual_at(-eps, bm, gm);
    double norms[2] = {0, 0}; // |FD - J w|^2, |FD|^2
    for (std::int32_t i = 0; i < owned; ++i)
    {
      const double fd = (bp.array()[i] - bm.array()[i]) / (2 * eps);
      norms[0] += std::pow(fd - Jw.array()[i], 2);
      norms[1] += fd * fd;
    }
    MPI_Allreduce(MPI_IN_PLACE, norms, 2, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
    std::vector<double> rows = {std::sqrt(norms[0] / norms[1])};
    std::printf("bordered Jacobian vs central differences, eps %.0e: displacement rows %.2e",
                eps, rows[0]);
    for (std::size_t k = 0; k < ny; ++k)
    {
      const double fd_g = (gp[k] - gm[k]) / (2 * eps);
      rows.push_back(std::abs(fd_g - Jg[k]) / std::abs(fd_g));
      std::printf(", constraint row %zu %.2e", k, rows.back());
    }
    std::printf(" (relative)\n");
    errors.push_back(rows);
  }
  for (std::size_t i = 0; i < u.array().size(); ++i)
    u.mutable_array()[i] = u0.array()[i];
  *system.y = y0;
  return errors;
}

/// Every row's error below 1e-6 at eps = 1e-4, and falling at least
/// 50-fold from eps = 1e-2 to 1e-3 (second order: 100-fold) in every row
/// whose error at 1e-2 is above the round-off floor (1e-9; a row nearly
/// linear along the direction sits on it from the start).
void expect_second_order(const std::vector<std::vector<double>>& errors)
{
  for (std::size_t r = 0; r < errors[0].size(); ++r)
  {
    EXPECT_LT(errors[2][r], 1e-6) << "row " << r;
    if (errors[0][r] > 1e-9)
      EXPECT_LT(errors[1][r], 0.02 * errors[0][r]) << "row " << r;
  }
  EXPECT_GT(errors[0][0], 1e-9); // the displacement rows' truncation error shows
}

/// The coarse eye of scenes/cavity-press.toml (one layer, fibres off:
/// their tension-only switch makes R only once differentiable), with
/// `more` overrides, pressed by a Gaussian 100 mmHg patch.
nct::Model pressed_eye(const std::vector<std::string>& more)
{
  std::vector<std::string> sets = {"zero_pressure.enabled=false", "mesh.layers=1",
                                   "material.cornea.k1=0.0", "material.limbus.k1=0.0"};
  sets.insert(sets.end(), more.begin(), more.end());
  auto s = nct::read(MPI_COMM_WORLD,
                     std::filesystem::path(NCT_SOURCE_DIR) / "scenes/cavity-press.toml", sets);
  nct::Model model = nct::make_model(MPI_COMM_WORLD, s);
  auto& problem = model.solid->problem;
  problem.set_press_profile([](const std::array<double, 3>& x)
                              { return std::exp(-(x[0] * x[0] + x[2] * x[2]) / 4.5); });
  problem.set_press(100 * mmHg);
  return model;
}

/// A smooth, large state u and a smooth direction w on the quarter eye
/// (through the dof coordinates, so that every rank sees the same
/// fields), w normal to the symmetry planes, where the Jacobian's
/// Dirichlet rows and columns are identity; with `clamped` also zero on
/// the cut plane.
dolfinx::la::Vector<double> smooth_state(nct::solid::Problem& problem, bool clamped)
{
  const double cut_y = nct::scene::defaults<nct::eye::Geometry>().cut_y;
  auto V = problem.u->function_space();
  const std::vector<double> X = V->tabulate_dof_coordinates(false);
  auto& u = *problem.u->x();
  dolfinx::la::Vector<double> w(u);
  for (std::size_t i = 0; i < u.array().size(); ++i)
  {
    const double* x = &X[3 * (i / 3)];
    const int j = static_cast<int>(i % 3);
    u.mutable_array()[i] = 0.05 * std::sin(0.3 * x[0] + 0.2 * x[1] + j) * (x[1] + 12) / 24;
    const double normal = j == 0 ? x[0] : j == 2 ? x[2] : 1.0;
    w.mutable_array()[i] = 0.01 * std::cos(0.5 * x[2] - 0.4 * x[1] + 2 * j)
                           * (clamped ? x[1] - cut_y : 1.0) * normal;
  }
  return w;
}

} // namespace

// (b) The bordered Jacobian [K B; C 0] against central differences of
// (R, G) on a coarse eye, at a large pressed state. The fibres are off:
// their tension-only switch makes R only once differentiable, so central
// differences across it converge at first order whatever the Jacobian.
TEST(Cavity, BorderedJacobianMatchesFiniteDifferences)
{
  nct::Model model = pressed_eye({});
  auto& problem = model.solid->problem;
  nct::cavity::Closed closed(problem, {20 * mmHg});
  const auto w = smooth_state(problem, true);
  auto system = closed.system();
  // Direction in the pressure [MPa]: large, so that B q weighs as much as
  // K w in the product (the eye's wall is stiff against its cavity load).
  expect_second_order(bordered_errors(problem, system, w, {10.0}));
}

// The same in the dynamics, on springs, with the humor's mass
// (forms/humor_inertia.py): the border gains the humor's axial inertial
// force, with its own D; its load and tangent (the wall's and the lid's
// moments) are checked with the rest. The cut moves (w is not zero there).
TEST(Cavity, HumorInertiaJacobianMatchesFiniteDifferences)
{
  nct::Model model
      = pressed_eye({"support.model=\"springs\"", "cavity.humor_inertia=\"translation\""});
  auto& problem = model.solid->problem;
  nct::cavity::Closed closed(problem, {20 * mmHg});
  problem.start_dynamics({5.0, 0.8, 0.0}); // a long step: the mass does not hide the rest
  const auto w = smooth_state(problem, false);
  auto system = closed.system();
  ASSERT_EQ(system.y->size(), 2u); // the pressure and the axial force
  (*system.y)[1] = 50.0; // [N]: large, so that the tangent's f / V term weighs
  expect_second_order(bordered_errors(problem, system, w, {10.0, 200.0}));
}

// (c) The zero-pressure geometry of the nearly incompressible thick sphere
// against the closed form: the stress-free radii (A0, B0) whose inflation
// to 30 mmHg gives the meshed sphere (a, b) = (1, 1.5), with
// B0^3 - A0^3 = b^3 - a^3 and p(a / A0) = 30 mmHg.
TEST(ZeroPressure, ThickSphereMatchesClosedForm)
{
  auto summary = run_scene("tests/scenes/sphere_inflation.toml", "sphere_zero_pressure",
                           {"zero_pressure.enabled=true", "mesh.size_max=0.24"});
  ASSERT_EQ(summary["status"], "converged");
  const double a = 1.0, b = 1.5, mu = 2 * 0.005, p = 30 * mmHg;
  auto outer = [&](double A0) { return std::cbrt(A0 * A0 * A0 + b * b * b - a * a * a); };
  const double A0 = bisect([&](double A0) { return sphere_pressure(a / A0, A0, outer(A0), mu) - p; },
                           0.5, 1.0);
  const double A0_fe = summary["probe_reference_mm"]["probe_0"][0].get<double>();
  const double B0_fe = summary["probe_reference_mm"]["probe_1"][1].get<double>();
  std::printf("sphere zero-pressure: %d iterations; A0 FE %.6f exact %.6f; B0 FE %.6f "
              "exact %.6f; round trip %.2e mm\n",
              summary["zero_pressure_iterations"].get<int>(), A0_fe, A0, B0_fe, outer(A0),
              summary["zero_pressure_round_trip_max_mm"].get<double>());
  // As the forward inflation at this mesh size (2.5% of la - 1).
  EXPECT_NEAR((a - A0_fe) / (a - A0), 1.0, 0.05);
  EXPECT_NEAR((b - B0_fe) / (b - outer(A0)), 1.0, 0.05);
  EXPECT_LE(summary["zero_pressure_round_trip_max_mm"].get<double>(), 1e-4);
}

// (c) Round trip on the eye: inflating the stress-free geometry from rest
// gives back the imaged one within zero_pressure.tolerance, at a low, a
// normal and a high IOP; the apex rises from its stress-free place to the
// imaged apex. Reusing the fixed point's last inflation (the default) gives
// the ramp's state with fewer Newton iterations.
TEST(ZeroPressure, EyeRoundTrip)
{
  const double apex_y = nct::eye::derive(nct::scene::defaults<nct::eye::Geometry>()).apex_y;
  const std::vector<std::string> eye
      = {"mesh.dimension=\"axisymmetric\"", "mesh.layers=2", "inflate.steps=2",
         "press.pressure=0.0", "output.fields=false"};
  double previous = 0;
  for (int iop : {8, 15, 22})
  {
    auto summary = run_scene("scenes/cavity-press.toml", "zero_pressure_" + std::to_string(iop),
                             with(eye, {"inflate.iop=" + std::to_string(iop),
                                        "zero_pressure.round_trip=\"ramp\""}));
    ASSERT_EQ(summary["status"], "converged");
    const double round_trip = summary["zero_pressure_round_trip_max_mm"].get<double>();
    const double apex_rest = summary["probe_reference_mm"]["apex"][1].get<double>();
    const double rise = summary["apex_displacement_mm"].get<double>();
    std::printf("IOP %d mmHg: zero-pressure in %d iterations; round trip %.2e mm (max), "
                "%.2e mm (rms); stress-free apex %.5f mm, inflated %.7f, imaged %.7f\n",
                iop, summary["zero_pressure_iterations"].get<int>(), round_trip,
                summary["zero_pressure_round_trip_rms_mm"].get<double>(), apex_rest,
                apex_rest + rise, apex_y);
    EXPECT_LE(round_trip, 1e-4);
    EXPECT_NEAR(apex_rest + rise, apex_y, 1e-4);
    EXPECT_GT(rise, previous); // more pressure, more stress-free offset
    previous = rise;
    if (iop != 15)
      continue;
    auto reuse = run_scene("scenes/cavity-press.toml", "zero_pressure_reuse",
                           with(eye, {"inflate.iop=15"}));
    ASSERT_EQ(reuse["status"], "converged");
    std::printf("reused: round trip %.2e mm, apex rise %.8f mm (ramp %.8f); %d Newton "
                "iterations (ramp %d)\n",
                reuse["zero_pressure_round_trip_max_mm"].get<double>(),
                reuse["apex_displacement_mm"].get<double>(), rise,
                reuse["newton_iterations"].get<int>(), summary["newton_iterations"].get<int>());
    EXPECT_LE(reuse["zero_pressure_round_trip_max_mm"].get<double>(), 1e-4);
    EXPECT_NEAR(reuse["apex_displacement_mm"].get<double>(), rise, 1e-6);
    EXPECT_LT(reuse["newton_iterations"].get<int>(), summary["newton_iterations"].get<int>());
  }
}

// The linear-solve strategies are ways to the same state: full Newton,
// the kept factorisation (modified Newton, its border kept with it), and
// GMRES on the exact Jacobian preconditioned by the kept factorisation
// reach the same closed-cavity press to the Newton tolerance; the kept
// ones factorise less. The increment test stops earlier, within its
// tolerance of the same state where the state is path-independent (the
// open cavity: closing it would freeze the inflation's error into the
// held volume). On P1, to keep it cheap.
TEST(Solver, StrategiesReachTheSameState)
{
  const auto press_case = with(::press_case, {"fem.degree=1"});
  auto full = run_scene("scenes/cavity-press.toml", "solver_full",
                        with(press_case, {"solver.jacobian=\"every_iteration\""}));
  auto reuse = run_scene("scenes/cavity-press.toml", "solver_reuse",
                         with(press_case, {"solver.jacobian=\"reuse\""}));
  auto krylov = run_scene("scenes/cavity-press.toml", "solver_krylov",
                          with(press_case, {"solver.jacobian=\"krylov\""}));
  const auto open = with(press_case, {"solver.jacobian=\"every_iteration\"",
                                      "cavity.model=\"constant_pressure\""});
  auto open_full = run_scene("scenes/cavity-press.toml", "solver_open", open);
  auto increment = run_scene("scenes/cavity-press.toml", "solver_increment",
                             with(open, {"solver.increment_tol=1e-5"}));
  const double apex = full["apex_displacement_mm"].get<double>();
  const double iop = full["cavity_pressure_mmHg"].get<double>();
  for (const auto* s : {&full, &reuse, &krylov, &open_full, &increment})
  {
    ASSERT_EQ((*s)["status"], "converged");
    std::printf("apex %.10f mm, IOP %.8f mmHg: %d Newton iterations, %d Jacobians, %d "
                "factorisations, %d linear solves, %d Krylov iterations\n",
                (*s)["apex_displacement_mm"].get<double>(),
                (*s)["cavity_pressure_mmHg"].get<double>(), (*s)["newton_iterations"].get<int>(),
                (*s)["jacobians"].get<int>(), (*s)["factorisations"].get<int>(),
                (*s)["linear_solves"].get<int>(), (*s)["krylov_iterations"].get<int>());
  }
  for (const auto* s : {&reuse, &krylov})
  {
    EXPECT_NEAR((*s)["apex_displacement_mm"].get<double>(), apex, 1e-9);
    EXPECT_NEAR((*s)["cavity_pressure_mmHg"].get<double>(), iop, 1e-7);
    EXPECT_LT((*s)["factorisations"].get<int>(), full["factorisations"].get<int>());
  }
  // GMRES iterates on the kept factorisation: more Krylov iterations than solves.
  EXPECT_GT(krylov["krylov_iterations"].get<int>(), krylov["linear_solves"].get<int>());
  EXPECT_EQ(krylov["jacobians"].get<int>(), krylov["newton_iterations"].get<int>());
  EXPECT_NEAR(increment["apex_displacement_mm"].get<double>(),
              open_full["apex_displacement_mm"].get<double>(), 1e-5);
  EXPECT_LT(increment["newton_iterations"].get<int>(), open_full["newton_iterations"].get<int>());
}
