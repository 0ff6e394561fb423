// Scene cases against closed forms and independent computations; run
// serially and on 2 ranks (tests/CMakeLists.txt). Run folders go under
// $NCT_TEST_OUT (default: test-runs).
#include <cmath>
#include <cstdlib>
#include <fstream>
#include <functional>
#include <gtest/gtest.h>

#include "eye/geometry.h"
#include "helpers.h"

namespace
{

using namespace nct::test;

/// Cauchy stresses (axial, lateral) of the HGO law of forms/hgo.py under
/// F = diag(l1, l2, l2), fibres along the axis:
/// sigma = kappa ln J / J I + dev(tau_bar) / J,
/// tau_bar = 2 C10 b_bar + 2 psi4' (F_bar a) (x) (F_bar a).
std::array<double, 2> hgo_uniaxial_stress(double l1, double l2, double c10, double k1,
                                          double k2, double kappa)
{
  const double J = l1 * l2 * l2;
  const double b1 = std::pow(J, -2.0 / 3) * l1 * l1, b2 = std::pow(J, -2.0 / 3) * l2 * l2;
  const double E4 = b1 - 1; // Ibar4 - 1
  const double psi4 = E4 > 0 ? k1 * E4 * std::exp(k2 * E4 * E4) : 0.0;
  const double t1 = 2 * c10 * b1 + 2 * psi4 * b1, t2 = 2 * c10 * b2;
  const double mean = (t1 + 2 * t2) / 3;
  const double vol = kappa * std::log(J) / J;
  return {vol + (t1 - mean) / J, vol + (t2 - mean) / J};
}

/// Stretches (l1, l2) under a uniaxial Cauchy stress T: sigma_22 = 0 is
/// solved for l2 inside a bisection on l1.
std::array<double, 2> hgo_uniaxial_stretches(double T, double c10, double k1, double k2,
                                             double kappa)
{
  auto lateral = [&](double l1)
  {
    return bisect([&](double l2)
                  { return hgo_uniaxial_stress(l1, l2, c10, k1, k2, kappa)[1]; },
                  0.5, 1.5);
  };
  double l1 = bisect(
      [&](double l1)
      { return hgo_uniaxial_stress(l1, lateral(l1), c10, k1, k2, kappa)[0] - T; },
      0.7, 1.5);
  return {l1, lateral(l1)};
}

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

// Saint Venant-Kirchhoff (the linear_elastic law) in uniaxial tension:
// S22 = 0 gives E22 = -nu E11 exactly, and sigma11 = l1 E E11 / l2^2 with
// Green strains E_ii = (l_i^2 - 1)/2.
TEST(LinearElastic, UniaxialTension)
{
  const double E = 1.0, nu = 0.3, T = 150 * mmHg;
  auto summary = run_scene("tests/scenes/hgo_uniaxial.toml", "linear_elastic_tension",
                           {"material.tissue.model=linear_elastic",
                            "material.tissue.youngs_modulus=1.0",
                            "material.tissue.poisson_ratio=0.3"});
  auto lateral = [&](double l1) { return std::sqrt(1 - nu * (l1 * l1 - 1)); };
  const double l1 = bisect(
      [&](double l1)
      { return l1 * E * 0.5 * (l1 * l1 - 1) / std::pow(lateral(l1), 2) - T; },
      1.0, 1.5);
  const auto u = summary["steps"].back()["probe_0_displacement_mm"];
  EXPECT_NEAR(1 + u[0].get<double>(), l1, 1e-8);
  EXPECT_NEAR(1 + u[1].get<double>(), lateral(l1), 1e-8);
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
  const double exact = nct::eye::derive(nct::eye::Geometry{}).cavity_volume;
  const double meshed = summary["cavity_volume_reference_mm3"].get<double>();
  std::printf("eye cavity: meshed %.4f mm3, analytic %.4f mm3 (%.3f%%)\n", meshed, exact,
              100 * (meshed / exact - 1));
  EXPECT_NEAR(meshed / exact, 1.0, 5e-3);
  EXPECT_EQ(summary["symmetry_factor"].get<int>(), 4);
}

// With the internal structures, two cavities: each meshed volume against
// the analytic one, and together with the diaphragm they fill the merged
// cavity of the eye without internal structures. Closed and pressed,
// each holds its own volume while both pressures rise (the lens-zonule
// diaphragm passes part of the push on).
TEST(Eye, InternalStructuresMakeTwoClosedCavities)
{
  // A moderate IOP keeps this case short (the shipped scene goes to 10).
  auto summary = run_scene("scenes/eye-internal.toml", "eye_internal",
                           {"inflate.iop=6.0", "inflate.steps=2", "cavity.model=\"closed\"",
                            "press.pressure=20.0", "press.profile=\"gaussian\"",
                            "press.steps=1", "output.fields=false"});
  ASSERT_EQ(summary["status"], "converged");
  nct::eye::Geometry g;
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
}

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
