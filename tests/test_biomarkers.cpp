// Biomarker extraction on synthetic profiles with known answers.
#include <cmath>
#include <gtest/gtest.h>

#include "biomarkers/biomarkers.h"

namespace
{

using nct::biomarkers::Profile;

/// Samples of y(x) on [-6, 6] with step h, offset so that no sample need
/// fall on the features.
Profile sample(double h, const std::function<double(double)>& y, double offset = 0.0)
{
  Profile p;
  for (double x = -6 + offset; x <= 6; x += h)
    p.x.push_back(x), p.y.push_back(y(x));
  return p;
}

/// Flat for |x| <= a, then falling as c (|x| - a)^n.
double plateau(double x, double a, double c, int n)
{
  const double s = std::max(std::abs(x) - a, 0.0);
  return -c * std::pow(s, n);
}

} // namespace

// |y - y(0)| <= tol on |x| <= a + (tol / c)^(1/n).
TEST(Biomarkers, FlatLength)
{
  const double a = 1.0, c = 0.5, tol = 0.02;
  const double exact = 2 * (a + std::sqrt(tol / c));
  for (double h : {0.1, 0.01})
  {
    auto p = sample(h, [&](double x) { return 3.0 + plateau(x, a, c, 2); }, 0.3 * h);
    const double length = nct::biomarkers::flat_length(p, tol);
    std::printf("flat length, step %.2f: %.5f mm (exact %.5f)\n", h, length, exact);
    EXPECT_NEAR(length, exact, h * h * 2); // linear interpolation of a parabola
  }
  // A profile that is not flat anywhere has a zero-length flat segment
  // (up to the interpolation to the tolerance).
  auto round = sample(0.01, [](double x) { return -x * x; });
  EXPECT_NEAR(nct::biomarkers::flat_length(round, 1e-4), 2 * std::sqrt(1e-4), 1e-4);
}

// Two humps at +-d: y = -(x^2 - d^2)^2.
TEST(Biomarkers, PeakDistance)
{
  const double d = 2.3;
  auto p = sample(0.07, [&](double x) { return -std::pow(x * x - d * d, 2); }, 0.011);
  const double distance = nct::biomarkers::peak_distance(p);
  std::printf("peak distance: %.5f mm (exact %.5f)\n", distance, 2 * d);
  EXPECT_NEAR(distance, 2 * d, 2e-3);
  // A convex profile has one highest point, the apex: no distance, even
  // with the even-odd ripple of quadratic elements' nodes on its flanks.
  auto convex = sample(0.25, [](double x) { return -0.05 * x * x; }); // x = 0 is sample 24
  for (std::size_t i = 1; i < convex.y.size(); i += 2)
    convex.y[i] += 1e-3;
  EXPECT_EQ(nct::biomarkers::peak_distance(convex), 0.0);
}

TEST(Biomarkers, ApexCurvatureAndCrossings)
{
  auto p = sample(0.05, [](double x) { return 1.0 - 0.3 * x * x; }, 0.013);
  EXPECT_NEAR(nct::biomarkers::apex_curvature(p, 0.5), -0.3, 1e-12);
  std::vector<double> t, f;
  for (double s = 0; s < 7; s += 0.01)
    t.push_back(s), f.push_back(std::sin(s));
  auto down = nct::biomarkers::crossings(t, f, false), up = nct::biomarkers::crossings(t, f, true);
  ASSERT_EQ(down.size(), 1u);
  ASSERT_EQ(up.size(), 1u);
  EXPECT_NEAR(down[0], M_PI, 1e-5);
  EXPECT_NEAR(up[0], 2 * M_PI, 1e-5);
}

// A synthetic puff with known biomarkers: apex u(t) = -A sin(pi t / T),
// whole-eye motion -B sin(pi t / T), and a profile that is exactly
// y = u + b(t) x^2 near the axis (|x| <= h) and falls as -c (|x| - h)^4
// beyond, with b(t) = -b0 + (b0 + b1) sin(pi t / T): applanation where
// b = 0, at t1 = T / pi asin(b0 / (b0 + b1)) and T - t1.
TEST(Biomarkers, SyntheticPuff)
{
  const double T = 20, A = 1.1, B = 0.1, b0 = 0.08, b1 = 0.3, h = 0.5, c = 0.02;
  const double tol = 0.01, dt = 1.0 / 4.33; // Corvis: 4330 frames/s
  auto b = [&](double t) { return -b0 + (b0 + b1) * std::sin(M_PI * t / T); };
  std::vector<double> t, apex, whole;
  std::vector<Profile> profiles;
  for (double s = 0; s <= T; s += dt)
  {
    const double u = -A * std::sin(M_PI * s / T);
    t.push_back(s), apex.push_back(u), whole.push_back(-B * std::sin(M_PI * s / T));
    profiles.push_back(sample(0.02, [&](double x)
                              { return u + b(s) * std::min(x * x, h * h)
                                       + 2 * b(s) * h * std::max(std::abs(x) - h, 0.0)
                                       + plateau(x, h, c, 4); }, 0.007));
  }
  const auto r = nct::biomarkers::analyse(t, profiles, apex, whole, 0.4, tol);
  const double t1 = T / M_PI * std::asin(b0 / (b0 + b1));
  std::printf("HC %.4f ms (exact %.4f), DA %.5f, deflection %.5f; A1 %.4f ms (exact %.4f), "
              "length %.4f mm, velocity %.5f; A2 %.4f ms (exact %.4f), velocity %.5f; "
              "peak distance %.4f mm\n",
              r.hc_time, T / 2, r.deformation_amplitude, r.deflection_amplitude, r.a1.time, t1,
              r.a1.length, r.a1.apex_velocity, r.a2.time, T - t1, r.a2.apex_velocity,
              r.peak_distance);
  ASSERT_TRUE(r.applanated);
  EXPECT_NEAR(r.hc_time, T / 2, 1e-3);
  EXPECT_NEAR(r.deformation_amplitude, A, 1e-4);
  EXPECT_NEAR(r.deflection_amplitude, A - B, 1e-4);
  EXPECT_NEAR(r.a1.time, t1, 2e-3);
  EXPECT_NEAR(r.a2.time, T - t1, 2e-3);
  // At applanation the centre is exactly flat: the tolerance is reached
  // where c (|x| - h)^4 = tol.
  const double flat = 2 * (h + std::pow(tol / c, 0.25));
  EXPECT_NEAR(r.a1.length, flat, 2e-3);
  EXPECT_NEAR(r.a2.length, flat, 2e-3);
  const double v1 = -A * M_PI / T * std::cos(M_PI * t1 / T);
  EXPECT_NEAR(r.a1.apex_velocity, v1, 2e-3 * std::abs(v1));
  EXPECT_NEAR(r.a2.apex_velocity, -v1, 2e-3 * std::abs(v1));
  // At HC (frame nearest T/2) the humps sit where the slope 2 b1 h - 4 c
  // (x - h)^3 vanishes.
  const double hump = h + std::cbrt(2 * b(T / 2) * h / (4 * c));
  EXPECT_NEAR(r.peak_distance, 2 * hump, 0.02);
}
