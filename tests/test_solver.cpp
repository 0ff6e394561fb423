// The Anderson acceleration of a modified Newton iteration (solver/anderson.h)
// on a linear problem whose kept "Jacobian" P treats some modes badly:
// serially and on 2 ranks, with a global unknown (a bordered system's
// multiplier) that every rank holds.
#include <cmath>
#include <numeric>
#include <vector>

#include <gtest/gtest.h>
#include <mpi.h>

#include "solver/anderson.h"

namespace
{

constexpr int owned = 3; // entries per rank, then one global entry

/// The problem A x = b with A = diag(a), P = diag(p): the modified Newton
/// step is f = P^-1 (A x - b), whose iteration x -= f contracts mode i by
/// |1 - a_i / p_i|. Four distinct ratios, two of them outside (0, 2): the
/// plain iteration diverges; GMRES (and so Anderson) ends in as many steps
/// as there are distinct ratios.
struct Diagonal
{
  explicit Diagonal(int rank)
  {
    const double ratios[] = {0.5, 2.6, 1.2, 3.1};
    for (int i = 0; i <= owned; ++i)
    {
      const int global = i < owned ? owned * rank + i : -1; // -1: the global entry
      ratio.push_back(ratios[(global + 4) % 4]);
      b.push_back(1.0 + 0.1 * global);
    }
  }
  std::vector<double> step(const std::vector<double>& x) const
  {
    std::vector<double> f(x.size());
    for (std::size_t i = 0; i < x.size(); ++i)
      f[i] = ratio[i] * x[i] - b[i]; // P = 1, A = diag(ratio)
    return f;
  }
  std::vector<double> ratio, b;
};

double max_norm(const std::vector<double>& v)
{
  double m = 0;
  for (double x : v)
    m = std::max(m, std::abs(x));
  MPI_Allreduce(MPI_IN_PLACE, &m, 1, MPI_DOUBLE, MPI_MAX, MPI_COMM_WORLD);
  return m;
}

} // namespace

TEST(Solver, AndersonEndsWhereTheKeptJacobianDiverges)
{
  int rank;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  const Diagonal problem(rank);
  auto iterate = [&](int depth)
  {
    nct::solver::Anderson anderson(MPI_COMM_WORLD, std::max(depth, 1), 1);
    std::vector<double> x(owned + 1, 0.0);
    std::vector<double> history;
    for (int k = 0; k < 12; ++k)
    {
      std::vector<double> f = problem.step(x);
      history.push_back(max_norm(f));
      if (depth > 0)
        anderson.accelerate(x, f);
      for (std::size_t i = 0; i < x.size(); ++i)
        x[i] -= f[i];
    }
    history.push_back(max_norm(problem.step(x)));
    return history;
  };
  const auto plain = iterate(0), accelerated = iterate(4);
  // The plain iteration grows by about 2.1 (the mode at ratio 3.1) a step.
  EXPECT_GT(plain.back(), 100 * plain.front());
  // Anderson: four distinct ratios, four secants, then the solution (to the
  // least-squares ridge, 1e-10, then to rounding); the global entry's ratio
  // (3.1) is one of them on every rank count.
  for (std::size_t k = 0; k < accelerated.size(); ++k)
    std::printf("  iteration %2zu: |f| plain %.3e, Anderson(4) %.3e\n", k, plain[k],
                accelerated[k]);
  EXPECT_LT(accelerated[5], 1e-9 * accelerated[0]);
  EXPECT_LT(accelerated[6], 1e-14 * accelerated[0]);
}

TEST(Solver, AndersonCountsTheGlobalEntriesOnce)
{
  // The first accelerated step against the same least-squares problem
  // solved on every entry gathered on one rank: gamma = (dF . f)/(dF . dF).
  int rank, size;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  MPI_Comm_size(MPI_COMM_WORLD, &size);
  const Diagonal problem(rank);
  nct::solver::Anderson anderson(MPI_COMM_WORLD, 3, 1);
  std::vector<double> x0(owned + 1, 0.0), f0 = problem.step(x0);
  std::vector<double> f = f0;
  anderson.accelerate(x0, f); // no history: unchanged
  EXPECT_EQ(f, f0);
  std::vector<double> x1(owned + 1);
  for (std::size_t i = 0; i < x1.size(); ++i)
    x1[i] = x0[i] - f0[i];
  const std::vector<double> f1 = problem.step(x1);
  std::vector<double> accelerated = f1;
  anderson.accelerate(x1, accelerated);

  // The owned entries of every rank, and the global one once.
  std::vector<double> local;
  for (int i = 0; i < owned; ++i)
    local.insert(local.end(), {f1[i] - f0[i], f1[i]});
  std::vector<double> all(2 * owned * size);
  MPI_Allgather(local.data(), 2 * owned, MPI_DOUBLE, all.data(), 2 * owned, MPI_DOUBLE,
                MPI_COMM_WORLD);
  double dd = 0, df = 0;
  for (std::size_t i = 0; i < all.size(); i += 2)
    dd += all[i] * all[i], df += all[i] * all[i + 1];
  const double dg = f1[owned] - f0[owned];
  dd += dg * dg, df += dg * f1[owned];
  const double gamma = df / dd;
  for (int i = 0; i <= owned; ++i)
  {
    const double expected = f1[i] + gamma * ((x1[i] - x0[i]) - (f1[i] - f0[i]));
    EXPECT_NEAR(accelerated[i], expected, 1e-9 * std::abs(expected) + 1e-14) << "entry " << i;
  }
}
