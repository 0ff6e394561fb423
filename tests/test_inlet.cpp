// The inlet of a file mesh's fluid: profiles across the section against
// their closed forms, the mean of each over its section by quadrature, and
// the ramp in time.
#include <cmath>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>

#include "air/inlet.h"

namespace
{
using nct::air::Inlet;

TEST(Inlet, UniformIsTheSpeedAlongTheDirection)
{
  Inlet in;
  in.direction = {0, 0, -1};
  in.speed = 2.5;
  const auto u = in.velocity({3, -7, 11});
  EXPECT_DOUBLE_EQ(u[0], 0);
  EXPECT_DOUBLE_EQ(u[1], 0);
  EXPECT_DOUBLE_EQ(u[2], -2.5);
  EXPECT_DOUBLE_EQ(in.mean_factor(), 1);
}

TEST(Inlet, ChannelIsPoiseuilleAcrossOneWayOnly)
{
  // Turek-Hron's inlet: u = 1.5 U 4 y (H - y) / H^2 on x = 0, H = 410 mm,
  // the slab's depth unbounded.
  Inlet in;
  in.profile = Inlet::Profile::rectangle;
  in.center = {0, 205, 5};
  in.half_widths = {205, std::numeric_limits<double>::infinity()};
  in.speed = 0.3;
  for (double y : {0.0, 41.0, 100.0, 205.0, 333.0, 410.0})
    for (double z : {0.0, 5.0, 10.0, 1e3})
    {
      const auto u = in.velocity({0, y, z});
      EXPECT_NEAR(u[0], 0.3 * 4 * y * (410 - y) / (410.0 * 410.0), 1e-15) << y << " " << z;
      EXPECT_EQ(u[1], 0);
      EXPECT_EQ(u[2], 0);
    }
  EXPECT_DOUBLE_EQ(in.velocity({0, -1, 0})[0], 0); // outside the section: none
  EXPECT_DOUBLE_EQ(in.mean_factor(), 2.0 / 3);      // the mean speed is U = 0.2
}

TEST(Inlet, MeansOverTheSectionByQuadrature)
{
  // A rectangular duct (2 x 1 mm, tilted axes) and a pipe (radius 0.7 mm):
  // the midpoint rule of each profile over its section against mean_factor.
  Inlet duct;
  duct.profile = Inlet::Profile::rectangle;
  duct.direction = {0, 0, 1};
  duct.center = {1, 2, 0};
  const double c = std::cos(0.3), s = std::sin(0.3);
  duct.axes = {{{c, s, 0}, {-s, c, 0}}};
  duct.half_widths = {2, 1};
  const int n = 400;
  double sum = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
    {
      const double a = -2 + 4 * (i + 0.5) / n, b = -1 + 2 * (j + 0.5) / n;
      sum += duct.velocity({1 + a * c - b * s, 2 + a * s + b * c, 0})[2];
    }
  EXPECT_NEAR(sum / (n * n), duct.mean_factor(), 1e-5);
  EXPECT_NEAR(duct.mean_factor(), 4.0 / 9, 1e-15);

  Inlet pipe;
  pipe.profile = Inlet::Profile::circle;
  pipe.direction = {0, -1, 0};
  pipe.center = {0, 5, 0};
  pipe.radius = 0.7;
  double flux = 0, area = 0;
  for (int i = 0; i < n; ++i)
    for (int j = 0; j < n; ++j)
    {
      const double x = -0.7 + 1.4 * (i + 0.5) / n, z = -0.7 + 1.4 * (j + 0.5) / n;
      if (x * x + z * z > 0.49)
        continue;
      flux += -pipe.velocity({x, 5.3, z})[1]; // off the centre plane: the same
      area += 1;
    }
  EXPECT_NEAR(flux / area, pipe.mean_factor(), 2e-4);
  EXPECT_DOUBLE_EQ(pipe.mean_factor(), 0.5);
}

TEST(Inlet, RampRisesSmoothlyAndHolds)
{
  Inlet in;
  in.ramp_time = 2000;
  EXPECT_EQ(in.ramp(-1), 0);
  EXPECT_EQ(in.ramp(0), 0);
  EXPECT_NEAR(in.ramp(1000), 0.5, 1e-15);
  EXPECT_NEAR(in.ramp(500), (1 - std::cos(M_PI / 4)) / 2, 1e-15);
  EXPECT_EQ(in.ramp(2000), 1);
  EXPECT_EQ(in.ramp(5000), 1);
  // Its slope vanishes at both ends (no jump in the acceleration's start).
  EXPECT_NEAR((in.ramp(1e-3) - in.ramp(0)) / 1e-3, 0, 1e-6);
  EXPECT_NEAR((in.ramp(2000) - in.ramp(2000 - 1e-3)) / 1e-3, 0, 1e-6);
  in.ramp_time = 0;
  EXPECT_EQ(in.ramp(0), 1);
}

} // namespace

namespace
{

std::filesystem::path write_table(const std::string& name, const std::string& text)
{
  auto path = std::filesystem::temp_directory_path() / name;
  std::ofstream(path) << text;
  return path;
}

std::string table_error(const std::string& text)
{
  try
  {
    Inlet::read_table(write_table("nct_inlet_bad.csv", text));
  }
  catch (const std::invalid_argument& e)
  {
    return e.what();
  }
  return "";
}

TEST(Inlet, TableHoldsItsPointsAndBlendsBetween)
{
  Inlet in;
  in.profile = Inlet::Profile::table;
  in.direction = {1, 0, 0};
  in.points = Inlet::read_table(write_table(
      "nct_inlet.csv", "x_mm,y_mm,z_mm,u_m_s\n0,0,0,1.0\n0, 2, 0, 3.0\n\n0,4,0,2.0\n"));
  ASSERT_EQ(in.points.size(), 3u);
  EXPECT_DOUBLE_EQ(in.velocity({0, 0, 0})[0], 1.0); // each point's own value
  EXPECT_DOUBLE_EQ(in.velocity({0, 2, 0})[0], 3.0);
  EXPECT_DOUBLE_EQ(in.velocity({0, 4, 0})[0], 2.0);
  // Between: Shepard's weights 1/r^2 (r = 1, 1, 3 from y = 1).
  const double w = 1 + 1 + 1.0 / 9;
  EXPECT_NEAR(in.velocity({0, 1, 0})[0], (1.0 + 3.0 + 2.0 / 9) / w, 1e-14);
  EXPECT_EQ(in.velocity({0, 1, 0})[1], 0);
  const auto u = in.velocity({0, 7, 3});
  EXPECT_GT(u[0], 1.0);
  EXPECT_LT(u[0], 3.0); // a weighted mean stays within the values
}

TEST(Inlet, BadTablesNameTheLine)
{
  EXPECT_NE(table_error("").find(":1: empty file"), std::string::npos);
  EXPECT_NE(table_error("x,y,z,u\n").find(":1: header 'x,y,z,u'"), std::string::npos);
  EXPECT_NE(table_error("x_mm,y_mm,z_mm,u_m_s\n").find(":2: no rows after the header"), std::string::npos);
  EXPECT_NE(table_error("x_mm,y_mm,z_mm,u_m_s\n0,0,0,1\n0,1,nan,2\n").find(":3: '0,1,nan,2' is not four finite numbers"),
            std::string::npos);
  EXPECT_NE(table_error("x_mm,y_mm,z_mm,u_m_s\n0,0,0,1,5\n").find(":2:"), std::string::npos);
  EXPECT_NE(table_error("x_mm,y_mm,z_mm,u_m_s\n0,0,0\n").find(":2:"), std::string::npos);
}

} // namespace
