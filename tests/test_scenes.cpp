// Scene cases against closed forms and independent computations; run
// serially and on 2 ranks (tests/CMakeLists.txt). Run folders go under
// $NCT_TEST_OUT (default: test-runs).
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <functional>
#include <gtest/gtest.h>

#include "settings/settings.h"

#include "eye/geometry.h"
#include "helpers.h"
#include "run/air_block.h"
#include "run/model.h"
#include "run/solid_block.h"

namespace
{

using namespace nct::test;

} // namespace

// Tension with the fibres along the load: the homogeneous FE solution is
// exact, so it must match the closed form to the Newton tolerance.
TEST(Hgo, UniaxialTensionAlongFibres)
{
  auto summary = run_scene("tests/scenes/hgo_uniaxial.toml", "hgo_tension");
  const auto u = summary["steps"].back()["probe_0_displacement_mm"];
  auto [l1, l2] = hgo_uniaxial_stretches(150 * mmHg, 0.05, 0.010, 100, 5.0);
  std::printf("HGO tension: FE stretches %.10f %.10f, closed form %.10f %.10f\n",
              1 + u[0].get<double>(), 1 + u[1].get<double>(), l1, l2);
  EXPECT_NEAR(1 + u[0].get<double>(), l1, 1e-8);
  EXPECT_NEAR(1 + u[1].get<double>(), l2, 1e-8);
  EXPECT_NEAR(u[1].get<double>(), u[2].get<double>(), 1e-10);
  // The fibres really load: the isotropic matrix alone would stretch more.
  auto [m1, m2] = hgo_uniaxial_stretches(150 * mmHg, 0.05, 0.0, 100, 5.0);
  (void)m2;
  EXPECT_GT(m1 - l1, 1e-3);
}

// Compression: fibres carry no load, so the response is the matrix's alone.
TEST(Hgo, FibresCarryNoCompression)
{
  auto summary = run_scene("tests/scenes/hgo_uniaxial.toml", "hgo_compression",
                           {"press.pressure=150.0"});
  const auto u = summary["steps"].back()["probe_0_displacement_mm"];
  auto [l1, l2] = hgo_uniaxial_stretches(-150 * mmHg, 0.05, 0.0, 100, 5.0);
  EXPECT_LT(l1, 1.0);
  EXPECT_NEAR(1 + u[0].get<double>(), l1, 1e-8);
  EXPECT_NEAR(1 + u[1].get<double>(), l2, 1e-8);
}

// Dispersed fibres (Gasser, Ogden & Holzapfel 2006) along the load: the
// homogeneous FE solution against the closed form of tests/helpers.h.
TEST(Hgo, DispersedFibresUniaxialTension)
{
  auto summary = run_scene("tests/scenes/hgo_uniaxial.toml", "hgo_dispersed_tension",
                           {"material.tissue.dispersion=0.1"});
  const auto u = summary["steps"].back()["probe_0_displacement_mm"];
  auto [l1, l2] = hgo_uniaxial_stretches(150 * mmHg, 0.05, 0.010, 100, 5.0, Fibres::axial, 0.1);
  auto [a1, a2] = hgo_uniaxial_stretches(150 * mmHg, 0.05, 0.010, 100, 5.0);
  (void)a2;
  std::printf("HGO dispersed tension: FE stretch %.10f, closed form %.10f (aligned %.10f)\n",
              1 + u[0].get<double>(), l1, a1);
  EXPECT_NEAR(1 + u[0].get<double>(), l1, 1e-8);
  EXPECT_NEAR(1 + u[1].get<double>(), l2, 1e-8);
  // Dispersion takes stiffness off the load's direction.
  EXPECT_GT(l1 - a1, 1e-3);
}

// Equibiaxial tension of a cube with one dispersed family along x: the
// three stretches against the closed form; at kappa_f = 1/3 the fibres are
// isotropic and x and y stretch alike.
TEST(Hgo, DispersedFibresEquibiaxialTension)
{
  const double T = 150 * mmHg;
  for (double kf : {0.0, 0.1, 1.0 / 3})
  {
    char name[64], set[64];
    std::snprintf(name, sizeof name, "hgo_equibiaxial_%.3f", kf);
    std::snprintf(set, sizeof set, "material.tissue.dispersion=%.17g", kf);
    auto summary = run_scene("tests/scenes/hgo_uniaxial.toml", name,
                             {set, "boundary.press=[\"x1\", \"y1\"]"});
    const auto u = summary["steps"].back()["probe_0_displacement_mm"];
    auto l = hgo_equibiaxial_stretches(T, {0.05, 0.010, 100, 5.0, kf});
    std::printf("HGO equibiaxial, kappa_f %.3f: FE %.10f %.10f %.10f, closed form %.10f %.10f "
                "%.10f\n",
                kf, 1 + u[0].get<double>(), 1 + u[1].get<double>(), 1 + u[2].get<double>(),
                l[0], l[1], l[2]);
    for (int i = 0; i < 3; ++i)
      EXPECT_NEAR(1 + u[i].get<double>(), l[i], 1e-8) << "kappa_f " << kf << ", axis " << i;
    if (kf < 0.3)
      EXPECT_GT(l[1] - l[0], 1e-3); // the fibres stiffen x
    else
      EXPECT_NEAR(u[0].get<double>(), u[1].get<double>(), 1e-9);
  }
}

// Saint Venant-Kirchhoff in uniaxial tension: S22 = 0 gives
// E22 = -nu E11 exactly, and sigma11 = l1 E E11 / l2^2 with Green strains
// E_ii = (l_i^2 - 1)/2.
namespace
{
double svk_uniaxial_stress(double l1, double E, double nu)
{
  return l1 * E * 0.5 * (l1 * l1 - 1) / (1 - nu * (l1 * l1 - 1));
}
} // namespace

TEST(SaintVenantKirchhoff, UniaxialTension)
{
  const double E = 1.0, nu = 0.3, T = 150 * mmHg;
  auto summary = run_scene("tests/scenes/hgo_uniaxial.toml", "svk_tension",
                           {"material.tissue.model=saint_venant_kirchhoff",
                            "material.tissue.youngs_modulus=1.0",
                            "material.tissue.poisson_ratio=0.3"});
  auto lateral = [&](double l1) { return std::sqrt(1 - nu * (l1 * l1 - 1)); };
  const double l1 = bisect([&](double l1) { return svk_uniaxial_stress(l1, E, nu) - T; },
                           1.0, 1.5);
  const auto u = summary["steps"].back()["probe_0_displacement_mm"];
  EXPECT_NEAR(1 + u[0].get<double>(), l1, 1e-8);
  EXPECT_NEAR(1 + u[1].get<double>(), lateral(l1), 1e-8);
}

namespace
{
/// Compressible neo-Hookean (forms/compressible_neo_hookean.py) under
/// F = diag(l1, l2, l2): Cauchy stresses (mu (l_i^2 - 1) + lambda ln J) / J.
std::array<double, 2> cnh_stress(double l1, double l2, double E, double nu)
{
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  const double J = l1 * l2 * l2;
  return {(mu * (l1 * l1 - 1) + lambda * std::log(J)) / J,
          (mu * (l2 * l2 - 1) + lambda * std::log(J)) / J};
}

/// Stretches (l1, l2) of the compressible neo-Hookean under a uniaxial
/// Cauchy stress T (sigma22 = 0).
std::array<double, 2> cnh_uniaxial_stretches(double T, double E, double nu)
{
  auto lateral = [&](double l1)
  { return bisect([&](double l2) { return cnh_stress(l1, l2, E, nu)[1]; }, 0.2, 5.0); };
  const double l1
      = bisect([&](double l1) { return cnh_stress(l1, lateral(l1), E, nu)[0] - T; }, 0.05, 3.0);
  return {l1, lateral(l1)};
}
} // namespace

// The compressible neo-Hookean cube in uniaxial tension and compression
// against its closed form, at small strain (where it is Hooke's law:
// strain T/E, lateral -nu T/E) and at large compression, past the load
// that Saint Venant-Kirchhoff cannot carry at all.
TEST(CompressibleNeoHookean, UniaxialSmallAndLargeStrain)
{
  const double E = 1.0, nu = 0.3;
  const std::vector<std::string> law = {"material.tissue.model=compressible_neo_hookean",
                                        "material.tissue.youngs_modulus=1.0",
                                        "material.tissue.poisson_ratio=0.3"};
  auto with = [&](std::vector<std::string> extra)
  {
    extra.insert(extra.begin(), law.begin(), law.end());
    return extra;
  };
  // Small strain: 1 mmHg of tension.
  {
    const double T = 1.0 * mmHg;
    auto summary = run_scene("tests/scenes/hgo_uniaxial.toml", "cnh_small",
                             with({"press.pressure=-1.0", "press.steps=1"}));
    const auto u = summary["steps"].back()["probe_0_displacement_mm"];
    auto [l1, l2] = cnh_uniaxial_stretches(T, E, nu);
    EXPECT_NEAR(1 + u[0].get<double>(), l1, 1e-10);
    EXPECT_NEAR(1 + u[1].get<double>(), l2, 1e-10);
    EXPECT_NEAR(u[0].get<double>() / (T / E), 1.0, 1e-3);
    EXPECT_NEAR(-u[1].get<double>() / u[0].get<double>(), nu, 1e-3);
  }
  // Large strain: a compressive 0.25 E (1875 mmHg), 1.55 times the
  // largest compressive Cauchy stress Saint Venant-Kirchhoff can carry.
  const double T = -0.25;
  double svk_limit = 0;
  for (double l = 0.01; l < 1; l += 1e-4)
    svk_limit = std::min(svk_limit, svk_uniaxial_stress(l, E, nu));
  std::printf("Saint Venant-Kirchhoff: largest uniaxial compression %.4f E\n", -svk_limit);
  ASSERT_LT(T, 1.5 * svk_limit);
  auto summary = run_scene("tests/scenes/hgo_uniaxial.toml", "cnh_compression",
                           with({"press.pressure=" + std::to_string(-T / mmHg),
                                 "press.steps=4"}));
  ASSERT_EQ(summary["status"], "converged");
  for (const auto& step : summary["steps"])
  {
    if (step["phase"] != "press")
      continue;
    const auto u = step["probe_0_displacement_mm"];
    auto [l1, l2] = cnh_uniaxial_stretches(step["load_fraction"].get<double>() * T, E, nu);
    EXPECT_NEAR(1 + u[0].get<double>(), l1, 1e-8);
    EXPECT_NEAR(1 + u[1].get<double>(), l2, 1e-8);
  }
  const double l1 = 1 + summary["steps"].back()["probe_0_displacement_mm"][0].get<double>();
  std::printf("compressible neo-Hookean at %.2f E: stretch %.4f\n", T, l1);
  EXPECT_LT(l1, 0.8);
}

// The same compression collapses Saint Venant-Kirchhoff: past its
// largest compressive Cauchy stress there is no equilibrium. The run
// stops with a diagnosis, and the last load it carried is that limit.
TEST(SaintVenantKirchhoff, CollapsesInUniaxialCompression)
{
  const double E = 1.0, nu = 0.3, T = 0.25;
  double limit = 0;
  for (double l = 0.01; l < 1; l += 1e-5)
    limit = std::min(limit, svk_uniaxial_stress(l, E, nu));
  try
  {
    run_scene("tests/scenes/hgo_uniaxial.toml", "svk_compression",
              {"material.tissue.model=saint_venant_kirchhoff",
               "material.tissue.youngs_modulus=1.0", "material.tissue.poisson_ratio=0.3",
               "press.pressure=" + std::to_string(T / mmHg), "press.steps=4"});
    FAIL() << "Saint Venant-Kirchhoff carried a compression past its limit";
  }
  catch (const nct::Diverged& e)
  {
    const std::string what = e.what();
    const auto from = what.find("(from ");
    ASSERT_NE(from, std::string::npos) << what;
    const double carried = std::stod(what.substr(from + 6)) * T;
    std::printf("Saint Venant-Kirchhoff collapsed after %.4f E (limit %.4f E)\n", carried,
                -limit);
    EXPECT_NEAR(carried / -limit, 1.0, 0.01);
  }
}

namespace
{
/// Cauchy stress of a hydrostatic stretch l (J = l^3) under the laws of
/// E and nu: compressible neo-Hookean (mu (l^2 - 1) + lambda ln J) / J;
/// Saint Venant-Kirchhoff 3 K (l^2 - 1) / (2 l).
double hydrostatic_stress(const std::string& law, double l, double E, double nu)
{
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  const double K = lambda + 2 * mu / 3;
  return law == "saint_venant_kirchhoff"
             ? 3 * K * (l * l - 1) / (2 * l)
             : (mu * (l * l - 1) + lambda * 3 * std::log(l)) / (l * l * l);
}

/// Surface and interface radial displacements of a linear elastic ball
/// (radius B, core radius A, bulk and shear moduli K, G of core c and
/// shell s) under an external pressure p: the core is in uniform pressure
/// q, the shell has u = a r + b / r^2; continuity at A and the tractions
/// at A and B fix a, b, q (Timoshenko & Goodier, Theory of Elasticity,
/// 1970, sec. 137).
std::array<double, 2> compound_ball(double A, double B, double Kc, double Ks, double Gs,
                                    double p)
{
  // Unknowns a, b, q: sigma_rr(B) = 3 Ks a - 4 Gs b / B^3 = -p,
  // sigma_rr(A) = 3 Ks a - 4 Gs b / A^3 = -q, a A + b / A^2 = -q A / (3 Kc).
  // Eliminate q: a A + b / A^2 = A (3 Ks a - 4 Gs b / A^3) / (3 Kc).
  const double c1 = A - A * Ks / Kc, c2 = 1 / (A * A) + 4 * Gs / (3 * Kc * A * A);
  // c1 a + c2 b = 0 and 3 Ks a - 4 Gs b / B^3 = -p.
  const double b = -p / (-3 * Ks * c2 / c1 - 4 * Gs / (B * B * B));
  const double a = -c2 * b / c1;
  return {a * B + b / (B * B), a * A + b / (A * A)};
}
} // namespace

// A ball under a hydrostatic follower pressure: a homogeneous dilation,
// exact on any mesh. The compressible neo-Hookean matches its closed form
// at every load step from small strain to J = 0.53. Saint Venant-Kirchhoff
// matches its own only while its shear wave speed stays real,
// sigma > -l mu (l^2 > 3K / (3K + 2 mu): 0.33 MPa here); past it the
// homogeneous state is unstable, and whether Newton stays on it depends on
// the load path (with 8 steps its step cuts found a non-homogeneous state
// 1.5e-4 away; with these 16 it stays): printed, not asserted.
TEST(CompressibleNeoHookean, HydrostaticBall)
{
  const double E = 1.0, nu = 0.45, p = 4.0; // MPa
  const double lambda = E * nu / ((1 + nu) * (1 - 2 * nu)), mu = E / (2 * (1 + nu));
  const double K = lambda + 2 * mu / 3, l_elliptic = std::sqrt(3 * K / (3 * K + 2 * mu));
  const double p_elliptic = -hydrostatic_stress("saint_venant_kirchhoff", l_elliptic, E, nu);
  for (const std::string law : {"compressible_neo_hookean", "saint_venant_kirchhoff"})
  {
    auto summary = run_scene(
        "tests/scenes/ball_pressure.toml", "ball_" + law,
        {"material.core.model=\"" + law + "\"", "material.shell.model=\"" + law + "\"",
         "press.pressure=" + std::to_string(p / mmHg), "press.steps=16"});
    double departure = 0;
    for (const auto& step : summary["steps"])
    {
      if (step["phase"] != "press")
        continue;
      const double load = step["load_fraction"].get<double>() * p;
      const double l = bisect([&](double l) { return hydrostatic_stress(law, l, E, nu) + load; },
                              0.1, 1.0);
      const double lx = 1 + step["probe_0_displacement_mm"][0].get<double>();
      const double lz = 1 + step["probe_1_displacement_mm"][2].get<double>();
      if (law == "compressible_neo_hookean" || load < p_elliptic)
      {
        EXPECT_NEAR(lx, l, 1e-8) << law << " at " << load << " MPa";
        EXPECT_NEAR(lz, l, 1e-8) << law << " at " << load << " MPa";
      }
      departure = std::max({departure, std::abs(lx - l), std::abs(lz - l)});
    }
    const double l = 1 + summary["steps"].back()["probe_0_displacement_mm"][0].get<double>();
    std::printf("%s ball at %.1f E: stretch %.5f, J %.4f; largest departure from the "
                "homogeneous state %.2e (ellipticity lost past %.3f MPa for "
                "Saint Venant-Kirchhoff)\n",
                law.c_str(), p, l, l * l * l, departure, p_elliptic);
  }
}

// A soft core (1/1000 of the shell's modulus, as the lens nucleus in its
// cortex) in a ball under pressure. At 1 mmHg the compressible neo-Hookean
// matches the linear compound-sphere solution (on h = 0.0625; the error
// falls from 3.6 % on h = 0.25) and Saint Venant-Kirchhoff agrees with it
// (both are Hooke's law at small strain); at 1000 mmHg the compressible
// neo-Hookean converges, while Saint Venant-Kirchhoff's core loses its
// shear stiffness under the pressure and collapses.
TEST(CompressibleNeoHookean, SoftCoreBallStaysStable)
{
  const double Es = 1.0, Ec = 1e-3, nu = 0.45;
  const auto moduli = [&](double E)
  { return std::array<double, 2>{E / (3 * (1 - 2 * nu)), E / (2 * (1 + nu))}; };
  const auto exact
      = compound_ball(0.6, 1.0, moduli(Ec)[0], moduli(Es)[0], moduli(Es)[1], 1.0 * mmHg);
  auto small = [&](const std::string& law, const std::string& h)
  {
    auto summary = run_scene("tests/scenes/ball_pressure.toml", "soft_core_small_" + law,
                             {"material.core.model=\"" + law + "\"",
                              "material.shell.model=\"" + law + "\"",
                              "material.core.youngs_modulus=0.001", "press.pressure=1.0",
                              "press.steps=1", "mesh.parameters={h=" + h + "}"});
    const auto& last = summary["steps"].back();
    return std::array<double, 2>{last["probe_0_displacement_mm"][0].get<double>(),
                                 last["probe_2_displacement_mm"][0].get<double>()};
  };
  const auto fine = small("compressible_neo_hookean", "0.0625");
  std::printf("soft core, 1 mmHg: surface %.5e (linear %.5e), core %.5e (linear %.5e)\n",
              fine[0], exact[0], fine[1], exact[1]);
  EXPECT_NEAR(fine[0] / exact[0], 1.0, 0.01);
  EXPECT_NEAR(fine[1] / exact[1], 1.0, 0.01);
  const auto cnh = small("compressible_neo_hookean", "0.25");
  const auto svk = small("saint_venant_kirchhoff", "0.25");
  EXPECT_NEAR(svk[0] / cnh[0], 1.0, 1e-3);
  EXPECT_NEAR(svk[1] / cnh[1], 1.0, 1e-3);

  auto large = run_scene("tests/scenes/ball_pressure.toml", "soft_core_large",
                         {"material.core.youngs_modulus=0.001", "press.pressure=1000.0",
                          "press.steps=8"});
  EXPECT_EQ(large["status"], "converged");
  EXPECT_EQ(large["step_cuts"].get<int>(), 0);
  try
  {
    run_scene("tests/scenes/ball_pressure.toml", "soft_core_large_svk",
              {"material.core.model=\"saint_venant_kirchhoff\"",
               "material.shell.model=\"saint_venant_kirchhoff\"",
               "material.core.youngs_modulus=0.001", "press.pressure=1000.0",
               "press.steps=8"});
    FAIL() << "the Saint Venant-Kirchhoff core carried 1000 mmHg";
  }
  catch (const nct::Diverged& e)
  {
    const std::string what = e.what();
    const auto from = what.find("(from ");
    ASSERT_NE(from, std::string::npos) << what;
    const double carried = std::stod(what.substr(from + 6)) * 1000;
    std::printf("Saint Venant-Kirchhoff soft core collapsed after %.0f mmHg\n", carried);
    EXPECT_LT(carried, 500);
    EXPECT_NE(what.find("in the core"), std::string::npos) << what;
  }
}

// Inflation of a nearly incompressible thick sphere (kappa/mu = 1000)
// against the incompressible closed form, through the external-mesh path,
// at two mesh sizes: the error must fall at about second order (the
// faceted inner surface and the P2 field both converge so).
TEST(NeoHookean, ThickSphereInflation)
{
  const double A = 1.0, B = 1.5, mu = 2 * 0.005, p = 30 * mmHg;
  std::vector<double> errors;
  for (double h : {0.24, 0.12})
  {
    auto summary = run_scene("tests/scenes/sphere_inflation.toml",
                             h == 0.12 ? "sphere" : "sphere_coarse",
                             {"mesh.size_max=" + std::to_string(h)});
    double worst = 0;
    for (const auto& step : summary["steps"])
    {
      const double la = 1 + step["probe_0_displacement_mm"][0].get<double>();
      const double lb = 1 + step["probe_1_displacement_mm"][1].get<double>() / B;
      const double load = step["load_fraction"].get<double>() * p;
      const double la_exact = bisect(
          [&](double l) { return sphere_pressure(l, A, B, mu) - load; }, 1.0, 2.0);
      std::printf("sphere h %.2f: p %.5f MPa  inner stretch FE %.6f exact %.6f\n", h, load,
                  la, la_exact);
      worst = std::max(worst, std::abs(la - la_exact) / (la_exact - 1));
      // The wall keeps its volume (kappa/mu = 1000): b^3 - a^3 = B^3 - A^3.
      EXPECT_NEAR(std::pow(lb * B, 3) - std::pow(la * A, 3), B * B * B - A * A * A,
                  0.01 * (B * B * B - A * A * A));
      // The polyhedral cavity's volume follows the sphere's.
      const double V = step["cavity_volume_mm3"].get<double>();
      EXPECT_NEAR(V / (4.0 / 3 * M_PI * std::pow(la * A, 3)), 1.0, 0.02);
    }
    errors.push_back(worst);
  }
  const double order = std::log(errors[0] / errors[1]) / std::log(2.0);
  std::printf("sphere: relative error of (la - 1): %.3e (h 0.24), %.3e (h 0.12), order %.2f\n",
              errors[0], errors[1], order);
  EXPECT_LT(errors[1], 0.01);
  EXPECT_GT(order, 1.5);
}

// The meshed cavity volume (the dolfinx volume functional on the
// distributed mesh) against the analytic volume of the idealised eye.
TEST(Eye, CavityVolumeMatchesGeometry)
{
  auto summary = run_scene("scenes/inflate.toml", "eye_volume",
                           {"inflate.iop=0.0", "inflate.steps=1", "output.fields=false"});
  const double exact = nct::eye::derive(nct::scene::defaults<nct::eye::Geometry>()).cavity_volume;
  const double meshed = summary["cavity_volume_reference_mm3"].get<double>();
  std::printf("eye cavity: meshed %.4f mm3, analytic %.4f mm3 (%.3f%%)\n", meshed, exact,
              100 * (meshed / exact - 1));
  EXPECT_NEAR(meshed / exact, 1.0, 5e-3);
  EXPECT_EQ(summary["symmetry_factor"].get<int>(), 4);
}

// The cut's lid (forms/support.py) moves with the cut face: a whole-eye
// translation along the axis leaves the closed cavity's volume as it was
// (without the lid it would change by the translation times the lid's
// area, pi (R_inner^2 - cut_y^2) whole eye), and the unit cavity
// pressure's net axial force on the eye vanishes (divergence theorem over
// the wall and the lid).
TEST(Eye, WholeEyeTranslationKeepsTheCavityVolume)
{
  auto s = nct::read(MPI_COMM_WORLD, std::filesystem::path(NCT_SOURCE_DIR) / "scenes/default.toml",
                                   {"mesh.layers=2", "output.fields=false"});
  nct::Model model = nct::make_model(MPI_COMM_WORLD, s);
  auto& problem = model.solid->problem;
  problem.start_dynamics({0.5, 0.8, 0.1}); // the springs take over: the cut may move
  const double before = problem.cavity_volumes()[0];
  const double shift = 0.1; // mm along the axis
  auto u = problem.u->x()->mutable_array();
  for (std::size_t i = 1; i < u.size(); i += 3)
    u[i] = shift;
  const double after = problem.cavity_volumes()[0];
  const auto g = nct::scene::defaults<nct::eye::Geometry>();
  const double inner = g.sclera_outer_radius - g.sclera_thickness;
  const double lid = M_PI * (inner * inner - g.cut_y * g.cut_y);
  dolfinx::la::Vector<double> b(problem.u->x()->map(), 3);
  problem.cavity_load(0, b);
  double force = 0; // the quarter's axial force at unit pressure [N/MPa = mm^2]
  for (std::size_t i = 1; i < b.map()->size_local() * 3; i += 3)
    force += b.array()[i];
  MPI_Allreduce(MPI_IN_PLACE, &force, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  std::printf("translation by %.2f mm: cavity volume %.6f -> %.6f mm3 (change %.2e mm3; without "
              "the lid %.3f mm3); axial force at unit pressure %.3e mm2 (lid area %.2f mm2)\n",
              shift, before, after, after - before, shift * lid, 4 * force, lid);
  // The meshed wall's opening differs from the analytic lid by the
  // polygon's chords (observed on 2 layers: 2e-4 and 7e-4 of the lid).
  EXPECT_LT(std::abs(after - before), 1e-3 * shift * lid);
  EXPECT_LT(std::abs(4 * force), 2e-3 * lid);
}

// With the internal structures, two cavities: each meshed volume against
// the analytic one, and together with the diaphragm they fill the merged
// cavity of the eye without internal structures. Closed and pressed,
// each holds its own volume while both pressures rise (the lens-zonule
// diaphragm passes part of the push on). The same scene as an axisymmetric
// section agrees with the quarter eye: the meshed reference volumes, the
// inflated apex, each cavity's pressure rise under the press and the
// pressed apex.
TEST(Eye, InternalStructuresMakeTwoClosedCavities)
{
  // The scene's eye, inflated to a moderate IOP without its puff.
  const std::vector<std::string> sets
      = {"inflate.iop=6.0", "inflate.steps=2", "cavity.model=\"closed\"", "press.pressure=20.0",
         "press.profile=\"gaussian\"", "press.steps=1", "output.fields=false"};
  auto summary = run_scene("scenes/eye-internal.toml", "eye_internal", sets);
  ASSERT_EQ(summary["status"], "converged");
  auto g = nct::scene::defaults<nct::eye::Geometry>();
  g.internal_structures = true;
  const auto d = nct::eye::derive(g);
  const double aqueous = summary["aqueous_volume_reference_mm3"].get<double>();
  const double vitreous = summary["vitreous_volume_reference_mm3"].get<double>();
  std::printf("aqueous %.4f (analytic %.4f), vitreous %.4f (analytic %.4f) mm3\n", aqueous,
              d.aqueous_volume, vitreous, d.vitreous_volume);
  EXPECT_NEAR(aqueous / d.aqueous_volume, 1.0, 0.01);
  EXPECT_NEAR(vitreous / d.vitreous_volume, 1.0, 0.01);
  EXPECT_LT(aqueous + vitreous, d.cavity_volume);

  // Inflated, the eye grows; the apex moves forward as without the
  // internal structures (they hardly load the cornea).
  nlohmann::json inflated;
  for (const auto& step : summary["steps"])
    if (step["phase"] == "inflate")
      inflated = step;
  EXPECT_GT(inflated["apex_displacement_mm"][1].get<double>(), 0.05);
  EXPECT_GT(inflated["aqueous_volume_mm3"].get<double>(), aqueous);
  EXPECT_GT(inflated["vitreous_volume_mm3"].get<double>(), vitreous);

  // Pressed: (d) each cavity conserves its own volume.
  const auto& pressed = summary["steps"].back();
  ASSERT_EQ(pressed["phase"], "press");
  for (const char* c : {"aqueous", "vitreous"})
  {
    const std::string V = std::string(c) + "_volume_mm3", p = std::string(c) + "_pressure_mmHg";
    const double change
        = pressed[V].get<double>() / summary[std::string(c) + "_volume_closed_mm3"].get<double>()
          - 1;
    std::printf("pressed: %s %.4f mmHg (from %.1f), volume change %.1e\n", c,
                pressed[p].get<double>(), inflated[p].get<double>(), change);
    EXPECT_LT(std::abs(change), 1e-10);
    EXPECT_GT(pressed[p].get<double>(), inflated[p].get<double>() + 0.1);
  }
  EXPECT_LT(pressed["apex_displacement_mm"][1].get<double>(), 0.0); // pushed in

  // The section against the quarter eye.
  auto section_sets = sets;
  section_sets.push_back("mesh.dimension=\"axisymmetric\"");
  const auto section = run_scene("scenes/eye-internal.toml", "eye_internal_section", section_sets);
  ASSERT_EQ(section["status"], "converged");
  const auto at = [](const nlohmann::json& s, const char* phase)
  {
    nlohmann::json last;
    for (const auto& step : s["steps"])
      if (step["phase"] == phase)
        last = step;
    return last;
  };
  for (const char* c : {"aqueous", "vitreous"})
  {
    const std::string V = std::string(c) + "_volume_reference_mm3",
                      p = std::string(c) + "_pressure_mmHg";
    const double dV = section[V].get<double>() / summary[V].get<double>() - 1;
    const double rise_3d = pressed[p].get<double>() - inflated[p].get<double>();
    const double rise = at(section, "press")[p].get<double>() - at(section, "inflate")[p].get<double>();
    std::printf("section: %s reference volume %+.2e of the quarter eye's, pressure rise under "
                "the press %.4f (section) %.4f (3D) mmHg\n",
                c, dV, rise, rise_3d);
    EXPECT_LT(std::abs(dV), 1e-3);
    EXPECT_NEAR(rise / rise_3d, 1.0, 0.03);
  }
  for (const char* phase : {"inflate", "press"})
  {
    const double a = at(section, phase)["apex_displacement_mm"][1].get<double>();
    const double b = at(summary, phase)["apex_displacement_mm"][1].get<double>();
    std::printf("section: %s apex %.5f (section) %.5f (3D) mm\n", phase, a, b);
    EXPECT_NEAR(a / b, 1.0, 0.02);
  }
}

// The eye with its internal structures at the reference data inflates
// over the factorial studies' range of IOP, to 22 mmHg, at 3 and 5
// elements through the thickness: the soft nucleus (E = 0.3 kPa,
// compressible neo-Hookean, nu = 0.49: bulk modulus 37 mmHg) is
// squeezed, not crushed. Saint Venant-Kirchhoff stopped at a limit point
// near 10.6 mmHg (0.6 mmHg on 3 layers).
namespace
{

void inflate_internal_to_22(int layers)
{
  auto summary = run_scene("scenes/eye-internal.toml",
                           "eye_internal_22_l" + std::to_string(layers),
                           {"mesh.layers=" + std::to_string(layers), "inflate.iop=22.0",
                            "inflate.steps=11", "output.fields=false"});
  ASSERT_EQ(summary["status"], "converged");
  const auto& last = summary["steps"].back();
  std::printf("%d layers at 22 mmHg: apex %.4f mm, aqueous %.2f mm3, vitreous %.2f mm3, "
              "%d step cuts\n",
              layers, last["apex_displacement_mm"][1].get<double>(),
              last["aqueous_volume_mm3"].get<double>(), last["vitreous_volume_mm3"].get<double>(),
              summary["step_cuts"].get<int>());
  for (const char* c : {"aqueous", "vitreous"})
  {
    EXPECT_NEAR(last[std::string(c) + "_pressure_mmHg"].get<double>(), 22.0, 1e-9);
    EXPECT_GT(last[std::string(c) + "_volume_mm3"].get<double>(),
              summary[std::string(c) + "_volume_reference_mm3"].get<double>());
  }
  // The cornea bulges as without the internal structures (0.28 mm at
  // 22 mmHg on 3 layers), which carry little of the load.
  EXPECT_GT(last["apex_displacement_mm"][1].get<double>(), 0.2);
  EXPECT_LT(last["apex_displacement_mm"][1].get<double>(), 0.35);
}

} // namespace

TEST(InternalStructures, InflateTo22mmHg) { inflate_internal_to_22(3); }

// Labelled slow (tests/CMakeLists.txt): a minute.
TEST(InternalStructures, InflateTo22mmHgOnFiveLayers) { inflate_internal_to_22(5); }

// The inflation scene end to end; its summary is compared across rank counts.
TEST(Eye, InflateSceneInflates)
{
  auto summary = run_scene("scenes/inflate.toml", "inflate");
  EXPECT_EQ(summary["status"], "converged");
  const double apex = summary["apex_displacement_mm"].get<double>();
  // A pressurised shell bulges forward, by a fraction of a millimetre.
  EXPECT_GT(apex, 0.05);
  EXPECT_LT(apex, 0.5);
  EXPECT_GT(summary["cavity_volume_mm3"].get<double>(),
            summary["cavity_volume_reference_mm3"].get<double>());
}

// output.probes: each probe's history goes to probes.csv (a row per
// converged step, the phase and its time) and its last displacement to
// summary.json by name, equal to the last step's.
TEST(Output, ProbesHistoryAndLastValues)
{
  auto summary = run_scene("tests/scenes/hgo_uniaxial.toml", "probes_history");
  const auto& steps = summary["steps"];
  const auto& last = steps.back()["probe_0_displacement_mm"];
  EXPECT_EQ(summary["probe_displacement_mm"]["probe_0"], last);
  std::ifstream in(out_dir("probes_history") / "probes.csv");
  std::string header, line, row;
  std::getline(in, header);
  EXPECT_EQ(header, "t,phase,probe_0_ux_mm,probe_0_uy_mm,probe_0_uz_mm");
  std::size_t rows = 0;
  while (std::getline(in, line))
    row = line, ++rows;
  ASSERT_EQ(rows, steps.size());
  std::stringstream cells(row);
  std::vector<std::string> values;
  for (std::string cell; std::getline(cells, cell, ',');)
    values.push_back(cell);
  ASSERT_EQ(values.size(), 5u);
  EXPECT_NEAR(std::stod(values[0]), steps.back()["time"].get<double>(), 1e-9);
  EXPECT_EQ(values[1], steps.back()["phase"].get<std::string>());
  for (int k = 0; k < 3; ++k)
    EXPECT_NEAR(std::stod(values[2 + k]), last[k].get<double>(),
                1e-9 * std::max(1.0, std::abs(last[k].get<double>())));
}
