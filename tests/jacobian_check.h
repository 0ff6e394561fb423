// The Jacobian of a monolithic system against central differences of its
// residual, block by block (the fields' rows and columns).
#pragma once

#include <array>
#include <cmath>
#include <cstdio>
#include <string>
#include <vector>

#include <dolfinx/la/Vector.h>
#include <dolfinx/la/petsc.h>
#include <mpi.h>

#include "solver/monolithic.h"
#include "solver/newton.h"

namespace nct::test
{

/// A smooth pseudo-random number in [-1, 1] of a place and a seed (the
/// same on every rank).
inline double wiggle(const double* x, double seed)
{
  const double s = std::sin(12.9898 * x[0] + 78.233 * x[1] + 37.719 * x[2] + seed) * 43758.5453;
  return 2 * (s - std::floor(s)) - 1;
}

inline double norm(const dolfinx::la::Vector<double>& v)
{
  const std::int32_t n = v.map()->size_local();
  double s = 0;
  for (std::int32_t i = 0; i < n; ++i)
    s += v.array()[i] * v.array()[i];
  MPI_Allreduce(MPI_IN_PLACE, &s, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  return std::sqrt(s);
}

/// A monolithic Jacobian J against central differences of the residual R
/// in a direction d: per column field c (d restricted to it, the last
/// "c" the whole d) and row field r, |(R(x + e d) - R(x - e d)) / 2e - J d|,
/// the differences' own norm |(R(x + e d) - R(x - e d)) / 2e| and |J d|
/// over the rows of r, for e = eps and eps / 2.
struct JacobianCheck
{
  std::vector<std::string> fields;
  /// [c][r][k]: the error and the differences' norm at e = eps / 2^k; |J d|.
  std::vector<std::vector<std::array<double, 2>>> error, differences;
  std::vector<std::vector<double>> Jd;
  /// The whole direction's relative error |error| / |J d| at eps, eps / 2.
  std::array<double, 2> relative;
};

/// J = system.jacobian at x0 (into A, which has its pattern) against the
/// differences of system.residual about x0 in the direction d (zero
/// where the unknowns are held); prints the blocks under `title`. Leaves
/// x at the last difference's state.
inline JacobianCheck check_blocks(const solver::System& system,
                                  const solver::Monolithic& unknowns, Mat A,
                                  const dolfinx::la::Vector<double>& d,
                                  const dolfinx::la::Vector<double>& x0, double eps,
                                  const std::string& title)
{
  {
    auto x = system.x->mutable_array();
    std::copy(x0.array().begin(), x0.array().end(), x.begin());
  }
  system.jacobian(A);
  const std::size_t n = unknowns.fields();
  JacobianCheck out;
  for (std::size_t c = 0; c < n; ++c)
    out.fields.push_back(unknowns.field(c).name);
  // The rows of field r of v, as a vector of its own.
  auto rows = [&](const dolfinx::la::Vector<double>& v, std::size_t r)
  {
    dolfinx::la::Vector<double> part(v.map(), 1);
    std::vector<double> block(unknowns.owned(r));
    unknowns.extract(r, v, block);
    unknowns.insert(r, block, part);
    return norm(part);
  };
  for (std::size_t c = 0; c <= n; ++c)
  {
    dolfinx::la::Vector<double> dc(d.map(), 1);
    for (std::size_t f2 = 0; f2 < n; ++f2)
      if (c == n || f2 == c)
      {
        std::vector<double> block(unknowns.owned(f2));
        unknowns.extract(f2, d, block);
        unknowns.insert(f2, block, dc);
      }
    dc.scatter_fwd();
    dolfinx::la::Vector<double> Jd(d.map(), 1), r_plus(d.map(), 1), r_minus(d.map(), 1);
    Vec d_petsc = dolfinx::la::petsc::create_vector_wrap(dc);
    Vec Jd_petsc = dolfinx::la::petsc::create_vector_wrap(Jd);
    MatMult(A, d_petsc, Jd_petsc);
    VecDestroy(&d_petsc);
    VecDestroy(&Jd_petsc);
    out.error.emplace_back(n);
    out.differences.emplace_back(n);
    out.Jd.emplace_back(n);
    for (std::size_t r = 0; r < n; ++r)
      out.Jd[c][r] = rows(Jd, r);
    std::vector<double> g(system.y ? system.y->size() : 0);
    for (int k = 0; k < 2; ++k)
    {
      const double e = eps / (1 << k);
      for (auto [sign, r] : {std::pair{1.0, &r_plus}, std::pair{-1.0, &r_minus}})
      {
        auto x = system.x->mutable_array();
        for (std::size_t i = 0; i < x.size(); ++i)
          x[i] = x0.array()[i] + sign * e * dc.array()[i];
        system.residual(*r, g);
      }
      dolfinx::la::Vector<double> diff(d.map(), 1), fd(d.map(), 1);
      for (std::size_t i = 0; i < diff.array().size(); ++i)
      {
        fd.mutable_array()[i] = (r_plus.array()[i] - r_minus.array()[i]) / (2 * e);
        diff.mutable_array()[i] = fd.array()[i] - Jd.array()[i];
      }
      for (std::size_t r = 0; r < n; ++r)
      {
        out.error[c][r][k] = rows(diff, r);
        out.differences[c][r][k] = rows(fd, r);
      }
      if (c == n)
        out.relative[k] = norm(diff) / norm(Jd);
    }
  }
  std::printf("%s, %lld unknowns, e = %g: relative error of the whole %.3e (%.3e at e / 2, "
              "ratio %.2f)\n",
              title.c_str(), (long long)unknowns.size_global(), eps, out.relative[0],
              out.relative[1], out.relative[0] / out.relative[1]);
  for (std::size_t c = 0; c < n; ++c)
    for (std::size_t r = 0; r < n; ++r)
      std::printf("  rows %-11s columns %-11s |J d| %.3e  differences %.3e  error %.3e, "
                  "%.3e at e / 2\n",
                  out.fields[r].c_str(), out.fields[c].c_str(), out.Jd[c][r],
                  out.differences[c][r][1], out.error[c][r][0], out.error[c][r][1]);
  return out;
}

/// The blocks (rows, columns) whose error exceeds 1e-5 of the
/// differences' own norm there, every block compared, a zero one too:
/// a block missing from J (|J d| = 0 where the differences are not)
/// fails. The floor, 1e-9 of the largest block's differences, is the
/// round-off of the differences (about 1e-16 |R| / e) in a block J
/// rightly leaves empty.
inline std::vector<std::string> wrong_blocks(const JacobianCheck& check)
{
  const std::size_t n = check.fields.size();
  double largest = 0;
  for (std::size_t c = 0; c < n; ++c)
    for (std::size_t r = 0; r < n; ++r)
      largest = std::max(largest, check.differences[c][r][1]);
  std::vector<std::string> wrong;
  for (std::size_t c = 0; c < n; ++c)
    for (std::size_t r = 0; r < n; ++r)
      if (check.error[c][r][1] > 1e-5 * check.differences[c][r][1] + 1e-9 * largest)
        wrong.push_back(check.fields[r] + "/" + check.fields[c]);
  return wrong;
}

} // namespace nct::test
