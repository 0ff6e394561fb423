#include "study/analysis.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <set>
#include <stdexcept>

#include <boost/math/distributions/fisher_f.hpp>

#include "io/format.h"

namespace nct::study
{
using io::nan;

Anova factorial_anova(const std::vector<std::vector<int>>& coded,
                      const std::vector<double>& y, const std::vector<std::string>& labels)
{
  const std::size_t n = y.size(), k = labels.size();
  if (coded.size() != n || n != (std::size_t(1) << k))
    throw std::invalid_argument("a 2^" + std::to_string(k) + " factorial needs "
                                + std::to_string(std::size_t(1) << k) + " cases, got "
                                + std::to_string(n));
  std::set<std::vector<int>> seen;
  for (const auto& row : coded)
  {
    if (row.size() != k)
      throw std::invalid_argument("a case has " + std::to_string(row.size()) + " coded levels, not "
                                  + std::to_string(k));
    for (int x : row)
      if (x != -1 && x != 1)
        throw std::invalid_argument("coded levels are -1 or +1");
    if (!seen.insert(row).second)
      throw std::invalid_argument("a combination of levels occurs twice: not a full factorial");
  }

  Anova a;
  const double mean = std::accumulate(y.begin(), y.end(), 0.0) / n;
  a.total_sum_sq = 0;
  for (double v : y)
    a.total_sum_sq += (v - mean) * (v - mean);
  a.total_df = int(n) - 1;

  auto term = [&](std::vector<int> factors)
  {
    Term t{"", factors, 0, 0, 0, 0, 0};
    for (std::size_t c = 0; c < n; ++c)
    {
      int x = 1;
      for (int i : factors)
        x *= coded[c][i];
      t.effect += x * y[c];
    }
    t.effect *= 2.0 / n;
    t.sum_sq = n * t.effect * t.effect / 4;
    t.percent = a.total_sum_sq > 0 ? 100 * t.sum_sq / a.total_sum_sq : 0;
    for (std::size_t j = 0; j < factors.size(); ++j)
      t.name += (j ? ":" : "") + labels[factors[j]];
    return t;
  };
  for (std::size_t i = 0; i < k; ++i)
    a.terms.push_back(term({int(i)}));
  for (std::size_t i = 0; i < k; ++i)
    for (std::size_t j = i + 1; j < k; ++j)
      a.terms.push_back(term({int(i), int(j)}));

  // The orthogonal contrasts split the total exactly: the error is what
  // the model's terms leave.
  a.error_df = a.total_df - int(a.terms.size());
  a.error_sum_sq = a.total_sum_sq;
  for (const Term& t : a.terms)
    a.error_sum_sq -= t.sum_sq;
  // Round-off of an exact fit; nothing at all without error dof.
  a.error_sum_sq = a.error_df > 0 ? std::max(a.error_sum_sq, 0.0) : 0.0;
  for (Term& t : a.terms)
  {
    if (a.error_df <= 0)
    {
      t.f = t.p = nan;
      continue;
    }
    const double ms_error = a.error_sum_sq / a.error_df;
    // An exact fit (no error at all) makes every nonzero term infinitely
    // significant.
    if (ms_error <= 1e-300)
    {
      t.f = t.sum_sq > 0 ? std::numeric_limits<double>::infinity() : nan;
      t.p = t.sum_sq > 0 ? 0.0 : nan;
      continue;
    }
    t.f = t.sum_sq / ms_error;
    boost::math::fisher_f_distribution<double> dist(1.0, a.error_df);
    t.p = boost::math::cdf(boost::math::complement(dist, t.f));
  }
  return a;
}

std::vector<std::vector<double>> pearson(const std::vector<std::vector<double>>& columns)
{
  const std::size_t m = columns.size();
  std::vector<std::vector<double>> r(m, std::vector<double>(m));
  std::vector<std::vector<double>> centred = columns;
  std::vector<double> norm(m);
  for (std::size_t i = 0; i < m; ++i)
  {
    auto& c = centred[i];
    if (c.size() != columns[0].size())
      throw std::invalid_argument("pearson: columns of different lengths");
    const double mean = std::accumulate(c.begin(), c.end(), 0.0) / c.size();
    double largest = 0;
    for (double& v : c)
    {
      largest = std::max(largest, std::abs(v));
      v -= mean;
    }
    norm[i] = std::sqrt(std::inner_product(c.begin(), c.end(), c.begin(), 0.0));
    // A column constant up to round-off has no correlation.
    if (norm[i] <= 1e-13 * largest * std::sqrt(double(c.size())))
      norm[i] = 0;
  }
  for (std::size_t i = 0; i < m; ++i)
    for (std::size_t j = 0; j < m; ++j)
      r[i][j] = norm[i] == 0 || norm[j] == 0
                    ? nan
                    : std::inner_product(centred[i].begin(), centred[i].end(),
                                         centred[j].begin(), 0.0)
                          / (norm[i] * norm[j]);
  return r;
}

std::vector<double> level_means(const std::vector<double>& factor, const std::vector<double>& levels,
                                const std::vector<double>& y)
{
  std::vector<double> means;
  for (double level : levels)
  {
    double sum = 0;
    int count = 0;
    for (std::size_t c = 0; c < y.size(); ++c)
      if (factor[c] == level)
      {
        sum += y[c];
        ++count;
      }
    means.push_back(count ? sum / count : std::numeric_limits<double>::quiet_NaN());
  }
  return means;
}

std::vector<Comparison> compare_to_baseline(const std::vector<double>& y)
{
  if (y.empty())
    throw std::invalid_argument("compare_to_baseline: no baseline");
  const double base = y[0];
  std::vector<Comparison> out;
  for (double v : y)
  {
    Comparison c{std::isfinite(v) ? v : nan, nan, nan}; // an infinity is no value either
    if (std::isfinite(v) && std::isfinite(base))
    {
      c.difference = v - base;
      if (base != 0)
        c.percent = 100 * c.difference / std::abs(base);
    }
    out.push_back(c);
  }
  return out;
}

} // namespace nct::study
