// A posterior by Markov chain Monte Carlo: the affine-invariant ensemble
// sampler's stretch move (Goodman and Weare 2010, Comm. App. Math. Comp.
// Sci. 5:65; the algorithm of emcee, Foreman-Mackey et al. 2013, PASP
// 125:306). Each walker x_k moves towards or away from another x_j:
//
//   y = x_j + z (x_k - x_j),  g(z) ~ 1/sqrt(z) on [1/a, a] (a = 2),
//   accepted with probability min(1, z^(n-1) p(y) / p(x_k)),
//
// which leaves p invariant and is unaffected by how the parameters
// correlate (the valley where IOP and stiffness trade off).
#pragma once

#include <functional>
#include <vector>

namespace nct::fit
{

/// A sampled posterior.
struct Chain
{
  std::vector<std::vector<double>> samples; ///< after the burn-in, walker by walker each step
  std::vector<double> log_p;                ///< per sample
  double acceptance = 0;                    ///< the share of moves accepted
  std::vector<double> autocorrelation;      ///< integrated autocorrelation time, steps, per variable
  int steps = 0, burn_in = 0, walkers = 0;
};

/// Sample log_p (-infinity outside its support) with an ensemble started
/// at `start` (one point per walker, each with finite log_p), `steps`
/// steps of which the first `burn_in` are dropped, with a seeded generator.
Chain sample(const std::function<double(const std::vector<double>&)>& log_p,
             std::vector<std::vector<double>> start, int steps, int burn_in, int seed);

/// The q-quantile of values (linear between order statistics).
double quantile(std::vector<double> values, double q);

} // namespace nct::fit
