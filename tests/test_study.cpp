// The study's statistics against hand computations: 2^2 and 2^3
// factorials worked by hand, a 2^5 with known effects, Pearson's r,
// main-effect means and an ablation's differences from its baseline.
// (tests/study_check.py compares a whole study's tables with an
// independent least-squares fit.)
#include <cmath>
#include <filesystem>
#include <fstream>
#include <gtest/gtest.h>
#include <limits>
#include <numbers>

#include "scene/scene.h"
#include "study/analysis.h"
#include "study/study.h"

using nct::study::factorial_anova;

namespace
{

/// The 2^k cases in Yates order: factor i is -1 or +1 in case c by bit i.
std::vector<std::vector<int>> yates(int k)
{
  std::vector<std::vector<int>> coded(1 << k, std::vector<int>(k));
  for (int c = 0; c < (1 << k); ++c)
    for (int i = 0; i < k; ++i)
      coded[c][i] = (c >> i) & 1 ? 1 : -1;
  return coded;
}

} // namespace

// y = (1, 5, 3, 11) in the order (1), a, b, ab:
// A = (5 + 11 - 1 - 3)/2 = 6, B = (3 + 11 - 1 - 5)/2 = 4,
// AB = (1 + 11 - 5 - 3)/2 = 2; SS = 4 e^2 / 4 = 36, 16, 4; total 56.
TEST(Study, TwoByTwoByHand)
{
  auto a = factorial_anova(yates(2), {1, 5, 3, 11}, {"A", "B"});
  ASSERT_EQ(a.terms.size(), 3u);
  EXPECT_EQ(a.terms[0].name, "A");
  EXPECT_EQ(a.terms[2].name, "A:B");
  EXPECT_DOUBLE_EQ(a.terms[0].effect, 6);
  EXPECT_DOUBLE_EQ(a.terms[1].effect, 4);
  EXPECT_DOUBLE_EQ(a.terms[2].effect, 2);
  EXPECT_DOUBLE_EQ(a.terms[0].sum_sq, 36);
  EXPECT_DOUBLE_EQ(a.terms[1].sum_sq, 16);
  EXPECT_DOUBLE_EQ(a.terms[2].sum_sq, 4);
  EXPECT_DOUBLE_EQ(a.total_sum_sq, 56);
  EXPECT_NEAR(a.terms[0].percent, 100 * 36.0 / 56, 1e-12);
  // No degrees of freedom are left for an error: no F, no p.
  EXPECT_EQ(a.error_df, 0);
  EXPECT_EQ(a.total_df, 3);
  EXPECT_TRUE(std::isnan(a.terms[0].f));
  EXPECT_TRUE(std::isnan(a.terms[0].p));
}

// y = 10 + 2 A - 3 B + C + 0.5 AB + 0.25 ABC: effects are twice the
// coefficients (4, -6, 2, 1, 0, 0); the three-way term is the error,
// SS_error = 8 (0.25)^2 = 0.5 on 1 dof. F(1, 1) is the square of
// Student's t with 1 dof (Cauchy), so p = (2/pi) atan(1/sqrt(F)).
TEST(Study, TwoByThreeByHand)
{
  auto coded = yates(3);
  std::vector<double> y;
  for (auto& x : coded)
    y.push_back(10 + 2 * x[0] - 3 * x[1] + x[2] + 0.5 * x[0] * x[1] + 0.25 * x[0] * x[1] * x[2]);
  auto a = factorial_anova(coded, y, {"A", "B", "C"});
  const std::vector<std::string> names = {"A", "B", "C", "A:B", "A:C", "B:C"};
  const std::vector<double> effects = {4, -6, 2, 1, 0, 0};
  ASSERT_EQ(a.terms.size(), 6u);
  EXPECT_EQ(a.error_df, 1);
  EXPECT_NEAR(a.error_sum_sq, 0.5, 1e-12);
  for (int t = 0; t < 6; ++t)
  {
    EXPECT_EQ(a.terms[t].name, names[t]);
    EXPECT_NEAR(a.terms[t].effect, effects[t], 1e-12);
    const double ss = 8 * effects[t] * effects[t] / 4;
    EXPECT_NEAR(a.terms[t].sum_sq, ss, 1e-12);
    EXPECT_NEAR(a.terms[t].f, ss / 0.5, 1e-10);
    EXPECT_NEAR(a.terms[t].p, 2 / std::numbers::pi * std::atan(1 / std::sqrt(ss / 0.5)), 1e-12);
  }
  // A: F = 32/0.5 = 64, p = (2/pi) atan(1/8) = 0.0792.
  EXPECT_NEAR(a.terms[0].p, 0.07916, 1e-5);
}

// A 2^5 with known main effects and interactions and a pooled error of
// known size: every effect comes back, and the sums of squares add up.
TEST(Study, KnownEffectsTwoToTheFive)
{
  auto coded = yates(5);
  std::vector<double> y;
  const double main[5] = {-3, 0.5, 0, 1.5, 8};
  for (auto& x : coded)
  {
    double v = 20;
    for (int i = 0; i < 5; ++i)
      v += main[i] / 2 * x[i];
    v += 0.4 / 2 * x[0] * x[4]; // A:E = 0.4
    v += 0.1 * x[1] * x[2] * x[3]; // a three-way term: error
    v += 0.05 * x[0] * x[1] * x[2] * x[3] * x[4]; // and a five-way one
    y.push_back(v);
  }
  auto a = factorial_anova(coded, y, {"A", "B", "C", "D", "E"});
  ASSERT_EQ(a.terms.size(), 15u);
  EXPECT_EQ(a.error_df, 16);
  for (int i = 0; i < 5; ++i)
    EXPECT_NEAR(a.terms[i].effect, main[i], 1e-12) << a.terms[i].name;
  for (std::size_t t = 5; t < 15; ++t)
    EXPECT_NEAR(a.terms[t].effect, a.terms[t].name == "A:E" ? 0.4 : 0.0, 1e-12) << a.terms[t].name;
  // Error: 32 (0.1^2 + 0.05^2) = 0.4.
  EXPECT_NEAR(a.error_sum_sq, 0.4, 1e-10);
  double sum = a.error_sum_sq;
  for (auto& t : a.terms)
    sum += t.sum_sq;
  EXPECT_NEAR(sum, a.total_sum_sq, 1e-9);
  // The IOP-like factor E dominates with p far below any threshold; C,
  // absent, has p = 1.
  EXPECT_LT(a.terms[4].p, 1e-20);
  EXPECT_NEAR(a.terms[2].p, 1.0, 1e-12);
  // F for A: SS = 32 * 9 / 4 = 72 against 0.4 / 16.
  EXPECT_NEAR(a.terms[0].f, 72 / (0.4 / 16), 1e-6);
}

TEST(Study, NotAFullFactorial)
{
  auto coded = yates(2);
  coded[3] = coded[0];
  EXPECT_THROW(factorial_anova(coded, {1, 2, 3, 4}, {"A", "B"}), std::invalid_argument);
  EXPECT_THROW(factorial_anova(yates(2), {1, 2, 3}, {"A", "B"}), std::invalid_argument);
}

// x = 1..4 and y = 2x + 1 are perfectly correlated; z = (1, -1, -1, 1) is
// orthogonal to x (sum of centred products -1.5 + 0.5 - 0.5 + 1.5 = 0);
// w = -x gives -1; a constant has no correlation.
TEST(Study, Pearson)
{
  auto r = nct::study::pearson({{1, 2, 3, 4}, {3, 5, 7, 9}, {1, -1, -1, 1}, {-1, -2, -3, -4},
                                {2, 2, 2, 2}});
  EXPECT_NEAR(r[0][1], 1, 1e-15);
  EXPECT_NEAR(r[0][2], 0, 1e-15);
  EXPECT_NEAR(r[0][3], -1, 1e-15);
  EXPECT_NEAR(r[2][2], 1, 1e-15);
  EXPECT_TRUE(std::isnan(r[0][4]));
  // x against (1, 3, 2, 4): centred (-1.5, 0.5, -0.5, 1.5), r = 4/5.
  auto s = nct::study::pearson({{1, 2, 3, 4}, {1, 3, 2, 4}});
  EXPECT_NEAR(s[0][1], 0.8, 1e-15);
  EXPECT_NEAR(s[1][0], 0.8, 1e-15);
}

TEST(Study, LevelMeans)
{
  auto m = nct::study::level_means({8, 22, 8, 22}, {8, 22}, {1, 2, 3, 5});
  EXPECT_DOUBLE_EQ(m[0], 2);
  EXPECT_DOUBLE_EQ(m[1], 3.5);
}

// The study file: the factorial's cases in Yates order and the one-factor
// sweep about the base scene, with the overrides they pass to nct run.
TEST(Study, Designs)
{
  const auto dir = std::filesystem::temp_directory_path();
  const std::string scene = std::string(NCT_SOURCE_DIR) + "/scenes/default.toml";
  std::ofstream(dir / "nct_study_factorial.toml")
      << "[study]\nscene = \"" << scene << "\"\nresponses = [\"peak_distance_mm\"]\n"
      << "set = [\"fem.degree=1\"]\n"
      << "[[factor]]\nkey = [\"material.cornea.c10\", \"material.limbus.c10\"]\nlabel = \"C10\"\n"
      << "levels = [0.05, 0.1]\n"
      << "[[factor]]\nkey = \"cavity.model\"\nlevels = [\"closed\", \"constant_pressure\"]\n";
  auto f = nct::study::Study::load(dir / "nct_study_factorial.toml");
  ASSERT_EQ(f.cases.size(), 4u);
  EXPECT_EQ(f.factors[1].label, "cavity.model");
  EXPECT_EQ(f.cases[1].levels, (std::vector<int>{1, 0}));
  EXPECT_EQ(f.cases[1].sets,
            (std::vector<std::string>{"fem.degree=1", "material.cornea.c10=0.1",
                                      "material.limbus.c10=0.1", "cavity.model='closed'"}));
  EXPECT_EQ(f.cases[2].sets.back(), "cavity.model='constant_pressure'");

  // One factor at a time: the base (IOP 15), then each level that differs
  // from it.
  std::ofstream(dir / "nct_study_ofat.toml")
      << "[study]\nscene = \"" << scene << "\"\ndesign = \"ofat\"\n"
      << "responses = [\"deflection_amplitude_mm\", \"a1_time_ms\"]\n"
      << "[[factor]]\nkey = \"inflate.iop\"\nlevels = [10.0, 15.0, 20.0]\n"
      << "[[factor]]\nkey = \"material.cornea.k2\"\nlevels = [50.0, 200.0]\n";
  auto o = nct::study::Study::load(dir / "nct_study_ofat.toml");
  ASSERT_EQ(o.cases.size(), 5u);
  EXPECT_EQ(o.base_values, (std::vector<double>{15, 100}));
  EXPECT_EQ(o.cases[0].sets.size(), 0u);
  EXPECT_EQ(o.cases[2].sets, (std::vector<std::string>{"inflate.iop=20.0"}));
  EXPECT_EQ(o.cases[4].levels, (std::vector<int>{-1, 1}));
}

// A table design: a case per row of its CSV, a column per factor's label
// (in any order), the values passed on exactly; the levels are each
// factor's distinct values in the order met.
TEST(Study, TableDesign)
{
  const auto dir = std::filesystem::temp_directory_path();
  const std::string scene = std::string(NCT_SOURCE_DIR) + "/scenes/default.toml";
  std::ofstream(dir / "nct_study_table.csv")
      << "IOP, C10\n12.5,0.1\n\n20.0,0.1\n12.5,0.0523456789012345\n";
  std::ofstream(dir / "nct_study_table.toml")
      << "[study]\nscene = \"" << scene << "\"\ndesign = \"table\"\n"
      << "cases = \"nct_study_table.csv\"\nresponses = [\"deflection_amplitude_mm\"]\n"
      << "[[factor]]\nkey = [\"material.cornea.c10\", \"material.limbus.c10\"]\nlabel = \"C10\"\n"
      << "[[factor]]\nkey = \"inflate.iop\"\nlabel = \"IOP\"\n";
  auto t = nct::study::Study::load(dir / "nct_study_table.toml");
  ASSERT_EQ(t.cases.size(), 3u);
  EXPECT_EQ(t.cases[0].levels, (std::vector<int>{0, 0}));
  EXPECT_EQ(t.cases[1].levels, (std::vector<int>{0, 1}));
  EXPECT_EQ(t.cases[2].levels, (std::vector<int>{1, 0}));
  EXPECT_EQ(t.cases[2].sets,
            (std::vector<std::string>{"material.cornea.c10=0.0523456789012345",
                                      "material.limbus.c10=0.0523456789012345",
                                      "inflate.iop=12.5"}));
  EXPECT_EQ(t.factor_value(t.cases[1], 1), 20.0);
  EXPECT_EQ(std::stod(t.factors[0].levels[1]), 0.0523456789012345);

  // A repeated row is the same case; a column no factor names is refused.
  std::ofstream(dir / "nct_study_table.csv") << "IOP,C10\n12.5,0.1\n12.5,0.1\n";
  EXPECT_THROW(
      {
        try
        {
          nct::study::Study::load(dir / "nct_study_table.toml");
        }
        catch (const std::exception& e)
        {
          EXPECT_NE(std::string(e.what()).find("nct_study_table.csv:3: the same case as line 2"),
                    std::string::npos)
              << e.what();
          throw;
        }
      },
      std::exception);
  std::ofstream(dir / "nct_study_table.csv") << "IOP,C10,k1\n12.5,0.1,1\n";
  EXPECT_THROW(nct::study::Study::load(dir / "nct_study_table.toml"), std::exception);

  // A factor's range (the box a design fills): a value outside it is
  // refused with its line; the ends are inside.
  std::ofstream(dir / "nct_study_table.toml", std::ios::app)
      << "range = [8.0, 35.0]\n";
  std::ofstream(dir / "nct_study_table.csv") << "IOP,C10\n8.0,0.1\n35.0,0.1\n";
  EXPECT_EQ(nct::study::Study::load(dir / "nct_study_table.toml").factors[1].range,
            (std::vector<double>{8, 35}));
  std::ofstream(dir / "nct_study_table.csv") << "IOP,C10\n8.0,0.1\n35.5,0.1\n";
  try
  {
    nct::study::Study::load(dir / "nct_study_table.toml");
    ADD_FAILURE() << "IOP = 35.5 outside [8, 35] was accepted";
  }
  catch (const std::exception& e)
  {
    EXPECT_NE(std::string(e.what()).find("nct_study_table.csv:3: IOP = 35.5 is outside its range "
                                         "[8, 35]"),
              std::string::npos)
        << e.what();
  }
}

// An ablation against its baseline, worked by hand. Baseline 2: 3 is
// +1 (+50 %), 1.5 is -0.5 (-25 %); a failed case has no value and no
// difference. A negative baseline -4: -3 is +1, 100 * 1 / |-4| = +25 %.
// A zero baseline has differences but no percents; a missing one has
// neither.
TEST(Study, CompareToBaselineByHand)
{
  const double nan = std::numeric_limits<double>::quiet_NaN();
  auto c = nct::study::compare_to_baseline({2.0, 3.0, 1.5, nan});
  ASSERT_EQ(c.size(), 4u);
  EXPECT_DOUBLE_EQ(c[0].value, 2);
  EXPECT_DOUBLE_EQ(c[0].difference, 0);
  EXPECT_DOUBLE_EQ(c[0].percent, 0);
  EXPECT_DOUBLE_EQ(c[1].difference, 1);
  EXPECT_DOUBLE_EQ(c[1].percent, 50);
  EXPECT_DOUBLE_EQ(c[2].value, 1.5);
  EXPECT_DOUBLE_EQ(c[2].difference, -0.5);
  EXPECT_DOUBLE_EQ(c[2].percent, -25);
  EXPECT_TRUE(std::isnan(c[3].value));
  EXPECT_TRUE(std::isnan(c[3].difference));
  EXPECT_TRUE(std::isnan(c[3].percent));

  auto negative = nct::study::compare_to_baseline({-4.0, -3.0, -6.0});
  EXPECT_DOUBLE_EQ(negative[1].difference, 1);
  EXPECT_DOUBLE_EQ(negative[1].percent, 25);
  EXPECT_DOUBLE_EQ(negative[2].difference, -2);
  EXPECT_DOUBLE_EQ(negative[2].percent, -50);

  auto zero = nct::study::compare_to_baseline({0.0, 0.5, -0.25});
  EXPECT_DOUBLE_EQ(zero[0].difference, 0);
  EXPECT_DOUBLE_EQ(zero[1].difference, 0.5);
  EXPECT_DOUBLE_EQ(zero[2].difference, -0.25);
  for (auto& z : zero)
    EXPECT_TRUE(std::isnan(z.percent));

  // The baseline's case failed: the variants keep their values only.
  auto no_base = nct::study::compare_to_baseline({nan, 1.0, std::numeric_limits<double>::infinity()});
  EXPECT_DOUBLE_EQ(no_base[1].value, 1);
  EXPECT_TRUE(std::isnan(no_base[1].difference));
  EXPECT_TRUE(std::isnan(no_base[1].percent));
  EXPECT_TRUE(std::isnan(no_base[2].value)); // an infinity is no value

  EXPECT_THROW(nct::study::compare_to_baseline({}), std::invalid_argument);
}

// An ablation file: one case per variant in order, the study's overrides
// first, then the variant's; the first variant is the baseline.
TEST(Study, AblationVariants)
{
  const auto dir = std::filesystem::temp_directory_path();
  const std::string scene = std::string(NCT_SOURCE_DIR) + "/scenes/default.toml";
  std::ofstream(dir / "nct_study_ablation.toml")
      << "[study]\nscene = \"" << scene << "\"\ndesign = \"ablation\"\n"
      << "responses = [\"peak_distance_mm\"]\nset = [\"fem.degree=1\"]\n"
      << "[[variant]]\nname = \"baseline\"\nset = []\n"
      << "[[variant]]\nname = \"stiff_cornea\"\ndescription = \"C10 doubled\"\n"
      << "set = [\"material.cornea.c10=0.1\", \"material.limbus.c10=0.1\"]\n"
      << "[[variant]]\nname = \"constant_iop\"\nset = [\"cavity.model='constant_pressure'\"]\n";
  auto a = nct::study::Study::load(dir / "nct_study_ablation.toml");
  EXPECT_EQ(a.design, "ablation");
  EXPECT_TRUE(a.factors.empty());
  ASSERT_EQ(a.variants.size(), 3u);
  ASSERT_EQ(a.cases.size(), 3u);
  EXPECT_EQ(a.variants[1].name, "stiff_cornea");
  EXPECT_EQ(a.variants[1].description, "C10 doubled");
  EXPECT_EQ(a.cases[0].sets, (std::vector<std::string>{"fem.degree=1"}));
  EXPECT_EQ(a.cases[1].sets,
            (std::vector<std::string>{"fem.degree=1", "material.cornea.c10=0.1",
                                      "material.limbus.c10=0.1"}));
  EXPECT_EQ(a.cases[2].variant, 2);
  EXPECT_EQ(a.cases[2].sets.back(), "cavity.model='constant_pressure'");

  // A variant that sets a key to its default makes the baseline's scene.
  std::ofstream(dir / "nct_study_ablation_same.toml")
      << "[study]\nscene = \"" << scene << "\"\ndesign = \"ablation\"\n"
      << "responses = [\"peak_distance_mm\"]\n"
      << "[[variant]]\nname = \"baseline\"\n"
      << "[[variant]]\nname = \"closed\"\nset = [\"cavity.model='closed'\"]\n";
  try
  {
    nct::study::Study::load(dir / "nct_study_ablation_same.toml");
    ADD_FAILURE() << "two variants of the same scene were accepted";
  }
  catch (const nct::scene::Error& e)
  {
    EXPECT_NE(std::string(e.what()).find("'closed' makes the same scene as 'baseline'"),
              std::string::npos)
        << e.what();
  }
}
