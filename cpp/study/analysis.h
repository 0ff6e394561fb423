// Statistics of a study's cases: two-level factorial effects and ANOVA,
// Pearson correlations, main effects, an ablation's differences from its
// baseline. Pure functions of the case table.
#pragma once

#include <string>
#include <vector>

namespace nct::study
{

/// One term of a two-level factorial model: a main factor or a two-way
/// interaction. With factors coded x = -1 (first level) and +1 (second),
/// effect = mean(y | x_term = +1) - mean(y | x_term = -1)
///        = (2/N) sum_n x_term,n y_n,
/// sum_sq = N effect^2 / 4 (1 degree of freedom) (Montgomery, Design and
/// Analysis of Experiments, 8th ed., section 6.3).
struct Term
{
  std::string name;         ///< "A" or "A:B", from the factor labels
  std::vector<int> factors; ///< indices of its one or two factors
  double effect;
  double sum_sq;
  double percent; ///< 100 sum_sq / total sum_sq: the effect size eta^2 in %
  double f;       ///< mean square / error mean square; NaN without error dof
  double p;       ///< P(F(1, error_df) > f); NaN without error dof
};

/// The ANOVA of a 2^k full factorial without replication on main factors
/// and two-way interactions. The error term pools the interactions of
/// three and more factors (the sparsity-of-effects principle): 2^k - 1 -
/// k - k(k-1)/2 degrees of freedom, none for k <= 2, where F and p are
/// NaN. A deterministic simulation has no replication error.
struct Anova
{
  std::vector<Term> terms; ///< main factors, then interactions (A:B, A:C, ..., B:C, ...)
  double error_sum_sq;
  int error_df;
  double total_sum_sq; ///< about the mean
  int total_df;
};

/// The ANOVA of responses y of the 2^k cases with coded levels
/// coded[n][i] = +-1 of factor i in case n. Each combination must occur
/// exactly once (throws std::invalid_argument otherwise).
Anova factorial_anova(const std::vector<std::vector<int>>& coded,
                      const std::vector<double>& y, const std::vector<std::string>& labels);

/// Pearson's correlation r of every pair of columns (each a variable over
/// the cases): r = sum (a - mean a)(b - mean b) / sqrt(sum (a - mean a)^2
/// sum (b - mean b)^2). NaN where a column is constant.
std::vector<std::vector<double>> pearson(const std::vector<std::vector<double>>& columns);

/// The mean response at each distinct value of a factor, in order of
/// first appearance of the level in `levels` (main-effects plot data).
std::vector<double> level_means(const std::vector<double>& factor, const std::vector<double>& levels,
                                const std::vector<double>& y);

/// One variant's response against the baseline's (an ablation study).
struct Comparison
{
  double value;      ///< the variant's response; NaN when it gave none
  double difference; ///< value - baseline; NaN when either is missing
  double percent;    ///< 100 difference / |baseline|; NaN when either is missing or the
                     ///< baseline is 0
};

/// Each variant's response y[v] against the baseline's, y[0] (NaN: the
/// case gave no value). The baseline's own row is 0 difference, 0 %.
std::vector<Comparison> compare_to_baseline(const std::vector<double>& y);

} // namespace nct::study
