// The emulator evaluated in C++ from its exported file against
// scikit-learn's own predictions (tests/emulator_fixture.py writes both,
// ctest runs it first): means to 1e-10 (relative above 1: the sum k*^T alpha
// cancels, and its order is the library's own), variances to 1e-12, the
// gradient against scikit-learn's central differences, an input outside
// the box refused by name.
#include <cstdlib>
#include <fstream>
#include <gtest/gtest.h>
#include <nlohmann/json.hpp>

#include "emulator/emulator.h"

namespace
{
std::filesystem::path fixture()
{
  const char* dir = std::getenv("NCT_EMULATOR_FIXTURE");
  if (!dir)
    throw std::runtime_error("NCT_EMULATOR_FIXTURE is not set: run this test through ctest, "
                             "after tests/emulator_fixture.py");
  return dir;
}
} // namespace

TEST(Emulator, MatchesScikitLearn)
{
  const nct::emulator::Emulator em(fixture() / "emulator.json");
  ASSERT_EQ(em.inputs().size(), 3u);
  EXPECT_EQ(em.inputs()[0].name, "c10");
  EXPECT_TRUE(em.inputs()[0].log);
  EXPECT_EQ(em.blocks().front().first, "apex_mm");
  EXPECT_EQ(em.blocks().front().second, em.t_ms().size());
  EXPECT_EQ(em.profile_x_mm().size(), 7u);
  EXPECT_EQ(em.profile_t_ms(), (std::vector<double>{5, 10, 15}));
  const auto cases = nlohmann::json::parse(std::ifstream(fixture() / "expected.json"));
  for (const auto& c : cases)
  {
    const std::vector<double> x = c.at("x");
    const auto curves = em.curves(x);
    const auto& p = c.at("prediction");
    ASSERT_EQ(curves.size(), p.at("curves_mm").size());
    for (std::size_t o = 0; o < curves.size(); ++o)
    {
      const double m = p.at("curves_mm")[o];
      EXPECT_NEAR(curves[o].mean, m, 1e-10 * std::max(1.0, std::abs(m))) << o;
      EXPECT_NEAR(curves[o].variance, p.at("curves_var_mm2")[o].get<double>(), 1e-12) << o;
    }
    for (const auto& [key, mv] : p.at("readings").items())
    {
      const auto v = em.reading(key, x);
      const double m = mv.at(0);
      EXPECT_NEAR(v.mean, m, 1e-10 * std::max(1.0, std::abs(m))) << key;
      EXPECT_NEAR(v.variance, mv.at(1).get<double>(), 1e-12) << key;
    }
    // The analytic gradient against scikit-learn's central differences.
    for (std::size_t j = 0; j < x.size(); ++j)
    {
      const auto& d = c.at("differences")[j];
      double worst = 0, scale = 1e-12;
      for (std::size_t o = 0; o < curves.size(); ++o)
      {
        const double fd = d.at("curves_mm")[o];
        worst = std::max(worst, std::abs(curves[o].gradient[j] - fd));
        scale = std::max(scale, std::abs(fd));
      }
      EXPECT_LT(worst / scale, 1e-5) << "input " << j;
      for (const auto& [key, fd] : d.at("readings").items())
        EXPECT_NEAR(em.reading(key, x).gradient[j], fd.get<double>(),
                    1e-5 * std::max(1.0, std::abs(fd.get<double>())))
            << key << ", input " << j;
    }
  }
}

// The variance's gradient against central differences of the variance (to
// 1e-3: the variance is c + noise - |w|^2, a difference of near-equal
// numbers, so that its differences are good to some 1e-4 at best; a wrong
// term is off by its whole size), and a functional's mean and variance
// against the outputs' own.
TEST(Emulator, VarianceGradientAndProjection)
{
  const nct::emulator::Emulator em(fixture() / "emulator.json");
  const std::vector<double> x = {0.05, 14.0, 0.52};
  const auto curves = em.curves(x);
  for (std::size_t j = 0; j < x.size(); ++j)
  {
    const double h = 1e-3 * x[j]; // the variance cancels: c + noise - |w|^2
    auto up = x, down = x;
    up[j] += h, down[j] -= h;
    const auto a = em.curves(up), b = em.curves(down);
    double worst = 0, scale = 1e-30;
    for (std::size_t o = 0; o < curves.size(); ++o)
    {
      const double fd = (a[o].variance - b[o].variance) / (2 * h);
      worst = std::max(worst, std::abs(curves[o].variance_gradient[j] - fd));
      scale = std::max(scale, std::abs(fd));
    }
    EXPECT_LT(worst / scale, 1e-3) << "input " << j;
    const auto ra = em.reading("hc_time_ms", up), rb = em.reading("hc_time_ms", down);
    const double fd = (ra.variance - rb.variance) / (2 * h);
    EXPECT_NEAR(em.reading("hc_time_ms", x).variance_gradient[j], fd,
                1e-3 * std::max(std::abs(fd), 1e-12)) << "input " << j;
  }
  // A single output, and half of two neighbours: offset + factor w.
  const std::size_t o = 7;
  const auto p = em.project({{{o, 1.0}}, {{o, 0.5}, {o + 1, 0.5}}});
  const auto w = em.components(x);
  auto at = [&](std::size_t f)
  {
    double mean = p.offset[f], variance = p.truncation[f];
    std::vector<double> gradient(x.size(), 0.0);
    for (std::size_t c = 0; c < w.size(); ++c)
    {
      mean += p.factor[f][c] * w[c].mean;
      variance += p.factor[f][c] * p.factor[f][c] * w[c].variance;
      for (std::size_t j = 0; j < x.size(); ++j)
        gradient[j] += p.factor[f][c] * w[c].gradient[j];
    }
    return nct::emulator::Value{mean, variance, gradient, {}};
  };
  EXPECT_NEAR(at(0).mean, curves[o].mean, 1e-12);
  EXPECT_NEAR(at(0).variance, curves[o].variance, 1e-15);
  EXPECT_NEAR(at(1).mean, 0.5 * (curves[o].mean + curves[o + 1].mean), 1e-12);
  for (std::size_t j = 0; j < x.size(); ++j)
    EXPECT_NEAR(at(0).gradient[j], curves[o].gradient[j],
                1e-12 * std::abs(curves[o].gradient[j]));
  EXPECT_EQ(em.inputs()[1].keys, (std::vector<std::string>{"inflate.iop"}));
  const auto [lo, hi] = em.reading_range("hc_time_ms");
  EXPECT_LT(lo, hi);
}

TEST(Emulator, RefusesWhatItCannotAnswer)
{
  const nct::emulator::Emulator em(fixture() / "emulator.json");
  try
  {
    em.curves({0.06, 40.0, 0.55});
    ADD_FAILURE() << "an IOP of 40 outside [8, 35] was accepted";
  }
  catch (const std::out_of_range& e)
  {
    EXPECT_STREQ(e.what(), "iop = 40 is outside the emulator's box [8, 35]");
  }
  EXPECT_THROW(em.reading("no_such_reading", {0.06, 15.0, 0.55}), std::out_of_range);
  EXPECT_THROW(em.curves({0.06, 15.0}), std::out_of_range);
  EXPECT_THROW(nct::emulator::Emulator("no_such_emulator.json"), std::invalid_argument);
}
