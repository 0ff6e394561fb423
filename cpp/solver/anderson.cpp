#include "solver/anderson.h"

#include <algorithm>
#include <cmath>

#include "solver/dense.h"

namespace nct::solver
{

Anderson::Anderson(MPI_Comm comm, int depth, std::size_t global)
    : _comm(comm), _depth(static_cast<std::size_t>(std::max(depth, 1))), _global(global)
{
}

std::vector<double>
Anderson::dots(const std::vector<std::pair<const double*, const double*>>& pairs,
               std::size_t n) const
{
  const std::size_t owned = n - _global;
  std::vector<double> s(pairs.size(), 0.0);
  for (std::size_t k = 0; k < pairs.size(); ++k)
    for (std::size_t i = 0; i < owned; ++i)
      s[k] += pairs[k].first[i] * pairs[k].second[i];
  MPI_Allreduce(MPI_IN_PLACE, s.data(), static_cast<int>(s.size()), MPI_DOUBLE, MPI_SUM, _comm);
  for (std::size_t k = 0; k < pairs.size(); ++k)
    for (std::size_t i = owned; i < n; ++i)
      s[k] += pairs[k].first[i] * pairs[k].second[i];
  return s;
}

void Anderson::accelerate(std::span<const double> x, std::span<double> f)
{
  const std::size_t n = x.size();
  if (_have_last)
  {
    std::vector<double> dx(n), df(n);
    for (std::size_t i = 0; i < n; ++i)
      dx[i] = x[i] - _x_last[i], df[i] = f[i] - _f_last[i];
    _dX.push_back(std::move(dx)), _dF.push_back(std::move(df));
    if (_dF.size() > _depth)
      _dX.erase(_dX.begin()), _dF.erase(_dF.begin());
  }
  _x_last.assign(x.begin(), x.end());
  _f_last.assign(f.begin(), f.end());
  _have_last = true;
  const std::size_t m = _dF.size();
  if (m == 0)
    return;

  // The least-squares problem by its normal equations, the columns scaled
  // to unit length and a small ridge against near dependence.
  std::vector<std::pair<const double*, const double*>> pairs;
  for (std::size_t i = 0; i < m; ++i)
  {
    for (std::size_t j = i; j < m; ++j)
      pairs.push_back({_dF[i].data(), _dF[j].data()});
    pairs.push_back({_dF[i].data(), f.data()});
  }
  const std::vector<double> s = dots(pairs, n);
  std::vector<double> G(m * m), rhs(m), scale(m);
  std::size_t k = 0;
  for (std::size_t i = 0; i < m; ++i)
  {
    for (std::size_t j = i; j < m; ++j, ++k)
      G[i * m + j] = G[j * m + i] = s[k];
    rhs[i] = s[k++];
  }
  for (std::size_t i = 0; i < m; ++i)
    scale[i] = G[i * m + i] > 0 ? 1 / std::sqrt(G[i * m + i]) : 0.0;
  for (std::size_t i = 0; i < m; ++i)
  {
    for (std::size_t j = 0; j < m; ++j)
      G[i * m + j] *= scale[i] * scale[j];
    G[i * m + i] += 1e-10;
    rhs[i] *= scale[i];
  }
  std::vector<double> gamma = solve_dense(G, rhs);
  if (!std::all_of(gamma.begin(), gamma.end(), [](double g) { return std::isfinite(g); }))
  {
    reset();
    return;
  }
  for (std::size_t j = 0; j < m; ++j)
  {
    const double g = gamma[j] * scale[j];
    for (std::size_t i = 0; i < n; ++i)
      f[i] += g * (_dX[j][i] - _dF[j][i]);
  }
}

} // namespace nct::solver
