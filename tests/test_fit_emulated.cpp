// A fit's likelihood on an emulator (cpp/fit/emulated.h) and the ensemble
// sampler (cpp/fit/mcmc.h): the residuals' exact Jacobian against central
// differences (a step of 1e-4: the emulator's variance is a difference of
// near-equal numbers, good to some 1e-4 relative, so smaller steps measure
// its rounding), the Woodbury log-likelihood against the dense one, the
// answer's shift under another model's values; the sampler's moments
// and quantiles of a correlated Gaussian.
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "fit/emulated.h"
#include "fit/mcmc.h"

namespace
{
using nct::fit::Fit;
using nct::fit::Kind;

/// A fit of c10 (log) and the IOP (with a prior) on the fixture's emulator
/// (tests/emulator_fixture.py), the thickness fixed: an apex curve between
/// frames, two profile points and a reading, measured at c10 = 0.07 and
/// IOP 17 plus offsets of about a noise.
Fit fixture_fit()
{
  const char* dir = std::getenv("NCT_EMULATOR_FIXTURE");
  if (!dir)
    throw std::runtime_error("NCT_EMULATOR_FIXTURE is not set: run through ctest");
  Fit fit;
  fit.emulator_file = std::filesystem::path(dir) / "emulator.json";
  fit.emulator = std::make_shared<const nct::emulator::Emulator>(fit.emulator_file);
  fit.parameters.push_back({"c10", {"material.cornea.c10"}, 0.06, 0.03, 0.12, true});
  fit.parameters.push_back({"iop", {"inflate.iop"}, 15.0, 8.0, 35.0, false, true, 16.0, 1.5});
  fit.emulator_inputs = {{0, 0.0}, {1, 0.0}, {-1, 0.55}};
  nct::fit::Observation apex{"apex", Kind::curve, "apex_displacement_mm", "", true, {}, {}, {}, {}};
  for (double t = 1.3; t < 19; t += 2.1)
    apex.t.push_back(t), apex.x.push_back(NAN), apex.sd.push_back(0.02);
  nct::fit::Observation profile{"profile", Kind::profile, "anterior", "", true,
                                {10.0, 5.0}, {-1.0, 2.0}, {}, {0.02, 0.03}};
  nct::fit::Observation da{"da", Kind::biomarker, "deformation_amplitude_mm", "", true,
                           {NAN}, {NAN}, {}, {0.08}};
  fit.observations = {apex, profile, da};
  for (auto& o : fit.observations)
    o.value.assign(o.sd.size(), 0.0);
  // The measured values: the emulator's mean at the truth plus offsets.
  const nct::fit::EmulatedLikelihood at_truth(fit);
  const auto e = at_truth.evaluate({std::log(0.07 / 0.06), 17.0}, false);
  std::size_t j = 0;
  for (auto& o : fit.observations)
  {
    o.value.clear();
    for (std::size_t i = 0; i < o.sd.size(); ++i, ++j)
      o.value.push_back(e.model(Eigen::Index(j)) + 0.7 * o.sd[i] * std::sin(double(j)));
  }
  return fit;
}

} // namespace

TEST(FitEmulated, JacobianMatchesDifferences)
{
  const Fit fit = fixture_fit();
  const nct::fit::EmulatedLikelihood l(fit);
  EXPECT_EQ(l.residuals(), fit.residuals() + 1);
  for (const std::vector<double>& theta :
       {std::vector<double>{0.1, 19.0}, std::vector<double>{-0.4, 11.0}})
  {
    const auto e = l.evaluate(theta, true);
    ASSERT_EQ(e.jacobian.rows(), Eigen::Index(l.residuals()));
    for (std::size_t j = 0; j < theta.size(); ++j)
    {
      const double h = 1e-4 * std::max(1.0, std::abs(theta[j]));
      auto up = theta, down = theta;
      up[j] += h, down[j] -= h;
      const Eigen::VectorXd fd = (l.evaluate(up, false).r - l.evaluate(down, false).r) / (2 * h);
      const double error = (e.jacobian.col(Eigen::Index(j)) - fd).norm();
      EXPECT_LT(error, 1e-5 * fd.norm()) << "parameter " << j;
      // The log determinant's row, the emulator's variance alone.
      const Eigen::Index det = Eigen::Index(l.residuals()) - 2;
      EXPECT_NEAR(e.jacobian(det, Eigen::Index(j)), fd(det), 1e-3 * std::abs(fd(det)))
          << "parameter " << j;
    }
  }
}

TEST(FitEmulated, WoodburyLikelihoodIsTheDenseOne)
{
  const Fit fit = fixture_fit();
  const nct::fit::EmulatedLikelihood l(fit);
  for (const std::vector<double>& theta :
       {std::vector<double>{0.1, 19.0}, std::vector<double>{-0.4, 11.0}})
  {
    const double dense = -0.5 * l.evaluate(theta, false).r.squaredNorm();
    EXPECT_NEAR(l.log_posterior(theta), dense, 1e-9 * std::abs(dense));
  }
  EXPECT_TRUE(std::isinf(l.log_posterior({std::log(0.2 / 0.06), 15.0}))); // c10 beyond 0.12
  // The emulator's own mean moves nothing; with the corneal C10 alone
  // fitted (the IOP given), the values the emulator gives at theta + a
  // move the answer by -a, to first order.
  Fit one = fit;
  one.parameters.resize(1);
  one.emulator_inputs = {{0, 0.0}, {-1, 19.0}, {-1, 0.55}};
  const nct::fit::EmulatedLikelihood lo(one);
  const auto e = lo.evaluate({0.1}, false);
  std::vector<double> mean(e.model.data(), e.model.data() + e.model.size()), moved = mean;
  EXPECT_LT(lo.shift({0.1}, mean).norm(), 1e-12);
  const auto up = lo.evaluate({0.1 + 0.01}, false);
  for (std::size_t i = 0; i < moved.size(); ++i)
    moved[i] = up.model(Eigen::Index(i));
  EXPECT_NEAR(lo.shift({0.1}, moved)(0), -0.01, 0.0005);
}

// A Gaussian with correlation 0.95 (IOP and stiffness's valley): the
// samples' means, SDs, correlation and 2.5 % quantile, within what
// 64 walkers x 2000 steps allow.
TEST(FitEmulated, SamplerRecoversACorrelatedGaussian)
{
  const double s1 = 2.0, s2 = 0.5, rho = 0.95;
  auto log_p = [&](const std::vector<double>& x)
  {
    const double a = (x[0] - 1) / s1, b = (x[1] + 3) / s2;
    return -0.5 * (a * a - 2 * rho * a * b + b * b) / (1 - rho * rho);
  };
  std::vector<std::vector<double>> start;
  for (int w = 0; w < 64; ++w)
    start.push_back({1 + 0.01 * std::sin(w), -3 + 0.01 * std::cos(3 * w)});
  const auto chain = nct::fit::sample(log_p, start, 2000, 500, 3);
  ASSERT_EQ(chain.samples.size(), 64u * 1500u);
  double m[2] = {0, 0}, c[3] = {0, 0, 0};
  for (const auto& x : chain.samples)
    m[0] += x[0], m[1] += x[1];
  m[0] /= double(chain.samples.size()), m[1] /= double(chain.samples.size());
  std::vector<double> first;
  for (const auto& x : chain.samples)
  {
    c[0] += (x[0] - m[0]) * (x[0] - m[0]);
    c[1] += (x[0] - m[0]) * (x[1] - m[1]);
    c[2] += (x[1] - m[1]) * (x[1] - m[1]);
    first.push_back(x[0]);
  }
  for (double& v : c)
    v /= double(chain.samples.size());
  EXPECT_NEAR(m[0], 1.0, 0.1 * s1);
  EXPECT_NEAR(m[1], -3.0, 0.1 * s2);
  EXPECT_NEAR(std::sqrt(c[0]), s1, 0.1 * s1);
  EXPECT_NEAR(std::sqrt(c[2]), s2, 0.1 * s2);
  EXPECT_NEAR(c[1] / std::sqrt(c[0] * c[2]), rho, 0.02);
  EXPECT_NEAR(nct::fit::quantile(first, 0.025), 1 - 1.959964 * s1, 0.15 * s1);
  EXPECT_GT(chain.acceptance, 0.2);
  EXPECT_LT(chain.acceptance, 0.9);
  for (double tau : chain.autocorrelation)
    EXPECT_LT(tau, 150.0);
}

// A measured discrepancy: its mean moves the curve points' model by its
// value (not the reading's), its covariance joins the likelihood (the
// Jacobian and the Woodbury form still exact).
TEST(FitEmulated, DiscrepancyJoinsTheLikelihood)
{
  Fit fit = fixture_fit();
  std::size_t outputs = 0;
  for (const auto& [name, size] : fit.emulator->blocks())
    outputs += size;
  const auto file = std::filesystem::temp_directory_path() / "nct_test_discrepancy.json";
  {
    nlohmann::json d = {{"format", "nct-discrepancy-1"},
                        {"mean_mm", std::vector<double>(outputs, 0.001)},
                        {"factor_mm", std::vector<std::vector<double>>(outputs, {0.002, -0.001})}};
    std::ofstream(file) << d.dump();
  }
  const nct::fit::EmulatedLikelihood plain(fit);
  fit.discrepancy_file = file;
  const nct::fit::EmulatedLikelihood with(fit);
  const std::vector<double> theta = {0.1, 19.0};
  const auto a = plain.evaluate(theta, false), b = with.evaluate(theta, true);
  const Eigen::Index m = a.model.size();
  for (Eigen::Index i = 0; i + 1 < m; ++i) // the curve and profile points
    EXPECT_NEAR(b.model(i) - a.model(i), 0.001, 1e-12);
  EXPECT_NEAR(b.model(m - 1), a.model(m - 1), 1e-15); // the reading
  EXPECT_NEAR(b.model_sd(0) * b.model_sd(0) - a.model_sd(0) * a.model_sd(0), 5e-6, 1e-12);
  EXPECT_NEAR(with.log_posterior(theta), -0.5 * b.r.squaredNorm(), 1e-9 * b.r.squaredNorm());
  for (std::size_t j = 0; j < theta.size(); ++j)
  {
    auto up = theta, down = theta;
    const double h = 1e-4 * std::max(1.0, std::abs(theta[j]));
    up[j] += h, down[j] -= h;
    const Eigen::VectorXd fd = (with.evaluate(up, false).r - with.evaluate(down, false).r) / (2 * h);
    EXPECT_LT((b.jacobian.col(Eigen::Index(j)) - fd).norm(), 1e-5 * fd.norm()) << j;
  }
  std::filesystem::remove(file);
}
