// Biomarker extraction on synthetic profiles with known answers.
#include <cmath>
#include <functional>
#include <set>
#include <gtest/gtest.h>

#include "biomarkers/biomarkers.h"
#include "biomarkers/registry.h"
#include "biomarkers/record.h"

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

// y = 2 + b x^2 is fitted exactly: the concave radius is 1 / (2 b); a
// convex or flat apex has none.
TEST(Biomarkers, ConcaveRadius)
{
  auto concave = sample(0.05, [](double x) { return 2.0 + 0.04 * x * x; }, 0.013);
  const auto radius = nct::biomarkers::concave_radius(concave, 1.5);
  ASSERT_TRUE(radius);
  EXPECT_NEAR(*radius, 12.5, 1e-9); // least squares of an exact parabola: round-off only
  auto convex = sample(0.05, [](double x) { return 2.0 - 0.064 * x * x; }, 0.013);
  EXPECT_FALSE(nct::biomarkers::concave_radius(convex, 1.5));
  auto flat = sample(0.05, [](double) { return 2.0; }, 0.013);
  EXPECT_FALSE(nct::biomarkers::concave_radius(flat, 1.5));
}

// A concavity that is an arc of a circle of radius Rc (centre on the outer
// side) between rims at +-a, falling as a cornea beyond them: the circle
// over the samples between the two highest points is the arc's, to round-off.
TEST(Biomarkers, ConcavityRadius)
{
  const double Rc = 8.0, a = 2.4, y0 = -1.0;
  auto arc = [&](double x) { return y0 + Rc - std::sqrt(Rc * Rc - x * x); };
  auto dent = [&](double x)
  {
    const double s = std::abs(x);
    return s <= a ? arc(x) : arc(a) - (s - a) * (s - a) / 7.8 - 0.3 * (s - a);
  };
  for (double h : {0.05, 0.013})
  {
    auto p = sample(h, dent, 0.3 * h);
    const auto radius = nct::biomarkers::concavity_radius(p);
    ASSERT_TRUE(radius);
    std::printf("concavity radius, step %.3f: %.9f mm (exact %.1f)\n", h, *radius, Rc);
    EXPECT_NEAR(*radius, Rc, 1e-9);
    nct::biomarkers::Definitions d; // the rule by default: the whole concavity
    EXPECT_NEAR(*nct::biomarkers::concave_radius(p, d), Rc, 1e-9);
  }
  // A concavity shallower than the depth asked (the flatness) is flat: the
  // arc's sag to the rims is Rc - sqrt(Rc^2 - a^2) = 0.3717 mm.
  auto p = sample(0.013, dent, 0.0039);
  EXPECT_TRUE(nct::biomarkers::concavity_radius(p, 0.36)); // the rims read within a sample
  EXPECT_FALSE(nct::biomarkers::concavity_radius(p, 0.38));
  // A cornea only pushed flatter (convex) or not at all has no concavity.
  auto convex = sample(0.05, [](double x) { return -x * x / (2 * 7.8); }, 0.013);
  EXPECT_FALSE(nct::biomarkers::concavity_radius(convex));
  auto flatter = sample(0.05, [](double x) { return -x * x / (2 * 20.0); }, 0.013);
  EXPECT_FALSE(nct::biomarkers::concavity_radius(flatter));
}

// A cornea of radius 7.8 mm pushed in by D0 exp(-x^2 / (2 w^2)), its nodes
// moved sideways (sampled 0.011 mm off the rest's columns): the DA ratio at
// d is exp(d^2 / (2 w^2)).
TEST(Biomarkers, DaRatio)
{
  const double R = 7.8, D0 = 1.0, w = 1.5, h = 0.02;
  auto cornea = [&](double x) { return -x * x / (2 * R); };
  auto rest = sample(h, cornea, 0.007);
  auto dent = [&](double x) { return D0 * std::exp(-x * x / (2 * w * w)); };
  auto pushed = sample(h, [&](double x) { return cornea(x) - dent(x); }, 0.007 + 0.011);
  for (double d : {1.0, 2.0})
  {
    const auto ratio = nct::biomarkers::da_ratio(rest, pushed, d);
    ASSERT_TRUE(ratio);
    const double exact = std::exp(d * d / (2 * w * w));
    // Each height read between samples errs by at most h^2/8 |y''|: 1/R
    // at rest, 1/R + D0/w^2 pushed; the deformations by the sum, e, and
    // the ratio by e (1 + ratio) / (the flanks' deformation).
    const double e = h * h / 8 * (2 / R + D0 / (w * w));
    const double flank = dent(d);
    std::printf("DA ratio at %.0f mm: %.6f (exact %.6f, bound %.1e)\n", d, *ratio, exact,
                e * (1 + exact) / flank);
    EXPECT_NEAR(*ratio, exact, e * (1 + exact) / flank);
  }
  // No deformation of the flanks: no ratio.
  EXPECT_FALSE(nct::biomarkers::da_ratio(rest, rest, 1.0));
}

// SP-A1 = (the apex air pressure at A1 - the IOP at rest) / the deflection at A1.
TEST(Biomarkers, StiffnessParameterA1)
{
  const auto sp = nct::biomarkers::stiffness_parameter_a1(95.0, 15.0, 0.25);
  ASSERT_TRUE(sp);
  EXPECT_DOUBLE_EQ(*sp, 320.0);
  EXPECT_FALSE(nct::biomarkers::stiffness_parameter_a1(95.0, 15.0, 0.0));
  EXPECT_FALSE(nct::biomarkers::stiffness_parameter_a1(95.0, 15.0, -0.1));
}

// A synthetic puff with known biomarkers: apex u(t) = -A sin(pi t / T),
// whole-eye motion w(t) = -B sin(pi (t - t0) / T2) from t0 on, and a
// profile that is exactly y = u + b(t) x^2 near the axis (|x| <= h) and
// falls as -c (|x| - h)^4 beyond, with b(t) = -b0 + (b0 + b1) sin(pi t / T):
// applanation where b = 0, at t1 = T / pi asin(b0 / (b0 + b1)) and T - t1.
TEST(Biomarkers, SyntheticPuff)
{
  const double T = 20, A = 1.1, B = 0.1, t0 = 1, T2 = 24, b0 = 0.08, b1 = 0.3, h = 0.5,
               c = 0.02;
  const double tol = 0.01, dt = 1.0 / 4.33; // Corvis: 4330 frames/s
  const double radius_window = 0.45;        // within |x| <= h: the fits are exact
  auto b = [&](double t) { return -b0 + (b0 + b1) * std::sin(M_PI * t / T); };
  auto u = [&](double t) { return -A * std::sin(M_PI * t / T); };
  auto whole_eye = [&](double t) { return -B * std::sin(M_PI * std::max(t - t0, 0.0) / T2); };
  std::vector<double> t, apex, whole;
  std::vector<Profile> profiles;
  for (double s = 0; s <= T; s += dt)
  {
    t.push_back(s), apex.push_back(u(s)), whole.push_back(whole_eye(s));
    profiles.push_back(sample(0.02, [&](double x)
                              { return u(s) + b(s) * std::min(x * x, h * h)
                                       + 2 * b(s) * h * std::max(std::abs(x) - h, 0.0)
                                       + plateau(x, h, c, 4); }, 0.007));
  }
  nct::biomarkers::Definitions d;
  d.apex_window = 0.4, d.radius_rule = nct::biomarkers::RadiusRule::window;
  d.radius_window = radius_window, d.flatness = tol, d.frame_interval = dt;
  const auto r = nct::biomarkers::analyse(t, profiles, apex, whole, d);
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
  EXPECT_NEAR(r.deflection_amplitude, A + whole_eye(T / 2), 1e-4);
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

  // The intervals, within the A1, A2 and HC tolerances above.
  EXPECT_NEAR(r.a1_a2_interval(), T - 2 * t1, 4e-3);
  EXPECT_NEAR(r.a1_hc_interval(), T / 2 - t1, 3e-3);
  // The deflection at the A1 and A2 found: u and w linear between frames
  // err by at most dt^2/8 |u'' - w''|.
  const double linear = dt * dt / 8 * (A * std::pow(M_PI / T, 2) + B * std::pow(M_PI / T2, 2));
  for (const auto* a : {&r.a1, &r.a2})
  {
    std::printf("deflection at %.4f ms: %.6f mm (exact %.6f)\n", a->time, a->deflection,
                whole_eye(a->time) - u(a->time));
    EXPECT_NEAR(a->deflection, whole_eye(a->time) - u(a->time), linear);
  }

  // HC radius 1 / (2 b(T/2)) = 1 / (2 b1): b read linearly between frames
  // errs by at most dt^2/8 |b''|, the radius by that over 2 b1^2.
  const double db = dt * dt / 8 * (b0 + b1) * std::pow(M_PI / T, 2);
  ASSERT_TRUE(r.hc_radius);
  std::printf("HC radius %.6f mm (exact %.6f, bound %.1e)\n", *r.hc_radius, 1 / (2 * b1),
              db / (2 * b1 * b1));
  EXPECT_NEAR(*r.hc_radius, 1 / (2 * b1), db / (2 * b1 * b1));
  // The largest 2 b(t) of the frames, 2 b1 at T/2: the nearest frame, at
  // most dt/2 away, falls short by at most (b0 + b1) (pi dt / (2 T))^2.
  const double off_peak = (b0 + b1) * std::pow(M_PI * dt / (2 * T), 2);
  std::printf("max inverse radius %.6f /mm (exact %.6f, bound %.1e)\n", r.max_inverse_radius,
              2 * b1, off_peak);
  EXPECT_LE(r.max_inverse_radius, 2 * b1 + 1e-12);
  EXPECT_GE(r.max_inverse_radius, 2 * b1 - off_peak);
  // The integral of 2 b(t) from t1 to T - t1:
  // 2 (-b0 (T - 2 t1) + (b0 + b1) 2 T / pi cos(pi t1 / T)). A trapezoid of
  // width h <= dt errs by at most h^3/12 max |f''|, f'' = -2 (b0 + b1) (pi / T)^2
  // sin(pi t / T): in all at most dt^2/12 (T - 2 t1) 2 (b0 + b1) (pi / T)^2.
  const double integral = 2 * (-b0 * (T - 2 * t1) + (b0 + b1) * 2 * T / M_PI
                                                        * std::cos(M_PI * t1 / T));
  const double trapezoids = dt * dt / 12 * (T - 2 * t1) * 2 * (b0 + b1) * std::pow(M_PI / T, 2);
  // The device counts time in frames: the integral over the frame interval.
  ASSERT_TRUE(r.integrated_radius);
  std::printf("integrated radius %.9f /mm (exact %.9f, bound %.4e)\n", *r.integrated_radius,
              integral / dt, trapezoids / dt);
  EXPECT_NEAR(*r.integrated_radius, integral / dt, trapezoids / dt);

  // The deformation y(x, 0) - y(x, t) is sin(pi t / T) (A - (b0 + b1) g(x))
  // with g = x^2 for |x| <= h, h^2 + 2 h (|x| - h) beyond: a constant ratio
  // A / (A - (b0 + b1) g(d)), g linear at 1 and 2 mm. On the axis the
  // samples at -0.013 and 0.007 mm read g(0) as at most 0.02^2 / 4.
  for (auto [d, ratio] : {std::pair{1.0, r.da_ratio_1mm}, {2.0, r.da_ratio_2mm}})
  {
    const double flank = A - (b0 + b1) * (h * h + 2 * h * (d - h));
    ASSERT_TRUE(ratio);
    std::printf("DA ratio %.0f mm %.6f (exact %.6f)\n", d, *ratio, A / flank);
    EXPECT_NEAR(*ratio, A / flank, (b0 + b1) * 0.02 * 0.02 / 4 / flank);
  }

  // The whole eye's deepest, B at t0 + T2 / 2: the parabola through three
  // samples of a sine B cos(omega s) misplaces its vertex by at most
  // omega^2 dt^3 / (36 sqrt 3) and lowers it by at most 3 B (omega dt)^4 / 128,
  // to leading order in omega dt (0.03): the next is (omega dt)^2 smaller.
  const double omega = M_PI / T2;
  ASSERT_TRUE(r.whole_eye_movement_time);
  std::printf("whole-eye movement %.12f mm at %.9f ms (exact %.12f at %.9f)\n",
              r.whole_eye_movement_max, *r.whole_eye_movement_time, B, t0 + T2 / 2);
  EXPECT_NEAR(r.whole_eye_movement_max, B,
              3 * B * std::pow(omega * dt, 4) / 128 * (1 + std::pow(omega * dt, 2)));
  EXPECT_NEAR(*r.whole_eye_movement_time, t0 + T2 / 2,
              omega * omega * std::pow(dt, 3) / (36 * std::sqrt(3.0))
                  * (1 + std::pow(omega * dt, 2)));
}

// A stiff cornea that only flattens (b stays negative) while the eye moves
// outwards: no applanation, no concavity, no inward whole-eye motion.
TEST(Biomarkers, StiffPuff)
{
  const double T = 20, A = 0.3, B = 0.05, b0 = 0.08, dt = 1.0 / 4.33;
  std::vector<double> t, apex, whole;
  std::vector<Profile> profiles;
  for (double s = 0; s <= T; s += dt)
  {
    const double u = -A * std::sin(M_PI * s / T), b = -b0 + 0.5 * b0 * std::sin(M_PI * s / T);
    t.push_back(s), apex.push_back(u), whole.push_back(B * std::sin(M_PI * s / T));
    profiles.push_back(sample(0.02, [&](double x) { return u + b * x * x; }, 0.007));
  }
  nct::biomarkers::Definitions d;
  d.apex_window = 0.4, d.flatness = 0.01, d.frame_interval = dt;
  for (auto rule : {nct::biomarkers::RadiusRule::window, nct::biomarkers::RadiusRule::concavity})
  {
    d.radius_rule = rule;
    const auto r = nct::biomarkers::analyse(t, profiles, apex, whole, d);
    EXPECT_FALSE(r.applanated);
    EXPECT_FALSE(r.hc_radius);
    EXPECT_EQ(r.max_inverse_radius, 0.0);
    EXPECT_FALSE(r.integrated_radius);
    EXPECT_FALSE(r.da_ratio_1mm);
    EXPECT_FALSE(r.da_ratio_2mm);
    EXPECT_EQ(r.whole_eye_movement_max, 0.0);
    EXPECT_FALSE(r.whole_eye_movement_time);
  }
}

// The frames between two steps: the cubic Hermite interpolant of the nodes'
// positions and velocities is exact for a cubic motion, where the linear
// blend misses the midpoint by h^2 |u''| / 8 (a deepest frame set between
// two steps comes out too shallow).
TEST(Biomarkers, FramesBetweenStepsFollowACubicMotion)
{
  const double h = 0.5, t0 = 1.0;
  // One node per motion: x(t), y(t) cubics, different per node.
  auto motion = [](int node, double t)
  {
    const double c = 0.1 * (node + 1);
    return std::array<double, 4>{1 + c * t - 0.3 * t * t + 0.02 * t * t * t,  // x
                                 c - 2 * c * t * t + 0.05 * t * t * t,          // y
                                 c - 0.3 * 2 * t + 0.06 * t * t,                // vx
                                 -4 * c * t + 0.15 * t * t};                    // vy
  };
  auto state = [&](double t)
  {
    nct::biomarkers::SectionState s;
    for (int n = 0; n < 3; ++n)
    {
      const auto m = motion(n, t), m0 = motion(n, 0);
      s.X.push_back(m0[0]), s.x.push_back(m[0]), s.y.push_back(m[1]);
      s.uy.push_back(m[1] - m0[1]), s.vx.push_back(m[2]), s.vy.push_back(m[3]);
    }
    return s;
  };
  const auto a = state(t0), b = state(t0 + h);
  for (double s : {0.0, 0.25, 0.5, 0.8, 1.0})
  {
    const auto f = nct::biomarkers::hermite(a, b, s, h), exact = state(t0 + s * h);
    for (int n = 0; n < 3; ++n)
    {
      EXPECT_NEAR(f.x[n], exact.x[n], 1e-14);
      EXPECT_NEAR(f.y[n], exact.y[n], 1e-14);
      EXPECT_NEAR(f.uy[n], exact.uy[n], 1e-14);
      EXPECT_NEAR(f.vx[n], exact.vx[n], 1e-13);
      EXPECT_NEAR(f.vy[n], exact.vy[n], 1e-13);
      EXPECT_EQ(f.X[n], a.X[n]);
    }
  }
  // The linear blend at the midpoint, for scale: off by h^2 |y''| / 8.
  const auto mid = state(t0 + h / 2);
  const double linear = 0.5 * (a.y[2] + b.y[2]);
  EXPECT_GT(std::abs(linear - mid.y[2]), 1e-2);
}

// The registry: each key once; a cavity's name fills "<cavity>"; a key
// outside it is refused when a summary is written.
TEST(Biomarkers, Registry)
{
  std::set<std::string> keys;
  for (const auto& e : nct::biomarkers::registry())
    EXPECT_TRUE(keys.insert(e.key).second) << e.key << " twice";
  ASSERT_NE(nct::biomarkers::find("aqueous_pressure_max_mmHg"), nullptr);
  EXPECT_EQ(nct::biomarkers::find("aqueous_pressure_max_mmHg")->key, "<cavity>_pressure_max_mmHg");
  EXPECT_EQ(nct::biomarkers::find("lens_pressure_max_mmHg"), nullptr);
  EXPECT_EQ(nct::biomarkers::find("hc_time_ms")->unit, "ms");
  EXPECT_FALSE(nct::biomarkers::find("wall_s")->reading);
  nlohmann::json summary;
  nct::biomarkers::put(summary, "hc_time_ms", 16.5);
  EXPECT_EQ(summary["hc_time_ms"], 16.5);
  EXPECT_THROW(nct::biomarkers::put(summary, "hc_time", 16.5), std::logic_error);
}
