#include "zero_pressure/zero_pressure.h"

#include <algorithm>
#include <cmath>

#include <dolfinx/geometry/BoundingBoxTree.h>
#include <dolfinx/geometry/utils.h>
#include <dolfinx/mesh/Mesh.h>

namespace nct::zero_pressure
{
namespace
{

/// r = X + u(X) - x_imaged at the geometry nodes; returns max and rms |r|.
std::array<double, 2> residual(const solid::Problem& problem,
                               const std::vector<double>& x_imaged, std::vector<double>& r)
{
  const auto& mesh = *problem.u->function_space()->mesh();
  std::span<const double> X = mesh.geometry().x();
  const std::vector<double> u = problem.nodal_displacement();
  r.resize(X.size());
  for (std::size_t i = 0; i < X.size(); ++i)
    r[i] = X[i] + u[i] - x_imaged[i];
  const std::int32_t owned = mesh.geometry().index_map()->size_local();
  double max = 0, sum2 = 0;
  for (std::int32_t n = 0; n < owned; ++n)
  {
    const double d2
        = r[3 * n] * r[3 * n] + r[3 * n + 1] * r[3 * n + 1] + r[3 * n + 2] * r[3 * n + 2];
    sum2 += d2;
    max = std::max(max, std::sqrt(d2));
  }
  MPI_Allreduce(MPI_IN_PLACE, &max, 1, MPI_DOUBLE, MPI_MAX, mesh.comm());
  MPI_Allreduce(MPI_IN_PLACE, &sum2, 1, MPI_DOUBLE, MPI_SUM, mesh.comm());
  const double nodes = static_cast<double>(mesh.geometry().index_map()->size_global());
  return {max, std::sqrt(sum2 / nodes)};
}

} // namespace

SwappedGeometry::SwappedGeometry(const dolfinx::mesh::Mesh& mesh,
                                 const std::vector<double>& x)
    : _x(const_cast<dolfinx::mesh::Mesh&>(mesh).geometry().x()), _saved(_x.begin(), _x.end())
{
  std::copy(x.begin(), x.end(), _x.begin());
}

SwappedGeometry::~SwappedGeometry() { std::copy(_saved.begin(), _saved.end(), _x.begin()); }

std::array<double, 2> mismatch(const solid::Problem& problem,
                               const std::vector<double>& x_imaged)
{
  std::vector<double> r;
  return residual(problem, x_imaged, r);
}

Report solve(solid::Problem& problem, const Settings& settings,
             const std::function<void()>& pressurise,
             const std::function<void(int, const Iteration&)>& progress)
{
  auto mesh = std::const_pointer_cast<dolfinx::mesh::Mesh>(
      problem.u->function_space()->mesh());
  std::span<double> X = mesh->geometry().x();
  const std::vector<double> x_imaged(X.begin(), X.end());
  const std::int32_t owned = mesh->geometry().index_map()->size_local();
  MPI_Comm comm = mesh->comm();

  Report report;
  std::vector<double> r(X.size()), r_old;
  double omega = 1.0;
  for (int k = 0;; ++k)
  {
    const double t = MPI_Wtime();
    pressurise();
    Iteration it;
    const auto [max, rms] = residual(problem, x_imaged, r);
    it.max = max, it.rms = rms;
    report.converged = it.max <= settings.tolerance;
    if (!report.converged && k + 1 < settings.max_iterations)
    {
      if (settings.aitken && !r_old.empty())
      {
        // omega_k = -omega_{k-1} r_{k-1} . dr / |dr|^2, dr = r_k - r_{k-1}
        double num_den[2] = {0, 0};
        for (std::int32_t i = 0; i < 3 * owned; ++i)
        {
          const double dr = r[i] - r_old[i];
          num_den[0] += r_old[i] * dr;
          num_den[1] += dr * dr;
        }
        MPI_Allreduce(MPI_IN_PLACE, num_den, 2, MPI_DOUBLE, MPI_SUM, comm);
        if (num_den[1] > 0)
          omega = std::clamp(-omega * num_den[0] / num_den[1], 0.1, 2.0);
      }
      it.omega = omega;
      for (std::size_t i = 0; i < X.size(); ++i)
        X[i] -= omega * r[i];
      r_old = r;
      problem.update_reference();
    }
    it.wall = MPI_Wtime() - t;
    report.iterations.push_back(it);
    progress(k, it);
    if (report.converged || k + 1 >= settings.max_iterations)
      return report;
  }
}

std::vector<std::array<double, 3>> points_on_current(const dolfinx::mesh::Mesh& mesh,
                                         const std::vector<double>& x_from,
                                         const std::vector<std::array<double, 3>>& points)
{
  // Locate the points in the x_from geometry (swapped in for the search).
  std::span<const double> x = mesh.geometry().x();
  std::vector<double> p;
  for (auto& q : points)
    p.insert(p.end(), q.begin(), q.end());
  dolfinx::graph::AdjacencyList<std::int32_t> cells(0);
  {
    SwappedGeometry from(mesh, x_from);
    dolfinx::geometry::BoundingBoxTree tree(mesh, mesh.topology().dim(), 1e-8);
    auto candidates = dolfinx::geometry::compute_collisions(tree, p);
    cells = dolfinx::geometry::compute_colliding_cells(mesh, candidates, p);
  }

  // Barycentric coordinates in x_from, then the same combination in x.
  const auto& dofmap = mesh.geometry().dofmap();
  std::vector<double> sum(4 * points.size(), 0.0);
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    auto c = cells.links(static_cast<int>(i));
    if (c.empty())
      continue;
    auto n = dofmap.links(c[0]);
    const int nv = static_cast<int>(n.size()); // 4, or a triangle's 3
    // Solve [a1-a0, a2-a0, a3-a0] l = p - a0 by Cramer's rule (a
    // triangle's third column e_z: its l3 is the point's z, 0).
    double M[3][3], b[3];
    for (int j = 0; j < 3; ++j)
    {
      for (int k = 0; k < 3; ++k)
        M[j][k] = k + 1 < nv ? x_from[3 * n[k + 1] + j] - x_from[3 * n[0] + j]
                             : static_cast<double>(j == 2);
      b[j] = points[i][j] - x_from[3 * n[0] + j];
    }
    auto det = [](double A[3][3])
    {
      return A[0][0] * (A[1][1] * A[2][2] - A[1][2] * A[2][1])
             - A[0][1] * (A[1][0] * A[2][2] - A[1][2] * A[2][0])
             + A[0][2] * (A[1][0] * A[2][1] - A[1][1] * A[2][0]);
    };
    const double d = det(M);
    std::array<double, 4> l{1, 0, 0, 0};
    for (int k = 0; k + 1 < nv; ++k)
    {
      double Mk[3][3];
      for (int j = 0; j < 3; ++j)
        for (int m = 0; m < 3; ++m)
          Mk[j][m] = m == k ? b[j] : M[j][m];
      l[k + 1] = det(Mk) / d;
      l[0] -= l[k + 1];
    }
    for (int v = 0; v < nv; ++v)
      for (int j = 0; j < 3; ++j)
        sum[4 * i + j] += l[v] * x[3 * n[v] + j];
    sum[4 * i + 3] = 1;
  }
  return meshio::combine_points(mesh.comm(), std::move(sum), points);
}

} // namespace nct::zero_pressure
