#include "mesh_motion/problem.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <stdexcept>

#include <dolfinx/fem/assembler.h>
#include <dolfinx/fem/utils.h>
#include <dolfinx/la/petsc.h>
#include <petscksp.h>

#include "form_tags.h"
#include "mesh_motion_p1_full.h"
#include "mesh_motion_p1_full_plane.h"
#include "solver/monolithic.h"

namespace nct::mesh_motion
{
namespace
{
using namespace dolfinx;

/// Cell tag of the moving region in forms/mesh_motion.py (forms/tags.py).
constexpr std::int32_t moving_tag = forms::tags::moving;

/// Per point of `x` (3 coordinates each): is it within `distance` of one
/// of `targets`? Buckets of the distance's size keep it linear.
std::vector<bool> near(const std::vector<double>& x, const std::vector<double>& targets,
                       double distance)
{
  const std::size_t n = x.size() / 3;
  if (!std::isfinite(distance))
    return std::vector<bool>(n, true);
  using Key = std::array<std::int64_t, 3>;
  auto key = [distance](const double* p)
  {
    return Key{static_cast<std::int64_t>(std::floor(p[0] / distance)),
               static_cast<std::int64_t>(std::floor(p[1] / distance)),
               static_cast<std::int64_t>(std::floor(p[2] / distance))};
  };
  std::map<Key, std::vector<std::size_t>> buckets;
  for (std::size_t i = 0; i < targets.size() / 3; ++i)
    buckets[key(&targets[3 * i])].push_back(i);
  std::vector<bool> out(n, false);
  const double d2 = distance * distance;
  for (std::size_t i = 0; i < n && !buckets.empty(); ++i)
  {
    const Key k = key(&x[3 * i]);
    for (int a = -1; a <= 1 && !out[i]; ++a)
      for (int b = -1; b <= 1 && !out[i]; ++b)
        for (int c = -1; c <= 1 && !out[i]; ++c)
          if (auto it = buckets.find({k[0] + a, k[1] + b, k[2] + c}); it != buckets.end())
            for (std::size_t t : it->second)
            {
              const double dx = x[3 * i] - targets[3 * t], dy = x[3 * i + 1] - targets[3 * t + 1],
                           dz = x[3 * i + 2] - targets[3 * t + 2];
              if (dx * dx + dy * dy + dz * dz <= d2)
              {
                out[i] = true;
                break;
              }
            }
  }
  return out;
}

} // namespace

Problem::Problem(const meshio::Tagged& m, const Settings& settings, const Boundaries& boundaries)
{
  if (settings.model != "harmonic" && settings.model != "elastic")
    throw std::invalid_argument("mesh_motion: model \"" + settings.model
                                + "\" is not \"harmonic\" or \"elastic\"");
  const bool harmonic = settings.model == "harmonic";
  // A section's extension is the planar one, axisymmetric or plane
  // (forms/mesh_motion.py).
  const int gdim = m.mesh->geometry().dim();
  const bool plane = gdim == 2;
  const auto space = plane ? functionspace_form_mesh_motion_p1_full_plane_R_harmonic
                           : functionspace_form_mesh_motion_p1_full_R_harmonic;
  auto D = std::make_shared<fem::FunctionSpace>(fem::create_functionspace(space, "d", m.mesh));
  d = std::make_shared<fem::Function<double>>(D);
  d->name = "air_mesh_displacement";
  const auto& map = *D->dofmap()->index_map;
  const int bs = D->dofmap()->index_map_bs();
  const std::int32_t nodes = map.size_local() + map.num_ghosts();
  _fixed.assign(bs * nodes, 0);
  _interface.assign(bs * nodes, 0);
  _diagonal = settings.scale * 1.0;

  // The interface's nodes, and every node's place.
  const std::vector<double> X = D->tabulate_dof_coordinates(false);
  std::vector<double> on_interface;
  for (auto g : boundaries.interface)
    for (auto b : fem::locate_dofs_topological(*D, gdim - 1, m.facets->find(g)))
    {
      for (int k = 0; k < bs; ++k)
        _interface[bs * b + k] = 1;
      if (b < map.size_local())
        on_interface.insert(on_interface.end(), X.begin() + 3 * b, X.begin() + 3 * b + 3);
    }
  // The moving region: nodes within `distance` of the interface.
  const std::vector<bool> moves = near(X, meshio::all_gather(m.mesh->comm(), on_interface),
                                       settings.distance);
  for (std::int32_t b = 0; b < map.size_local(); ++b)
    if (moves[b])
      _active.push_back(b);
  for (auto& [g, components] : boundaries.fixed)
    for (auto b : fem::locate_dofs_topological(*D, gdim - 1, m.facets->find(g)))
      if (moves[b])
        for (int k : components)
          if (k < bs)
            _fixed[bs * b + k] = 1;

  // Moving cells: those with a moving node. J_0: the smallest of their
  // Jacobian determinants, so that k <= scale.
  const auto& mesh = *m.mesh;
  const std::int32_t cells = mesh.topology().index_map(gdim)->size_local();
  std::vector<std::int32_t> moving_cells;
  double smallest = std::numeric_limits<double>::infinity();
  for (std::int32_t c = 0; c < cells; ++c)
  {
    auto dofs = D->dofmap()->cell_dofs(c);
    if (std::none_of(dofs.begin(), dofs.end(), [&](auto b) { return bool(moves[b]); }))
      continue;
    moving_cells.push_back(c);
    smallest = std::min(smallest, std::abs(meshio::determinant(meshio::cell_edges(mesh, c))));
  }
  MPI_Allreduce(MPI_IN_PLACE, &smallest, 1, MPI_DOUBLE, MPI_MIN, mesh.comm());
  _moving = std::make_shared<mesh::MeshTags<std::int32_t>>(
      m.mesh, gdim, moving_cells, std::vector<std::int32_t>(moving_cells.size(), moving_tag));

  for (auto [name, value] : {std::pair{"scale", settings.scale},
                             std::pair{"reference_jacobian", std::isfinite(smallest) ? smallest : 1.0},
                             std::pair{"chi", settings.stiffening},
                             std::pair{"poisson_ratio", settings.poisson_ratio}})
    _constants[name] = std::make_shared<fem::Constant<double>>(value);
  const std::map<fem::IntegralType, const mesh::MeshTags<int>*> subdomains
      = {{fem::IntegralType::cell, _moving.get()}};
  const std::map<std::string, std::shared_ptr<const fem::Constant<double>>> constants(
      _constants.begin(), _constants.end());
  auto make = [&](const ufcx_form& form, std::vector<std::shared_ptr<const fem::FunctionSpace>> V)
  {
    return std::make_shared<fem::Form<double>>(
        fem::create_form<double>(form, V, {{"d", d}}, constants, subdomains));
  };
  if (plane)
  {
    _R = make(harmonic ? *form_mesh_motion_p1_full_plane_R_harmonic
                       : *form_mesh_motion_p1_full_plane_R_elastic,
              {D});
    _J = make(harmonic ? *form_mesh_motion_p1_full_plane_J_harmonic
                       : *form_mesh_motion_p1_full_plane_J_elastic,
              {D, D});
  }
  else
  {
    _R = make(harmonic ? *form_mesh_motion_p1_full_R_harmonic
                       : *form_mesh_motion_p1_full_R_elastic,
              {D});
    _J = make(harmonic ? *form_mesh_motion_p1_full_J_harmonic
                       : *form_mesh_motion_p1_full_J_elastic,
              {D, D});
  }
}

void Problem::residual(la::Vector<double>& b)
{
  std::fill(b.mutable_array().begin(), b.mutable_array().end(), 0.0);
  fem::assemble_vector<double>(b.mutable_array(), *_R);
  b.scatter_rev(std::plus<double>());
  auto out = b.mutable_array();
  auto values = d->x()->array();
  for (std::size_t i = 0; i < _fixed.size(); ++i)
    if (_fixed[i])
      out[i] = _diagonal * values[i];
}

/// extend()'s system: the moving nodes as unknowns, the boundary rows
/// held, the operator factorised by MUMPS.
struct Problem::Extension
{
  std::unique_ptr<solver::Monolithic> system;
  std::unique_ptr<la::petsc::Matrix> A;
  KSP ksp = nullptr;
  ~Extension()
  {
    if (ksp)
      KSPDestroy(&ksp);
  }
};

void Problem::extend(const std::vector<std::pair<std::int32_t, std::array<double, 3>>>& g)
{
  auto D = d->function_space();
  const int bs = D->dofmap()->index_map_bs();
  auto values = d->x()->mutable_array();
  std::fill(values.begin(), values.end(), 0.0);
  for (auto& [b, v] : g)
    for (int k = 0; k < bs; ++k)
      if (_interface[bs * b + k] && !_fixed[bs * b + k])
        values[bs * b + k] = v[k];
  d->x()->scatter_fwd();

  // One Newton step of the linear problem, the boundary rows held.
  if (!_extension)
  {
    auto e = std::make_shared<Extension>();
    e->system = std::make_unique<solver::Monolithic>(d->function_space()->mesh()->comm(),
                                                     std::vector<solver::Monolithic::Field>{
                                                         {"mesh_motion", d, _active}});
    solver::BlockIndices indices{e->system->global(0), e->system->global(0), {}, bs, bs};
    std::vector<std::int64_t> held;
    for (std::size_t i = 0; i < _fixed.size(); ++i)
      if (_fixed[i] || _interface[i])
      {
        if (i < static_cast<std::size_t>(e->system->owned(0)) && indices.rows[i] >= 0)
          held.push_back(indices.rows[i]);
        indices.rows[i] = indices.cols[i] = -1;
      }
    auto add = [&](Mat A)
    {
      fem::assemble_matrix(solver::add_block(A, indices), *_J, {});
      for (auto r : held)
        MatSetValue(A, r, r, _diagonal, ADD_VALUES);
    };
    e->A = std::make_unique<la::petsc::Matrix>(e->system->create_matrix(add), false);
    MatZeroEntries(e->A->mat());
    add(e->A->mat());
    MatAssemblyBegin(e->A->mat(), MAT_FINAL_ASSEMBLY);
    MatAssemblyEnd(e->A->mat(), MAT_FINAL_ASSEMBLY);
    KSPCreate(d->function_space()->mesh()->comm(), &e->ksp);
    KSPSetType(e->ksp, KSPPREONLY);
    PC pc;
    KSPGetPC(e->ksp, &pc);
    PCSetType(pc, PCLU);
    PCFactorSetMatSolverType(pc, MATSOLVERMUMPS);
    KSPSetOperators(e->ksp, e->A->mat(), e->A->mat());
    _extension = e;
  }
  auto& system = *_extension->system;
  la::Vector<double> r(D->dofmap()->index_map, bs);
  residual(r);
  for (std::size_t i = 0; i < _interface.size(); ++i)
    if (_interface[i] || _fixed[i])
      r.mutable_array()[i] = 0.0;
  la::Vector<double> b(system.x().map(), 1), delta(system.x().map(), 1);
  system.insert(0, r.array(), b);
  Vec b_petsc = la::petsc::create_vector_wrap(b), delta_petsc = la::petsc::create_vector_wrap(delta);
  KSPSolve(_extension->ksp, b_petsc, delta_petsc);
  KSPConvergedReason reason;
  KSPGetConvergedReason(_extension->ksp, &reason);
  VecDestroy(&b_petsc);
  VecDestroy(&delta_petsc);
  if (reason < 0)
    throw std::runtime_error("mesh_motion: the extension's linear solve failed");
  system.pack();
  auto x = system.x().mutable_array();
  for (std::size_t i = 0; i < x.size(); ++i)
    x[i] -= delta.array()[i];
  system.x().scatter_fwd();
  system.unpack();
}

std::int64_t Problem::dofs() const
{
  std::int64_t n = static_cast<std::int64_t>(_active.size()) * 3;
  MPI_Allreduce(MPI_IN_PLACE, &n, 1, MPI_INT64_T, MPI_SUM, d->function_space()->mesh()->comm());
  return n;
}

} // namespace nct::mesh_motion
