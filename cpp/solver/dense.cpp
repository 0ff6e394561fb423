#include "solver/dense.h"

#include <cmath>
#include <utility>

namespace nct::solver
{

std::vector<double> solve_dense(std::vector<double> S, std::vector<double> r)
{
  const std::size_t n = r.size();
  for (std::size_t k = 0; k < n; ++k)
  {
    std::size_t p = k;
    for (std::size_t i = k + 1; i < n; ++i)
      if (std::abs(S[i * n + k]) > std::abs(S[p * n + k]))
        p = i;
    if (S[p * n + k] == 0)
      return std::vector<double>(n, std::nan(""));
    for (std::size_t j = 0; j < n; ++j)
      std::swap(S[k * n + j], S[p * n + j]);
    std::swap(r[k], r[p]);
    for (std::size_t i = k + 1; i < n; ++i)
    {
      const double f = S[i * n + k] / S[k * n + k];
      for (std::size_t j = k; j < n; ++j)
        S[i * n + j] -= f * S[k * n + j];
      r[i] -= f * r[k];
    }
  }
  for (std::size_t k = n; k-- > 0;)
  {
    for (std::size_t j = k + 1; j < n; ++j)
      r[k] -= S[k * n + j] * r[j];
    r[k] /= S[k * n + k];
  }
  return r;
}

} // namespace nct::solver
