// Generalised-alpha elastodynamics (forms/dynamics.py) on the neo-Hookean
// square in plane strain (time integration does not depend on the
// dimension): released from a stretched equilibrium by a smooth unload, it
// vibrates. Observed order of accuracy, energy conservation without
// damping, and the decay rate of mass-proportional damping.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>

#include <dolfinx/la/petsc.h>

#include "cavity/cavity.h"
#include "helpers.h"
#include "puff/load.h"
#include "run/air_block.h"
#include "run/model.h"
#include "run/solid_block.h"
#include "run/stepper.h"

namespace
{

using namespace nct::test;

struct Sample
{
  double t, u, energy; // time [ms], probe x-displacement [mm], total energy [mJ]
};

/// The square stretched by a 150 mmHg pull on x = 1, in equilibrium,
/// to be released over `release` ms by a twice continuously
/// differentiable ramp p = p0 (1 - 10 s^3 + 15 s^4 - 6 s^5), s = t / release.
struct StretchedSquare
{
  /// The communicator, the PETSc options set to the defaults (MUMPS LU) first.
  static MPI_Comm default_solver()
  {
    nct::solver::set_petsc_options({});
    return MPI_COMM_WORLD;
  }
  static constexpr double p0 = -150 * mmHg;
  explicit StretchedSquare(double release)
      : settings(nct::read(MPI_COMM_WORLD, std::filesystem::path(NCT_SOURCE_DIR)
                                               / "tests/scenes/square_plane.toml")),
        model(nct::make_model(MPI_COMM_WORLD, settings)), problem(model.solid->problem),
        A(problem.create_matrix(), false), newton(default_solver(), A.mat()),
        open(problem), probe(problem, {{1.0, 1.0, 0.0}}), release(release)
  {
    for (double f : {0.5, 1.0})
    {
      problem.set_press(f * p0);
      EXPECT_TRUE(newton.solve(open.system(), newton_settings).converged);
    }
  }
  double pressure(double t) const
  {
    const double x = std::min(t / release, 1.0);
    return p0 * (1 - x * x * x * (10 - 15 * x + 6 * x * x));
  }
  const nct::solver::NewtonSettings newton_settings{25, 1e-10, 1e-10, 0, false};
  nct::Input settings;
  nct::Model model;
  nct::solid::Problem& problem;
  dolfinx::la::petsc::Matrix A;
  nct::solver::Newton newton;
  nct::cavity::Open open;
  nct::solid::Probes probe;
  double release;
};

/// The stretched square released and followed to `end` ms with time step dt.
std::vector<Sample> vibrate(double dt, double end, double rho_inf, double damping,
                            double release)
{
  StretchedSquare square(release);
  auto& problem = square.problem;
  problem.start_dynamics({dt, rho_inf, damping});
  std::vector<Sample> samples;
  const int steps = static_cast<int>(std::lround(end / dt));
  for (int n = 0; n < steps; ++n)
  {
    problem.set_press(square.pressure((n + problem.load_level()) * dt));
    auto report = square.newton.solve(square.open.system(), square.newton_settings);
    if (!report.converged)
    {
      ADD_FAILURE() << "step " << n << ": " << report.reason << ", last residual "
                    << report.residuals.back();
      break;
    }
    problem.advance();
    const double u = square.probe.displacement()[0][0];
    samples.push_back({(n + 1) * dt, u, problem.strain_energy() + problem.kinetic_energy()});
  }
  return samples;
}

/// The same release marched by nct's Stepper from the first step dt, its
/// steps adapted to `tolerance` [mm] (0: fixed): the probe after each step.
struct March
{
  std::vector<double> t, u, dt;
  int rejections = 0;
};
March march(double dt, double end, double tolerance, double release)
{
  StretchedSquare square(release);
  auto& problem = square.problem;
  const nct::dynamics::TimeStep step{dt, 0.5, 0.1};
  problem.start_dynamics(step);
  nct::io::RunFolder folder(MPI_COMM_WORLD, out_dir("adaptive_square"));
  nct::Stepper stepper(square.newton_settings, 12, nct::Stepper::Predictor::extrapolate, folder);
  stepper.control = {tolerance, 0.05};
  const nct::Stepper::Dynamics dynamics{
      [&](const nct::dynamics::TimeStep& s) { problem.set_time_step(s); },
      [&] { return problem.load_level(); }, [&] { problem.advance(); },
      [&] { problem.predict(); }, [&] { return problem.local_error(); }};
  March m{{0}, {square.probe.displacement()[0][0]}, {0}};
  stepper.march(square.newton, "release", 0, end, step, dynamics, square.open.system(),
                [&](double t) { problem.set_press(square.pressure(t)); },
                [&](double t, double h, const nct::solver::NewtonReport&)
                {
                  m.t.push_back(t);
                  m.dt.push_back(h);
                  m.u.push_back(square.probe.displacement()[0][0]);
                });
  m.rejections = stepper.rejections;
  return m;
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

// Adaptive steps (dynamics.tolerance): Stepper::march keeps the local
// error estimate (beta - 1/6) dt^2 max|a_n+1 - a_n| below the tolerance,
// halving and doubling the step. For a second-order integrator the
// steps then grow as tol^(1/3) and the global error falls as tol^(2/3):
// a tolerance 8 times smaller takes about twice the steps and has about a
// quarter of the error, here against a 32 times finer fixed march. The
// steps follow the motion: short while the release drives it, longer in
// the free vibration after.
TEST(Dynamics, AdaptiveStepsFollowTheirTolerance)
{
  const double end = 0.32, release = 0.2, fine = 0.02 / 32;
  const March reference = march(fine, end, 0, release);
  ASSERT_EQ(reference.t.size(), 513u);
  // The reference between its steps: the parabola through three.
  auto at = [&](double t)
  {
    const std::size_t i = std::clamp<long>(std::lround(t / fine), 1, 511);
    const double x = t / fine - static_cast<double>(i);
    const auto& u = reference.u;
    return u[i] + 0.5 * x * (u[i + 1] - u[i - 1]) + 0.5 * x * x * (u[i + 1] - 2 * u[i] + u[i - 1]);
  };
  struct Result
  {
    double error;
    std::size_t steps;
    int rejections;
    double shortest, longest;
  };
  auto adaptive = [&](double tolerance)
  {
    const March m = march(0.02, end, tolerance, release);
    Result r{0, m.t.size() - 1, m.rejections, 1e300, 0};
    for (std::size_t i = 1; i < m.t.size(); ++i)
    {
      r.error = std::max(r.error, std::abs(m.u[i] - at(m.t[i])));
      r.shortest = std::min(r.shortest, m.dt[i]), r.longest = std::max(r.longest, m.dt[i]);
    }
    std::printf("tolerance %.1e mm: %zu steps (%d taken again), dt %.5f to %.5f ms; largest "
                "error %.3e mm\n",
                tolerance, r.steps, m.rejections, r.shortest, r.longest, r.error);
    return r;
  };
  const Result coarse = adaptive(1e-5), tight = adaptive(1e-5 / 8);
  const double steps = static_cast<double>(tight.steps) / coarse.steps,
               error = coarse.error / tight.error;
  std::printf("tolerance / 8: %.2f times the steps (tol^-1/3: 2), the error / %.2f (tol^2/3: 4)\n",
              steps, error);
  EXPECT_GT(steps, 1.6);
  EXPECT_LT(steps, 2.5);
  EXPECT_GT(error, 2.5);
  EXPECT_LT(error, 6.5);
  EXPECT_LT(tight.rejections, 0.1 * tight.steps);
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

// A rigid body on the support's springs and dashpots (forms/support.py):
// the stiff cube, held on y = 0 by K and C and set moving along y by a
// short push on y = 1, vibrates as m x'' + (alpha m + C) x' + K x = 0
// (alpha the mass-proportional damping): at omega_d = sqrt(K / m -
// sigma^2), decaying as exp(-sigma t) with sigma = (alpha + C / m) / 2.
// The cube's own modes are 100x faster: it moves as a rigid body.
TEST(Support, RigidBodyOnSpringsVibratesAtTheClosedForm)
{
  const double rho = 1e-3, K = 1.0, C = 0.004, alpha = 0.2; // g/mm^3, N/mm, N ms/mm, 1/ms
  auto s = nct::read(MPI_COMM_WORLD, 
      std::filesystem::path(NCT_SOURCE_DIR) / "tests/scenes/hgo_uniaxial.toml",
      {"fem.degree=1", "material.tissue.model=\"neo_hookean\"", "material.tissue.c10=1000.0",
       "material.tissue.kappa=10000.0", "material.tissue.density=" + std::to_string(rho),
       "boundary.symmetry=[\"x0\", \"z0\"]", "boundary.fixed=[\"y0\"]",
       "boundary.press=[\"y1\"]", "support.model=\"springs\"",
       "support.stiffness=" + std::to_string(K), "support.damping=" + std::to_string(C)});
  nct::Model model = nct::make_model(MPI_COMM_WORLD, s);
  auto& problem = model.solid->problem;
  dolfinx::la::petsc::Matrix A(problem.create_matrix(), false);
  nct::solver::set_petsc_options({});
  nct::solver::Newton newton(MPI_COMM_WORLD, A.mat());
  nct::cavity::Open open(problem);
  const nct::solver::NewtonSettings settings{25, 1e-10, 1e-10, 0, false};
  const double dt = 0.01, push = 0.05, end = 2.0; // ms
  problem.start_dynamics({dt, 0.8, alpha});
  const nct::solid::Probes probe(problem, {{0.5, 0.5, 0.5}});
  std::vector<double> t, y;
  for (int n = 0; (n + 1) * dt <= end + 1e-12; ++n)
  {
    const double tn = (n + problem.load_level()) * dt;
    const double x = std::min(tn / push, 1.0);
    problem.set_press(tn < push ? 100 * mmHg * std::pow(std::sin(M_PI * x), 2) : 0);
    const auto report = newton.solve(open.system(), settings);
    ASSERT_TRUE(report.converged) << "step " << n << ": " << report.reason << ", residuals "
                                  << report.residuals.front() << " to "
                                  << report.residuals.back();
    problem.advance();
    t.push_back((n + 1) * dt), y.push_back(probe.displacement()[0][1]);
  }
  const Oscillation o = damped_oscillation(t, y, 2 * push, dt);
  ASSERT_GE(o.periods, 3u);
  ASSERT_GE(o.peaks, 4u);
  const double omega_d = o.omega, sigma = o.sigma;
  const double m = 4 * rho; // the whole model: the quarter is the unit cube
  const double sigma_exact = 0.5 * (alpha + C / m);
  const double omega_exact = std::sqrt(K / m - sigma_exact * sigma_exact);
  std::printf("rigid body on springs: omega_d %.5f rad/ms (closed form %.5f), decay %.5f 1/ms "
              "(closed form %.5f), %zu periods\n",
              omega_d, omega_exact, sigma, sigma_exact, o.periods);
  // Generalised alpha at omega dt = 0.16: period error O((omega dt)^2) ~ 2e-3,
  // algorithmic damping O((omega dt)^3): below the tolerances.
  EXPECT_NEAR(omega_d, omega_exact, 5e-3 * omega_exact);
  EXPECT_NEAR(sigma, sigma_exact, 2e-2 * sigma_exact);
}

// The Gaussian scene's whole timeline (zero pressure, inflate, close, rest,
// puff) on a coarse mesh: the closed humor keeps its volume through the
// puff while the IOP rises; the eye at rest does not move; the cornea
// goes in and comes back out, so both applanations and the highest
// concavity are found in order; the frames sample the prescribed
// pressure's peak. Its summary is compared across rank counts.
TEST(Puff, ClosedEyeThroughThePuff)
{
  auto summary = run_scene("scenes/puff-gaussian.toml", "puff",
                           {"mesh.layers=2", "puff.duration=16.0", "output.fields=false",
                            "solver.atol=1e-11"});
  ASSERT_EQ(summary["status"], "converged");
  const double held = summary["cavity_volume_closed_mm3"].get<double>();
  double worst = 0, iop_max = 0;
  int puff_steps = 0;
  for (const auto& step : summary["steps"])
    if (step["phase"] == "puff" || step["phase"] == "rest")
    {
      puff_steps += step["phase"] == "puff";
      worst = std::max(worst, std::abs(step["cavity_volume_mm3"].get<double>() / held - 1));
      iop_max = std::max(iop_max, step["cavity_pressure_mmHg"].get<double>());
    }
  std::printf("puff: %d steps, largest volume change %.1e, IOP max %.3f mmHg (frames: %.3f)\n",
              puff_steps, worst, iop_max, summary["iop_max_mmHg"].get<double>());
  EXPECT_EQ(puff_steps, 32); // 16 ms at 0.5 ms, no step cut
  EXPECT_LT(worst, 1e-10);
  EXPECT_GT(iop_max, 15.0 + 2.0); // the puff pressurises the closed eye
  EXPECT_LE(summary["iop_max_mmHg"].get<double>(), iop_max + 1e-12);
  EXPECT_LT(summary["rest_drift_mm"].get<double>(), 1e-9);

  // 16 ms at 4330 frames/s: frames 0 to 69.
  EXPECT_EQ(summary["frames"].get<int>(), 70);
  // The gaussian's peak (65 mmHg at 10 ms) lies between frames 43 and 44.
  const double dt_frame = 1e3 / 4330, t43 = 43 * dt_frame;
  EXPECT_NEAR(summary["apex_pressure_max_mmHg"].get<double>(),
              65.0 * std::exp(-std::pow(t43 - 10.0, 2) / 18.0), 1e-9);

  const double a1 = summary["a1_time_ms"].get<double>(), hc = summary["hc_time_ms"].get<double>(),
               a2 = summary["a2_time_ms"].get<double>();
  const double da = summary["deformation_amplitude_mm"].get<double>();
  std::printf("A1 %.3f ms, HC %.3f ms, A2 %.3f ms; deformation %.4f mm, deflection %.4f mm, "
              "peak distance %.3f mm\n",
              a1, hc, a2, da, summary["deflection_amplitude_mm"].get<double>(),
              summary["peak_distance_mm"].get<double>());
  EXPECT_LT(a1, hc);
  EXPECT_LT(hc, a2);
  // The apex goes in (+ is outwards); it comes in at A1 and out at A2.
  EXPECT_GT(da, 0.1);
  EXPECT_LT(summary["a1_velocity_m_s"].get<double>(), 0);
  EXPECT_GT(summary["a2_velocity_m_s"].get<double>(), 0);
  // Deflection removes the whole-eye motion, which the clamped cut plane
  // keeps small: never more than the deformation's tenth.
  EXPECT_LT(std::abs(summary["whole_eye_motion_hc_mm"].get<double>()), 0.1 * da);
}

// The default scene on a coarse (P1) mesh: the measured pulse on the eye held
// by the orbit's springs and dashpots. The closed humor keeps its volume;
// the eye at rest does not move when the springs take over from the
// clamp; the frames within the pulse's hold see its peak; the whole eye
// retracts under the puff (inwards, after HC) and comes back; every DCR
// parameter is reported. Its summary is compared across rank counts.
TEST(Puff, MeasuredPulseOnTheOrbit)
{
  auto summary = run_scene("scenes/default.toml", "puff_measured",
                           {"fem.degree=1", "output.fields=false", "solver.atol=1e-11"});
  ASSERT_EQ(summary["status"], "converged");
  const double held = summary["cavity_volume_closed_mm3"].get<double>();
  double worst = 0;
  for (const auto& step : summary["steps"])
    if (step["phase"] == "puff" || step["phase"] == "rest")
      worst = std::max(worst, std::abs(step["cavity_volume_mm3"].get<double>() / held - 1));
  EXPECT_LT(worst, 1e-10);
  EXPECT_LT(summary["rest_drift_mm"].get<double>(), 1e-9);
  // The hold lasts 2.07 ms from 10.78 ms: frames fall in it.
  EXPECT_NEAR(summary["apex_pressure_max_mmHg"].get<double>(), 96.4, 1e-9);
  const double a1 = summary["a1_time_ms"].get<double>(), hc = summary["hc_time_ms"].get<double>(),
               a2 = summary["a2_time_ms"].get<double>();
  const double wem = summary["whole_eye_movement_max_mm"].get<double>();
  const double wem_time = summary["whole_eye_movement_time_ms"].get<double>();
  std::printf("A1 %.3f, HC %.3f, A2 %.3f ms; deformation %.4f, deflection %.4f mm; whole eye "
              "%.4f mm at %.2f ms; HC radius %.3f mm, SP-A1 %.1f mmHg/mm\n",
              a1, hc, a2, summary["deformation_amplitude_mm"].get<double>(),
              summary["deflection_amplitude_mm"].get<double>(), wem, wem_time,
              summary["hc_radius_mm"].get<double>(), summary["sp_a1_mmHg_per_mm"].get<double>());
  EXPECT_LT(a1, hc);
  EXPECT_LT(hc, a2);
  // The dashpots delay the retraction past the load's peak.
  EXPECT_GT(wem, 0);
  EXPECT_GT(wem_time, hc);
  for (const char* key : {"hc_radius_mm", "max_inverse_radius_per_mm",
                          "integrated_radius_per_mm", "da_ratio_1mm", "da_ratio_2mm",
                          "a1_a2_interval_ms", "a1_hc_interval_ms", "a1_deflection_mm",
                          "sp_a1_mmHg_per_mm"})
    EXPECT_TRUE(summary.contains(key)) << key;
}

// The whole puff on the eye with its internal structures at the
// reference data (scenes/puff-internal.toml, on a coarse P1 mesh): each
// humor keeps its own volume while both pressures rise, and the cornea
// goes in and comes back out. Its summary is compared across rank counts.
TEST(Puff, InternalStructuresThroughThePuff)
{
  auto summary = run_scene("scenes/puff-internal.toml", "puff_internal",
                           {"fem.degree=1", "puff.duration=16.0", "output.fields=false",
                            "solver.atol=1e-11"});
  ASSERT_EQ(summary["status"], "converged");
  for (const char* c : {"aqueous", "vitreous"})
  {
    const std::string name = c;
    const double held = summary[name + "_volume_closed_mm3"].get<double>();
    double worst = 0;
    for (const auto& step : summary["steps"])
      if (step["phase"] == "puff" || step["phase"] == "rest")
        worst = std::max(worst, std::abs(step[name + "_volume_mm3"].get<double>() / held - 1));
    const double rise = summary[name + "_pressure_max_mmHg"].get<double>() - 15.0;
    std::printf("puff with internal structures: %s rises by %.3f mmHg, volume held to %.1e\n",
                c, rise, worst);
    EXPECT_LT(worst, 1e-10) << c;
    EXPECT_GT(rise, 0.5) << c; // the puff pressurises both closed humors
  }
  const double a1 = summary["a1_time_ms"].get<double>(), hc = summary["hc_time_ms"].get<double>(),
               a2 = summary["a2_time_ms"].get<double>();
  std::printf("A1 %.3f ms, HC %.3f ms, A2 %.3f ms; deflection %.4f mm\n", a1, hc, a2,
              summary["deflection_amplitude_mm"].get<double>());
  EXPECT_LT(a1, hc);
  EXPECT_LT(hc, a2);
  EXPECT_LT(summary["rest_drift_mm"].get<double>(), 1e-9);
}

// The puff table (the format the CFD writes) drives the run as the
// gaussian it samples does: the same apex motion up to the table's
// bilinear interpolation error, about (h / width)^2 / 8 = 1e-4 of the
// pressure on a grid of h = 0.05 ms and 0.05 mm. On the eye's section: the
// load's lookup does not depend on the dimension.
TEST(Puff, TableDrivesTheSameMotionAsItsGaussian)
{
  const auto dir = out_dir("puff_table_scenes");
  const std::string common = "[mesh]\ndimension = \"axisymmetric\"\nlayers = 2\n"
                             "[output]\nfields = false\n"
                             "[dynamics]\ndt = 0.5\n[puff]\nduration = 6.0\n";
  const std::string gaussian = common + "load = \"gaussian\"\n";
  const std::string table = common + "load = \"table\"\ntable = \"gaussian.csv\"\n";
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  if (rank == 0)
  {
    std::filesystem::create_directories(dir);
    std::ofstream(dir / "gaussian.toml") << gaussian;
    std::ofstream(dir / "table.toml") << table;
    std::ofstream csv(dir / "gaussian.csv");
    csv.precision(17);
    csv << "t_ms,r_mm,p_mmHg\n";
    const nct::puff::Gaussian p(65.0, 10.0, 3.0, 1.5); // the defaults of puff.*
    for (int i = 0; i <= 120; ++i)
      for (int j = 0; j <= 160; ++j)
        csv << 0.05 * i << "," << 0.05 * j << "," << p(0.05 * j, 0.05 * i) << "\n";
  }
  MPI_Barrier(MPI_COMM_WORLD);
  auto a = run_scene((dir / "gaussian.toml").string(), "puff_gaussian");
  auto b = run_scene((dir / "table.toml").string(), "puff_table");
  ASSERT_EQ(a["status"], "converged");
  ASSERT_EQ(b["status"], "converged");
  ASSERT_EQ(a["steps"].size(), b["steps"].size());
  // From the inflated eye (the last step before the puff) on.
  double worst = 0, deepest = 0, rest = 0;
  for (std::size_t i = 0; i < a["steps"].size(); ++i)
  {
    const double ua = a["steps"][i]["apex_displacement_mm"][1].get<double>(),
                 ub = b["steps"][i]["apex_displacement_mm"][1].get<double>();
    if (a["steps"][i]["phase"] != "puff")
    {
      rest = ua;
      continue;
    }
    worst = std::max(worst, std::abs(ua - ub));
    deepest = std::max(deepest, rest - ua);
  }
  std::printf("table against gaussian: apex differs by %.2e mm at most; it moved %.4f mm\n",
              worst, deepest);
  EXPECT_GT(deepest, 0.05); // the puff has pushed the apex in
  EXPECT_LT(worst, 1e-3 * deepest);
}

// The predictor changes where Newton starts, not where it ends: the first
// 6 ms of the default puff (on the eye's section, full Newton) from the
// constant-acceleration state u_n + dt v_n + dt^2/2 a_n follow the same
// apex history to the Newton tolerance as from the last state, in fewer
// iterations.
TEST(Puff, PredictorKeepsTheMotion)
{
  const std::vector<std::string> sets
      = {"mesh.dimension=\"axisymmetric\"", "output.fields=false", "solver.atol=1e-11",
         "puff.duration=6",
         "zero_pressure.enabled=false", "solver.jacobian=\"every_iteration\""};
  auto without = sets;
  without.push_back("solver.predictor=\"previous\"");
  auto previous = run_scene("scenes/default.toml", "predictor_previous", without);
  auto with = sets;
  with.push_back("solver.predictor=\"extrapolate\"");
  auto extrapolated = run_scene("scenes/default.toml", "predictor_extrapolate", with);
  ASSERT_EQ(previous["status"], "converged");
  ASSERT_EQ(extrapolated["status"], "converged");
  const auto &a = previous["steps"], &b = extrapolated["steps"];
  ASSERT_EQ(a.size(), b.size());
  double worst = 0;
  int its_a = 0, its_b = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
  {
    if (a[i]["phase"] != "puff")
      continue;
    worst = std::max(worst, std::abs(a[i]["apex_displacement_mm"][1].get<double>()
                                     - b[i]["apex_displacement_mm"][1].get<double>()));
    its_a += a[i]["newton_iterations"].get<int>();
    its_b += b[i]["newton_iterations"].get<int>();
  }
  std::printf("puff: %d Newton iterations from the last state, %d extrapolated; apex "
              "histories differ by %.2e mm at most\n",
              its_a, its_b, worst);
  EXPECT_LT(worst, 1e-8);
  EXPECT_LT(its_b, its_a);
}

// An iterative linear solver in place of the factorisation: GMRES with
// PETSc's algebraic multigrid (GAMG), which builds its coarse spaces from
// the rigid-body modes the solid's matrix carries (its near-nullspace),
// named on the command line as a user would. Newton's residual test is the
// same, so the motion must be the direct solver's to the tolerance's
// footprint, and the solves must really be Krylov's (several iterations
// each), not the scene's LDL^T (which a named preconditioner overrides).
// On the quarter eye (its six rigid-body modes) with one layer.
TEST(Puff, AlgebraicMultigridGivesTheDirectSolversMotion)
{
  auto s = nct::read(MPI_COMM_WORLD, 
      std::filesystem::path(NCT_SOURCE_DIR) / "scenes/default.toml",
      {"fem.degree=1", "mesh.layers=1", "output.fields=false", "solver.atol=1e-11",
       "puff.duration=2", "zero_pressure.enabled=false"});
  auto direct = nct::run(MPI_COMM_WORLD, s, {out_dir("solver_direct"), {}});
  const std::vector<std::pair<std::string, std::string>> gamg
      = {{"ksp_type", "gmres"},        {"pc_type", "gamg"},
         {"ksp_rtol", "1e-8"},         {"ksp_max_it", "2000"},
         {"ksp_gmres_restart", "200"}, {"pc_gamg_threshold", "0.02"}};
  auto multigrid = nct::run(MPI_COMM_WORLD, s, {out_dir("solver_gamg"), gamg});
  for (const auto& [k, v] : gamg) // the options database is the process's
    PetscOptionsClearValue(nullptr, ("-" + k).c_str());
  ASSERT_EQ(direct["status"], "converged");
  ASSERT_EQ(multigrid["status"], "converged");
  const auto &a = direct["steps"], &b = multigrid["steps"];
  ASSERT_EQ(a.size(), b.size());
  double worst = 0;
  for (std::size_t i = 0; i < a.size(); ++i)
    for (int k = 0; k < 3; ++k)
      worst = std::max(worst, std::abs(a[i]["apex_displacement_mm"][k].get<double>()
                                       - b[i]["apex_displacement_mm"][k].get<double>()));
  const int solves = multigrid["linear_solves"], its = multigrid["krylov_iterations"];
  std::printf("direct: %d linear solves; GAMG: %d solves, %d Krylov iterations; apex "
              "histories differ by %.2e mm at most\n",
              direct["linear_solves"].get<int>(), solves, its, worst);
  EXPECT_EQ(direct["krylov_iterations"], direct["linear_solves"]);
  EXPECT_GT(its, 3 * solves);
  EXPECT_LT(worst, 1e-8);
}

// Checkpoint boundaries (checkpoint.steps) are part of a run; when files
// are written there (checkpoint.minutes) is not: written at every boundary
// or at none, the motion is the same (1 rank: bitwise; 2 ranks: to the
// round-off MUMPS' parallel factorisation leaves, through the tolerance).
// On the eye's section (checkpoint.py kills and resumes the 3D runs).
TEST(Checkpoint, ResultsDoNotDependOnWhenFilesAreWritten)
{
  const std::vector<std::string> sets = {"mesh.dimension=\"axisymmetric\"", "mesh.layers=2",
                                         "puff.duration=6.0",
                                         "output.fields=false", "solver.atol=1e-11",
                                         "checkpoint.steps=3"};
  auto every = sets, never = sets;
  every.push_back("checkpoint.minutes=0");
  never.push_back("checkpoint.minutes=1e4");
  const auto a = nct::test::run_scene("scenes/puff-gaussian.toml", "checkpoint_every", every);
  const auto b = nct::test::run_scene("scenes/puff-gaussian.toml", "checkpoint_never", never);
  ASSERT_EQ(a["status"], "converged");
  ASSERT_EQ(b["status"], "converged");
  // 12 puff steps, a boundary every 3rd; the 2 rest steps hold none.
  EXPECT_EQ(a["checkpoints"]["written"], 4);
  EXPECT_FALSE(b.contains("checkpoints"));
  EXPECT_TRUE(std::filesystem::exists(nct::test::out_dir("checkpoint_every") / "checkpoint" / "latest"));
  EXPECT_FALSE(std::filesystem::exists(nct::test::out_dir("checkpoint_never") / "checkpoint"));
  int ranks = 1;
  MPI_Comm_size(MPI_COMM_WORLD, &ranks);
  const double tol = ranks == 1 ? 0.0 : 1e-9;
  ASSERT_EQ(a["steps"].size(), b["steps"].size());
  for (std::size_t i = 0; i < a["steps"].size(); ++i)
    for (int k = 0; k < 3; ++k)
      EXPECT_NEAR(a["steps"][i]["apex_displacement_mm"][k].get<double>(),
                  b["steps"][i]["apex_displacement_mm"][k].get<double>(), tol)
          << "step " << i;
  EXPECT_NEAR(a["deflection_amplitude_mm"].get<double>(), b["deflection_amplitude_mm"].get<double>(),
              tol);
}
