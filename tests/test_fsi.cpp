// Two-way fluid-structure interaction (cpp/fsi): the coupled system's
// Jacobian against central differences of its residual, with and without
// the shape derivative.
#include <cmath>
#include <gtest/gtest.h>

#include <dolfinx/la/petsc.h>

#include "helpers.h"
#include "run/model.h"

namespace
{

/// A smooth pseudo-random number in [-1, 1] of a place and a seed (the
/// same on every rank).
double wiggle(const double* x, double seed)
{
  const double s = std::sin(12.9898 * x[0] + 78.233 * x[1] + 37.719 * x[2] + seed) * 43758.5453;
  return 2 * (s - std::floor(s)) - 1;
}

/// Fill the coupled unknowns' functions with a state: the solid and the
/// mesh displaced by `scale` times a wiggle, the air blowing outwards and
/// down (away from the outlet's backflow switch), the pressure a wiggle;
/// then pack them into x.
void set_state(nct::Model& f, nct::solid::Problem& solid, double scale, double seed,
               bool flow)
{
  auto fill = [&](dolfinx::fem::Function<double>& u, double amplitude, double s)
  {
    const auto X = u.function_space()->tabulate_dof_coordinates(false);
    const int bs = u.function_space()->dofmap()->index_map_bs();
    auto values = u.x()->mutable_array();
    for (std::size_t i = 0; i < values.size(); ++i)
      values[i] = amplitude * wiggle(&X[3 * (i / bs)], s + i % bs);
  };
  fill(*solid.u, 0.01 * scale, seed);
  fill(*f.motion->d, 0.01 * scale, seed + 3);
  const auto V = f.air->velocity->function_space(), Q = f.air->pressure->function_space();
  const auto XV = V->tabulate_dof_coordinates(false), XQ = Q->tabulate_dof_coordinates(false);
  auto up = f.air->up->x()->mutable_array();
  for (std::size_t i = 0; i < f.air->velocity_dofs().size(); ++i)
  {
    const double* x = &XV[3 * (i / 3)];
    const double base = i % 3 == 1 ? -5.0 : 1.5 * x[i % 3]; // outwards and down [mm/ms]
    up[f.air->velocity_dofs()[i]] = scale * ((flow ? base : 0.0) + wiggle(x, seed + 7 + i % 3));
  }
  for (std::size_t i = 0; i < f.air->pressure_dofs().size(); ++i)
    up[f.air->pressure_dofs()[i]] = scale * 1e-4 * wiggle(&XQ[3 * i], seed + 11);
  f.coupled->unknowns().pack();
}

double norm(const dolfinx::la::Vector<double>& v)
{
  const std::int32_t n = v.map()->size_local();
  double s = 0;
  for (std::int32_t i = 0; i < n; ++i)
    s += v.array()[i] * v.array()[i];
  MPI_Allreduce(MPI_IN_PLACE, &s, 1, MPI_DOUBLE, MPI_SUM, MPI_COMM_WORLD);
  return std::sqrt(s);
}

/// The coupled Jacobian J against central differences of the residual R
/// in a direction d: per column field c (d restricted to it, the last
/// "c" the whole d) and row field r, |(R(x + e d) - R(x - e d)) / 2e - J d|
/// and |J d| over the rows of r, for e = eps and eps / 2.
struct JacobianCheck
{
  std::vector<std::string> fields;
  /// [c][r][k]: the error at e = eps / 2^k, and |J d|.
  std::vector<std::vector<std::array<double, 2>>> error;
  std::vector<std::vector<double>> Jd;
  /// The whole direction's relative error |error| / |J d| at eps, eps / 2.
  std::array<double, 2> relative;
};

JacobianCheck check_jacobian(bool shape_derivative, double eps)
{
  auto s = nct::scene::Scene::load(
      std::filesystem::path(NCT_SOURCE_DIR) / "tests/scenes/fsi_coarse.toml",
      {"material.cornea.model=\"neo_hookean\"", "material.limbus.model=\"neo_hookean\"",
       std::string("fsi.shape_derivative=") + (shape_derivative ? "true" : "false")});
  nct::Model model = nct::make_model(MPI_COMM_WORLD, s);
  auto& f = model;
  auto& solid = *model.problem;
  solid.start_dynamics({0.1, 0.8, 0.1});
  f.coupled->start();
  f.coupled->set_time_step(0.1, 0.8, 0.1, 1);
  f.air->set_inlet_scale(5.0);

  // The direction d (zero where a Dirichlet condition holds the unknown:
  // the Jacobian leaves their columns out), then the state x (its
  // history: the air's up_n).
  set_state(f, solid, 1.0, 100.0, false);
  for (auto [u, held] : {std::pair{solid.u, solid.dirichlet_marker()},
                         std::pair{f.air->up, f.air->dirichlet_marker()},
                         std::pair{f.motion->d, f.motion->fixed()}})
    for (std::size_t i = 0; i < held.size(); ++i)
      if (held[i])
        u->x()->mutable_array()[i] = 0;
  auto& unknowns = f.coupled->unknowns();
  unknowns.pack();
  const dolfinx::la::Vector<double> d = unknowns.x();
  set_state(f, solid, 1.0, 0.0, true);
  std::copy(f.air->up->x()->array().begin(), f.air->up->x()->array().end(),
            f.air->up_n->x()->mutable_array().begin());
  const dolfinx::la::Vector<double> x0 = unknowns.x();

  auto system = f.coupled->system(nullptr);
  dolfinx::la::petsc::Matrix A(f.coupled->create_matrix(), false);
  system.jacobian(A.mat());
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
    MatMult(A.mat(), d_petsc, Jd_petsc);
    VecDestroy(&d_petsc);
    VecDestroy(&Jd_petsc);
    out.error.emplace_back(n);
    out.Jd.emplace_back(n);
    for (std::size_t r = 0; r < n; ++r)
      out.Jd[c][r] = rows(Jd, r);
    std::vector<double> g;
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
      dolfinx::la::Vector<double> diff(d.map(), 1);
      for (std::size_t i = 0; i < diff.array().size(); ++i)
        diff.mutable_array()[i]
            = (r_plus.array()[i] - r_minus.array()[i]) / (2 * e) - Jd.array()[i];
      for (std::size_t r = 0; r < n; ++r)
        out.error[c][r][k] = rows(diff, r);
      if (c == n)
        out.relative[k] = norm(diff) / norm(Jd);
    }
  }
  std::printf("coupled Jacobian (%s shape derivative), %lld unknowns, %zu interface nodes, "
              "e = %g: relative error of the whole %.3e (%.3e at e / 2, ratio %.2f)\n",
              shape_derivative ? "exact" : "no", (long long)unknowns.size_global(),
              f.coupled->interface_nodes(), eps, out.relative[0], out.relative[1],
              out.relative[0] / out.relative[1]);
  for (std::size_t c = 0; c < n; ++c)
    for (std::size_t r = 0; r < n; ++r)
      std::printf("  rows %-11s columns %-11s |J d| %.3e  error %.3e, %.3e at e / 2\n",
                  out.fields[r].c_str(), out.fields[c].c_str(), out.Jd[c][r],
                  out.error[c][r][0], out.error[c][r][1]);
  return out;
}

} // namespace

// Every block of the coupled Jacobian (solid, air, shape derivative, mesh
// motion, the interface's constraints and the reaction moved onto the
// solid) matches central differences of the coupled residual in a random
// direction, with the second-order decay of the differences' own error;
// without the shape derivative it does not.
TEST(Fsi, JacobianMatchesDifferences)
{
  const auto exact = check_jacobian(true, 1e-2);
  EXPECT_LT(exact.relative[1], 1e-6);
  EXPECT_GT(exact.relative[0] / exact.relative[1], 3.5); // second order: 4
  const std::size_t n = exact.fields.size();
  for (std::size_t c = 0; c < n; ++c)
    for (std::size_t r = 0; r < n; ++r)
      if (exact.Jd[c][r] > 0)
        EXPECT_LT(exact.error[c][r][1], 1e-5 * exact.Jd[c][r])
            << "rows " << exact.fields[r] << ", columns " << exact.fields[c];
  // Without the shape derivative, the air's rows miss their dependence on
  // the mesh motion (and so do the solid's, through the moved reaction).
  const auto approximate = check_jacobian(false, 1e-2);
  const std::size_t air = 1, mesh = 2;
  EXPECT_GT(approximate.error[mesh][air][1], 0.9 * exact.Jd[mesh][air]);
}
