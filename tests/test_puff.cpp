// The prescribed puff pressure p(r, t): the parametric gaussian and the
// CSV table that a CFD run writes (one-way coupling).
#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>

#include "puff/load.h"

namespace
{

std::filesystem::path write(const std::string& name, const std::string& text)
{
  auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path) << text;
  return path;
}

std::string error_of(const std::string& text)
{
  try
  {
    nct::puff::Table::read(write("nct_puff_bad.csv", text));
  }
  catch (const std::invalid_argument& e)
  {
    return e.what();
  }
  return "";
}

} // namespace

TEST(Puff, Gaussian)
{
  nct::puff::Gaussian p(65.0, 15.0, 3.0, 1.5);
  EXPECT_DOUBLE_EQ(p(0, 15), 65.0);
  EXPECT_NEAR(p(1.5, 15), 65.0 * std::exp(-0.5), 1e-12);
  EXPECT_NEAR(p(0, 18), 65.0 * std::exp(-0.5), 1e-12);
  EXPECT_NEAR(p(3.0, 9), 65.0 * std::exp(-2.0) * std::exp(-2.0), 1e-12);
}

// Bilinear data p = 2 + 3 t + 5 r - 0.5 t r is reproduced exactly between
// the grid points; outside the times the puff is off, beyond the last
// radius the value stays that of the last radius.
TEST(Puff, TableIsBilinear)
{
  auto f = [](double r, double t) { return 2 + 3 * t + 5 * r - 0.5 * t * r; };
  std::string csv = "t_ms,r_mm,p_mmHg\n";
  for (double t : {0.0, 1.0, 2.5, 4.0})
    for (double r : {0.0, 0.5, 2.0, 6.0})
      csv += std::to_string(t) + "," + std::to_string(r) + "," + std::to_string(f(r, t)) + "\n";
  auto table = nct::puff::Table::read(write("nct_puff_bilinear.csv", csv));
  EXPECT_EQ(table.times().size(), 4u);
  EXPECT_EQ(table.radii().size(), 4u);
  for (double t : {0.0, 0.3, 1.7, 3.99, 4.0})
    for (double r : {0.0, 0.1, 1.3, 5.9})
      EXPECT_NEAR(table(r, t), f(r, t), 1e-9) << "r " << r << " t " << t;
  EXPECT_EQ(table(1.0, -0.1), 0.0);
  EXPECT_EQ(table(1.0, 4.1), 0.0);
  EXPECT_NEAR(table(9.0, 2.0), f(6.0, 2.0), 1e-9);
}

TEST(Puff, BadTablesNameFileLineAndProblem)
{
  EXPECT_NE(error_of("").find("empty file"), std::string::npos);
  EXPECT_NE(error_of("t,r,p\n").find(":1: header 't,r,p'"), std::string::npos);
  EXPECT_NE(error_of("t_ms,r_mm,p_mmHg\n0,0,1\n0,x,2\n").find(":3: '0,x,2' is not three"),
            std::string::npos);
  EXPECT_NE(error_of("t_ms,r_mm,p_mmHg\n0,1,1\n0,0.5,2\n").find(":3: radius 0.500000 mm does "
                                                                 "not increase"),
            std::string::npos);
  EXPECT_NE(error_of("t_ms,r_mm,p_mmHg\n1,0,1\n1,1,1\n0,0,1\n0,1,1\n")
                .find(":4: time 0.000000 ms does not increase"),
            std::string::npos);
  EXPECT_NE(error_of("t_ms,r_mm,p_mmHg\n0,0,1\n0,1,1\n1,0,1\n1,2,1\n")
                .find(":5: every time needs the radii of the first time"),
            std::string::npos);
  EXPECT_NE(error_of("t_ms,r_mm,p_mmHg\n0,0,1\n0,1,1\n1,0,1\n").find("fewer radii"),
            std::string::npos);
  EXPECT_NE(error_of("t_ms,r_mm,p_mmHg\n0,-1,1\n").find("negative"), std::string::npos);
  EXPECT_NE(error_of("t_ms,r_mm,p_mmHg\n").find("no rows"), std::string::npos);
}

// The measured Corvis ST pulse (Oehring et al., Appl. Sci. 11 (2021) 2499):
// 96.4 mmHg at the centre, 21.48 ms long, edges +8.94 and -11.18 mmHg/ms.
// Its descriptors measured on the sampled pulse, independently of how the
// shape was built: the peak, the time from onset to end, and each edge's
// mean rate (the peak over the time from onset to the peak, and from the
// peak to the end).
TEST(Puff, PulseHoldsTheMeasuredDescriptors)
{
  const double peak = 96.4;
  const auto shape = nct::puff::PulseShape::from_descriptors(8.94 / peak, 11.18 / peak, 21.48);
  const nct::puff::Pulse pulse(peak, shape, nct::puff::RadialProfile({0.0, 2.0}, {1.0, 0.5}));
  const double dt = 1e-5;
  std::vector<double> t, p;
  for (double s = -1; s < shape.end() + 1; s += dt)
    t.push_back(s), p.push_back(pulse(0, s));
  const double top = *std::max_element(p.begin(), p.end());
  // Onset and end: the first and last samples above zero; the peak's
  // first and last samples within 1e-12 of it (1e-5 ms from the true
  // ends of the hold, where s = 1 - (pi dt / 2 T)^2).
  std::size_t onset = 0, end = 0, first = 0, last = 0;
  for (std::size_t i = 0; i < p.size(); ++i)
  {
    if (p[i] > 0 && !onset)
      onset = i;
    if (p[i] > 0)
      end = i;
    if (p[i] >= top * (1 - 1e-12) && !first)
      first = i;
    if (p[i] >= top * (1 - 1e-12))
      last = i;
  }
  const double duration = t[end] - t[onset] + dt;
  const double rise = top / (t[first] - t[onset]), fall = -top / (t[end] - t[last]);
  std::printf("pulse: peak %.4f mmHg, duration %.4f ms, edges %+.4f / %+.4f mmHg/ms; rise %.3f, "
              "hold %.3f, fall %.3f ms\n",
              top, duration, rise, fall, shape.rise_time(), shape.hold_time(), shape.fall_time());
  EXPECT_NEAR(top, 96.4, 1e-9);
  EXPECT_NEAR(duration, 21.48, 2 * dt);
  EXPECT_NEAR(rise, 8.94, 1e-4);
  EXPECT_NEAR(fall, -11.18, 1e-4);
  // Zero outside the pulse, and the radial profile scales it.
  EXPECT_EQ(pulse(0, -0.1), 0.0);
  EXPECT_EQ(pulse(0, shape.end() + 0.1), 0.0);
  EXPECT_NEAR(pulse(1.0, shape.rise_time()), 0.75 * peak, 1e-12);
  EXPECT_NEAR(pulse(3.0, shape.rise_time()), 0.5 * peak, 1e-12);
  // Edges too slow for the duration leave no room for a hold.
  EXPECT_THROW(nct::puff::PulseShape::from_descriptors(4.0 / peak, 4.0 / peak, 21.48),
               std::invalid_argument);
}

TEST(Puff, RadialProfileIsNormalisedOnTheAxis)
{
  auto p = nct::puff::RadialProfile::read(
      write("nct_profile.csv", "r_mm,p_mmHg\n0,80\n1,40\n2,-4\n"));
  EXPECT_DOUBLE_EQ(p(0), 1.0);
  EXPECT_DOUBLE_EQ(p(0.5), 0.75);
  EXPECT_DOUBLE_EQ(p(2), -0.05);
  EXPECT_DOUBLE_EQ(p(7), -0.05);
  auto error = [](const std::string& text)
  {
    try
    {
      nct::puff::RadialProfile::read(write("nct_profile_bad.csv", text));
    }
    catch (const std::invalid_argument& e)
    {
      return std::string(e.what());
    }
    return std::string();
  };
  EXPECT_NE(error("r_mm,p_mmHg\n0.5,80\n").find(":2: the first radius must be 0"),
            std::string::npos);
  EXPECT_NE(error("r_mm,p_mmHg\n0,0\n1,2\n").find(":2: the pressure on the axis must be positive"),
            std::string::npos);
  EXPECT_NE(error("r_mm,p_mmHg\n0,1\n1,2\n1,3\n").find(":4: radius 1.000000 mm does not increase"),
            std::string::npos);
  EXPECT_NE(error("r,p\n0,1\n").find(":1: header 'r,p'; expected r_mm,p_mmHg"), std::string::npos);
}
