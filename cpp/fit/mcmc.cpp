// The ensemble sampler (cpp/fit/mcmc.h).
#include "fit/mcmc.h"

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

namespace nct::fit
{
namespace
{

/// Integrated autocorrelation time of the walkers' chains of one variable
/// (per walker, the chain after the burn-in): the walkers' mean
/// normalised autocorrelation function summed over Sokal's window, the
/// first M with M >= 5 tau(M) (emcee's estimate).
double autocorrelation_time(const std::vector<std::vector<double>>& chains)
{
  const std::size_t n = chains.at(0).size();
  std::vector<double> rho(n, 0.0);
  for (const auto& c : chains)
  {
    double mean = 0;
    for (double x : c)
      mean += x;
    mean /= double(n);
    std::vector<double> acf(n, 0.0);
    for (std::size_t t = 0; t < n; ++t)
      for (std::size_t i = 0; i + t < n; ++i)
        acf[t] += (c[i] - mean) * (c[i + t] - mean);
    if (acf[0] <= 0)
      continue;
    for (std::size_t t = 0; t < n; ++t)
      rho[t] += acf[t] / acf[0] / double(chains.size());
  }
  double tau = 1;
  for (std::size_t m = 1; m < n; ++m)
  {
    tau += 2 * rho[m];
    if (double(m) >= 5 * tau)
      return tau;
  }
  return tau;
}

} // namespace

Chain sample(const std::function<double(const std::vector<double>&)>& log_p,
             std::vector<std::vector<double>> x, int steps, int burn_in, int seed)
{
  const std::size_t k = x.size(), n = x.at(0).size();
  if (k < 2 * n || steps <= burn_in)
    throw std::invalid_argument("the sampler needs at least twice as many walkers as variables "
                                "and more steps than its burn-in");
  std::mt19937_64 rng{static_cast<std::uint64_t>(seed)};
  std::uniform_real_distribution<double> uniform(0.0, 1.0);
  std::uniform_int_distribution<std::size_t> other(0, k - 2);
  const double a = 2;
  std::vector<double> lp(k);
  for (std::size_t w = 0; w < k; ++w)
    if (!std::isfinite(lp[w] = log_p(x[w])))
      throw std::invalid_argument("a walker starts where the posterior is zero");
  Chain chain;
  chain.steps = steps, chain.burn_in = burn_in, chain.walkers = int(k);
  std::vector<std::vector<std::vector<double>>> trace(n, std::vector<std::vector<double>>(k));
  long accepted = 0, moves = 0;
  for (int s = 0; s < steps; ++s)
  {
    for (std::size_t w = 0; w < k; ++w)
    {
      std::size_t j = other(rng);
      j += j >= w;
      const double u = uniform(rng), z = std::pow((a - 1) * u + 1, 2) / a;
      std::vector<double> y(n);
      for (std::size_t i = 0; i < n; ++i)
        y[i] = x[j][i] + z * (x[w][i] - x[j][i]);
      const double ly = log_p(y);
      const double q = double(n - 1) * std::log(z) + ly - lp[w];
      ++moves;
      if (std::isfinite(ly) && std::log(uniform(rng)) < q)
        x[w] = y, lp[w] = ly, ++accepted;
    }
    if (s >= burn_in)
      for (std::size_t w = 0; w < k; ++w)
      {
        chain.samples.push_back(x[w]);
        chain.log_p.push_back(lp[w]);
        for (std::size_t i = 0; i < n; ++i)
          trace[i][w].push_back(x[w][i]);
      }
  }
  chain.acceptance = double(accepted) / double(moves);
  for (std::size_t i = 0; i < n; ++i)
    chain.autocorrelation.push_back(autocorrelation_time(trace[i]));
  return chain;
}

double quantile(std::vector<double> values, double q)
{
  std::sort(values.begin(), values.end());
  const double at = q * double(values.size() - 1);
  const std::size_t i = std::size_t(std::floor(at));
  if (i + 1 >= values.size())
    return values.back();
  return values[i] + (at - double(i)) * (values[i + 1] - values[i]);
}

} // namespace nct::fit
