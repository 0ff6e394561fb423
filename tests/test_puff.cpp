// The prescribed puff pressure p(r, t): the parametric gaussian and the
// CSV table that a CFD run writes (one-way coupling).
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
