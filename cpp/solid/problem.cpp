#include "solid/problem.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <set>
#include <stdexcept>

#include <dolfinx/fem/assembler.h>
#include <dolfinx/fem/petsc.h>
#include <dolfinx/fem/utils.h>
#include <dolfinx/geometry/BoundingBoxTree.h>
#include <dolfinx/geometry/utils.h>
#include <dolfinx/mesh/utils.h>

#include "form_tags.h"
#include "solid_p1_full.h"
#include "solid_p1_full_axisymmetric.h"
#include "solid_p1_full_plane.h"
#include "solid_p1_reduced.h"
#include "solid_p1_reduced_axisymmetric.h"
#include "solid_p1_reduced_plane.h"
#include "solid_p2_full.h"
#include "solid_p2_full_axisymmetric.h"
#include "solid_p2_full_mixed.h"
#include "solid_p2_full_mixed_axisymmetric.h"
#include "solid_p2_full_mixed_plane.h"
#include "solid_p2_full_plane.h"
#include "solid_p2_reduced.h"
#include "solid_p2_reduced_axisymmetric.h"
#include "solid_p2_reduced_mixed.h"
#include "solid_p2_reduced_mixed_axisymmetric.h"
#include "solid_p2_reduced_mixed_plane.h"
#include "solid_p2_reduced_plane.h"

namespace nct::solid
{
namespace
{
using namespace dolfinx;

#define NCT_SOLID_KERNELS(v)                                                     \
  Kernels{form_solid_##v##_R, form_solid_##v##_J,                                \
          {form_solid_##v##_volume_1, form_solid_##v##_volume_2},                 \
          {form_solid_##v##_cavity_load_1, form_solid_##v##_cavity_load_2},       \
          {form_solid_##v##_dvolume_1, form_solid_##v##_dvolume_2},               \
          {form_solid_##v##_cavity_load_dynamic_1,                                \
           form_solid_##v##_cavity_load_dynamic_2},                               \
          form_solid_##v##_R_dynamic, form_solid_##v##_J_dynamic,                 \
          form_solid_##v##_strain_energy, form_solid_##v##_kinetic_energy,         \
          form_solid_##v##_support_area,                                          \
          expression_solid_##v##_von_mises, expression_solid_##v##_det_F,         \
          functionspace_form_solid_##v##_R}

// The kernels of one dimension; `d` is empty (3D), _axisymmetric or _plane.
#define NCT_SOLID_KERNELS_OF(e, d)                                               \
  if (e.degree == 1 && !e.mixed)                                                 \
    return e.reduced_quadrature ? NCT_SOLID_KERNELS(p1_reduced##d)              \
                                : NCT_SOLID_KERNELS(p1_full##d);                \
  if (e.degree == 2 && !e.mixed)                                                 \
    return e.reduced_quadrature ? NCT_SOLID_KERNELS(p2_reduced##d)              \
                                : NCT_SOLID_KERNELS(p2_full##d);                \
  if (e.degree == 2)                                                             \
    return e.reduced_quadrature ? NCT_SOLID_KERNELS(p2_reduced_mixed##d)        \
                                : NCT_SOLID_KERNELS(p2_full_mixed##d);


/// A facet group's name (its tag if it has none).
std::string group_name(const meshio::Groups& groups, std::int32_t tag)
{
  for (auto& [name, t] : groups.surfaces)
    if (t == tag)
      return name;
  return std::to_string(tag);
}

/// Facet tags of forms/solid.py (forms/tags.py).
constexpr std::array<std::int32_t, 2> cavity_wall_tags
    = {forms::tags::cavity_1_wall, forms::tags::cavity_2_wall};
constexpr std::int32_t press_tag = forms::tags::press;
constexpr std::int32_t support_tag = forms::tags::support;

/// The rigid-body modes of a displacement space, orthonormalised: three
/// translations and three rotations in 3D, two and one in the plane, the
/// axial translation of an axisymmetric section. The near-nullspace an
/// algebraic multigrid preconditioner (PETSc's GAMG) builds its coarse
/// spaces from (Adams 2002, the elasticity demo of dolfinx). Direct solvers
/// ignore it.
MatNullSpace rigid_body_modes(const fem::FunctionSpace& V, section::Dimension dimension)
{
  const auto map = V.dofmap()->index_map;
  const int bs = V.dofmap()->index_map_bs();
  const int modes = dimension == section::Dimension::three ? 6
                    : dimension == section::Dimension::plane ? 3
                                                               : 1;
  std::vector<la::Vector<double>> basis(modes, la::Vector<double>(map, bs));
  const std::vector<double> x = V.tabulate_dof_coordinates(false);
  const std::int32_t nodes = map->size_local() + map->num_ghosts();
  for (std::int32_t i = 0; i < nodes; ++i)
  {
    const double* p = &x[3 * i];
    if (dimension == section::Dimension::axisymmetric)
    {
      basis[0].mutable_array()[bs * i + 1] = 1;
      continue;
    }
    for (int k = 0; k < bs; ++k)
      basis[k].mutable_array()[bs * i + k] = 1;
    if (dimension == section::Dimension::plane)
    {
      basis[2].mutable_array()[bs * i] = -p[1];
      basis[2].mutable_array()[bs * i + 1] = p[0];
      continue;
    }
    const double r[3][3] = {{-p[1], p[0], 0}, {0, -p[2], p[1]}, {p[2], 0, -p[0]}};
    for (int m = 0; m < 3; ++m)
      for (int k = 0; k < 3; ++k)
        basis[3 + m].mutable_array()[3 * i + k] = r[m][k];
  }
  la::orthonormalize(std::span<la::Vector<double>>(basis));
  std::vector<Vec> vecs;
  for (const auto& b : basis)
  {
    Vec wrap = la::petsc::create_vector_wrap(b), copy;
    VecDuplicate(wrap, &copy);
    VecCopy(wrap, copy);
    VecDestroy(&wrap);
    vecs.push_back(copy);
  }
  MatNullSpace space;
  MatNullSpaceCreate(map->comm(), PETSC_FALSE, modes, vecs.data(), &space);
  for (Vec& v : vecs)
    VecDestroy(&v);
  return space;
}

} // namespace

/// The compiled kernels of forms/solid.py for one element and dimension.
struct Problem::Kernels
{
  ufcx_form* R;
  ufcx_form* J;
  std::array<ufcx_form*, 2> volumes, cavity_loads, dvolumes, cavity_loads_dynamic;
  ufcx_form* R_dynamic;
  ufcx_form* J_dynamic;
  ufcx_form* strain_energy;
  ufcx_form* kinetic_energy;
  ufcx_form* support_area;
  ufcx_expression* von_mises;
  ufcx_expression* det_F;
  ufcx_function_space* (*space)(const char*);
};

Problem::Kernels Problem::kernels(const Element& e)
{
  switch (e.dimension)
  {
  case section::Dimension::three:
    NCT_SOLID_KERNELS_OF(e, )
    break;
  case section::Dimension::axisymmetric:
    NCT_SOLID_KERNELS_OF(e, _axisymmetric)
    break;
  case section::Dimension::plane:
    NCT_SOLID_KERNELS_OF(e, _plane)
    break;
  }
  throw std::invalid_argument("the mixed formulation needs fem.degree = 2");
}

Problem::Problem(const meshio::Tagged& m, const Element& element,
                 const std::map<std::int32_t, std::string>& parts,
                 const std::map<std::string, Material>& materials,
                 const FibreRule& fibres, const Boundaries& boundaries,
                 std::array<double, 3> volume_origin)
    : _dimension(element.dimension), _cells(m.cells), _parts(parts), _materials(materials),
      _fibres(fibres)
{
  const Kernels k = kernels(element);
  const int gdim = section::mesh_dimension(_dimension);
  if (m.mesh->geometry().dim() != gdim)
    throw std::invalid_argument("a " + section::name(_dimension) + " model needs a mesh of "
                                + std::to_string(gdim) + " dimensions, not "
                                + std::to_string(m.mesh->geometry().dim()));
  for (const ufcx_form* f : {k.R, k.J, k.R_dynamic, k.J_dynamic})
    _forms_signature += std::string(f->signature) + " ";
  make_spaces(m, k, kernels(Element{1, false, false, element.dimension}));
  tag_integrals(m, boundaries);
  make_constants(volume_origin, boundaries);
  const std::set<int> mirrors = make_boundary_conditions(m, boundaries);
  make_forms(m, k, element, boundaries, mirrors);
}

void Problem::make_spaces(const meshio::Tagged& m, const Kernels& k, const Kernels& p1)
{
  auto V = std::make_shared<fem::FunctionSpace>(
      fem::create_functionspace(k.space, "u", m.mesh));
  auto Q0 = std::make_shared<fem::FunctionSpace>(
      fem::create_functionspace(k.space, "c10", m.mesh));
  auto Q0v = std::make_shared<fem::FunctionSpace>(
      fem::create_functionspace(k.space, "fibre_1", m.mesh));
  u = std::make_shared<fem::Function<double>>(V);
  u->name = "displacement";
  von_mises = std::make_shared<fem::Function<double>>(Q0);
  von_mises->name = "von_mises_stress";
  _coordinate_space = std::make_shared<fem::FunctionSpace>(
      fem::create_functionspace(p1.space, "u", m.mesh));
  press_profile = std::make_shared<fem::Function<double>>(
      std::make_shared<fem::FunctionSpace>(
          fem::create_functionspace(k.space, "press_profile", m.mesh)));
  press_profile->name = "press_profile";
  press_profile->x()->set(1.0);
  _profile_points = press_profile->function_space()->tabulate_dof_coordinates(false);
  fields = cell_fields(*m.cells, _parts, _materials, _fibres, _dimension, Q0, Q0v);
  _u_support = std::make_shared<fem::Function<double>>(V);
  u_old = std::make_shared<fem::Function<double>>(V);
  v_old = std::make_shared<fem::Function<double>>(V);
  v_old->name = "velocity";
  a_old = std::make_shared<fem::Function<double>>(V);
}

void Problem::tag_integrals(const meshio::Tagged& m, const Boundaries& boundaries)
{
  // Cells by law, facets by load.
  std::map<std::int32_t, std::int32_t> law_of_group, load_of_group;
  for (auto& [group, part] : _parts)
    law_of_group[group] = static_cast<std::int32_t>(_materials.at(part).law);
  if (boundaries.cavities.size() > cavity_wall_tags.size())
    throw std::invalid_argument("at most two cavities");
  for (std::size_t c = 0; c < boundaries.cavities.size(); ++c)
    for (auto g : boundaries.cavities[c])
      load_of_group[g] = cavity_wall_tags[c];
  for (auto g : boundaries.press)
    load_of_group[g] = press_tag;
  for (auto g : boundaries.fixed)
    load_of_group[g] = support_tag;
  _law_tags = std::make_shared<mesh::MeshTags<std::int32_t>>(
      meshio::retag(*m.cells, law_of_group));
  _load_tags = std::make_shared<mesh::MeshTags<std::int32_t>>(
      meshio::retag(*m.facets, load_of_group));
}

void Problem::make_constants(std::array<double, 3> volume_origin, const Boundaries& boundaries)
{
  const int gdim = section::mesh_dimension(_dimension);
  for (std::size_t c = 0; c < cavity_wall_tags.size(); ++c)
    _p_cavities.push_back(std::make_shared<fem::Constant<double>>(0.0));
  _p_press = std::make_shared<fem::Constant<double>>(0.0);
  _x0 = std::make_shared<fem::Constant<double>>(
      std::vector<double>(volume_origin.begin(), volume_origin.begin() + gdim));
  _support = boundaries.support;
  _support_stiffness = std::make_shared<fem::Constant<double>>(0.0);
  _support_damping = std::make_shared<fem::Constant<double>>(0.0);
  for (auto& lid : _lids)
    lid = std::make_shared<fem::Constant<double>>(0.0);
  for (const char* name : {"dt", "alpha_m", "alpha_f", "beta", "gamma", "damping"})
    _time[name] = std::make_shared<fem::Constant<double>>(0.0);
}

std::set<int> Problem::make_boundary_conditions(const meshio::Tagged& m,
                                                const Boundaries& boundaries)
{
  const auto V = u->function_space();
  const int gdim = section::mesh_dimension(_dimension);
  // Clamped groups, and one component per symmetry plane and on the axis.
  auto facets_of = [&](std::int32_t g) { return m.facets->find(g); };
  const int fdim = gdim - 1;
  for (auto g : boundaries.fixed)
  {
    auto dofs = fem::locate_dofs_topological(*V, fdim, facets_of(g));
    _bcs.push_back(std::make_shared<fem::DirichletBC<double>>(
        std::vector<double>(gdim, 0.0), std::move(dofs), V));
  }
  std::set<int> mirrors; // the axes of the mirror planes
  for (auto g : boundaries.symmetry)
  {
    // A group with no facets here is on a coupled fluid's side only.
    std::int64_t count = static_cast<std::int64_t>(facets_of(g).size());
    MPI_Allreduce(MPI_IN_PLACE, &count, 1, MPI_INT64_T, MPI_SUM, m.mesh->comm());
    if (count == 0)
      continue;
    int axis = meshio::normal_axis(*m.mesh, *m.facets, g);
    if (axis < 0)
    {
      throw std::runtime_error("symmetry group '" + group_name(m.groups, g)
                               + "' is not a plane x, y or z = const");
    }
    if (axis == 0 && _dimension == section::Dimension::axisymmetric)
      throw std::runtime_error("a symmetry plane r = const of an axisymmetric section is not "
                               "a mirror plane (the axis r = 0 is boundary.axis)");
    // A mirror plane halves the model; a group on two planes of one axis
    // (the faces of a slab) does not.
    const auto [lo, hi] = meshio::coordinate_range(*m.mesh, *m.facets, g, axis);
    if (hi - lo <= 1e-9 * std::max(1.0, std::abs(hi)))
      mirrors.insert(axis);
    auto Vi = V->sub({axis});
    auto dofs = fem::locate_dofs_topological(*Vi, fdim, facets_of(g));
    _symmetry_bcs.push_back(
        std::make_shared<fem::DirichletBC<double>>(0.0, std::move(dofs), Vi));
  }
  for (auto g : boundaries.axis)
  {
    // A group with no facets here is on a coupled fluid's side only.
    std::int64_t count = static_cast<std::int64_t>(facets_of(g).size());
    MPI_Allreduce(MPI_IN_PLACE, &count, 1, MPI_INT64_T, MPI_SUM, m.mesh->comm());
    if (count == 0)
      continue;
    const auto [lo, hi] = meshio::coordinate_range(*m.mesh, *m.facets, g, 0);
    if (std::max(std::abs(lo), std::abs(hi)) > 1e-9 * std::max(1.0, std::abs(hi)))
      throw std::runtime_error("axis group '" + group_name(m.groups, g) + "' is not on r = 0 "
                               "(its x runs from " + std::to_string(lo) + " to "
                               + std::to_string(hi) + ")");
    auto Vr = V->sub({0});
    auto dofs = fem::locate_dofs_topological(*Vr, fdim, facets_of(g));
    _symmetry_bcs.push_back(
        std::make_shared<fem::DirichletBC<double>>(0.0, std::move(dofs), Vr));
  }
  _bcs.insert(_bcs.end(), _symmetry_bcs.begin(), _symmetry_bcs.end());
  _symmetry_factor = (1 << mirrors.size())
                     * (_dimension == section::Dimension::axisymmetric ? 2 * M_PI : 1.0);
  return mirrors;
}

void Problem::make_forms(const meshio::Tagged& m, const Kernels& k, const Element& element,
                         const Boundaries& boundaries, const std::set<int>& mirrors)
{
  const auto V = u->function_space();
  const int gdim = section::mesh_dimension(_dimension);
  std::map<std::string, std::shared_ptr<const fem::Function<double>>> coeffs;
  coeffs["u"] = u;
  coeffs["u_old"] = u_old;
  coeffs["v_old"] = v_old;
  coeffs["a_old"] = a_old;
  coeffs["press_profile"] = press_profile;
  coeffs["u_support"] = _u_support;
  for (auto& [name, f] : fields)
    coeffs[name] = f;
  // Every form takes the constants it names from one map.
  std::map<std::string, std::shared_ptr<const fem::Constant<double>>> constants
      = {{"p_cavity_1", _p_cavities[0]}, {"p_cavity_2", _p_cavities[1]},
         {"p_press", _p_press},       {"x0", _x0},
         {"lid_1", _lids[0]},             {"lid_2", _lids[1]},
         {"support_stiffness", _support_stiffness}, {"support_damping", _support_damping}};
  constants.insert(_time.begin(), _time.end());
  const std::map<fem::IntegralType, const mesh::MeshTags<int>*> subdomains
      = {{fem::IntegralType::cell, _law_tags.get()},
         {fem::IntegralType::exterior_facet, _load_tags.get()}};
  auto pick = [&](const ufcx_form& form)
  {
    std::map<std::string, std::shared_ptr<const fem::Function<double>>> c;
    for (const auto& name : fem::get_coefficient_names(form))
      c[name] = coeffs.at(name);
    return c;
  };
  _R = std::make_shared<fem::Form<double>>(
      fem::create_form<double>(*k.R, {V}, pick(*k.R), constants, subdomains));
  _J = std::make_shared<fem::Form<double>>(
      fem::create_form<double>(*k.J, {V, V}, pick(*k.J), constants, subdomains));
  _R_dynamic = std::make_shared<fem::Form<double>>(
      fem::create_form<double>(*k.R_dynamic, {V}, pick(*k.R_dynamic), constants, subdomains));
  _J_dynamic = std::make_shared<fem::Form<double>>(fem::create_form<double>(
      *k.J_dynamic, {V, V}, pick(*k.J_dynamic), constants, subdomains));
  _strain_energy = std::make_shared<fem::Form<double>>(fem::create_form<double>(
      *k.strain_energy, {}, pick(*k.strain_energy), {}, subdomains, m.mesh));
  _kinetic_energy = std::make_shared<fem::Form<double>>(fem::create_form<double>(
      *k.kinetic_energy, {}, pick(*k.kinetic_energy), {}, subdomains, m.mesh));
  if (std::any_of(_materials.begin(), _materials.end(),
                  [](const auto& m) { return !m.second.relative_moduli.empty(); }))
    _viscoelasticity = std::make_unique<Viscoelasticity>(element, coeffs, constants, *_law_tags);
  for (std::size_t c = 0; c < boundaries.cavities.size(); ++c)
  {
    _volumes.push_back(std::make_shared<fem::Form<double>>(fem::create_form<double>(
        *k.volumes[c], {}, pick(*k.volumes[c]), constants, subdomains, m.mesh)));
    _cavity_loads.push_back(std::make_shared<fem::Form<double>>(fem::create_form<double>(
        *k.cavity_loads[c], {V}, pick(*k.cavity_loads[c]), constants, subdomains)));
    _dvolumes.push_back(std::make_shared<fem::Form<double>>(fem::create_form<double>(
        *k.dvolumes[c], {V}, pick(*k.dvolumes[c]), constants, subdomains)));
    _cavity_loads_dynamic.push_back(std::make_shared<fem::Form<double>>(
        fem::create_form<double>(*k.cavity_loads_dynamic[c], {V},
                                 pick(*k.cavity_loads_dynamic[c]), constants, subdomains)));
  }
  _support_area = std::make_shared<fem::Form<double>>(fem::create_form<double>(
      *k.support_area, {}, std::map<std::string, std::shared_ptr<const fem::Function<double>>>{},
      std::map<std::string, std::shared_ptr<const fem::Constant<double>>>{}, subdomains,
      m.mesh));
  // The lids: each cavity's opening on the cut, relative to the cut's area.
  double cut_area = fem::assemble_scalar(*_support_area);
  MPI_Allreduce(MPI_IN_PLACE, &cut_area, 1, MPI_DOUBLE, MPI_SUM, m.mesh->comm());
  for (std::size_t c = 0; c < boundaries.lids.size() && c < _lids.size(); ++c)
    if (boundaries.lids[c] > 0)
    {
      if (cut_area <= 0)
        throw std::invalid_argument("a cavity has a lid but the model no fixed face");
      _lids[c]->value = {boundaries.lids[c] / cut_area};
    }
  _von_mises = std::make_shared<fem::Expression<double>>(
      fem::create_expression<double>(*k.von_mises, coeffs, {}, m.mesh));
  _det_F = std::make_shared<fem::Expression<double>>(
      fem::create_expression<double>(*k.det_F, coeffs, {}, m.mesh));

  if (boundaries.humor_density && !boundaries.cavities.empty())
  {
    // The humors move along the axes no mirror plane holds (an
    // axisymmetric section: along its axis only, unless mirrored); none
    // left: the mirrors hold the centroids, and the humors' translation
    // has no inertia.
    std::vector<int> components;
    for (int i = 0; i < gdim; ++i)
      if ((_dimension != section::Dimension::axisymmetric || i == 1) && !mirrors.count(i))
        components.push_back(i);
    if (!components.empty())
      _humor_inertia = std::make_unique<HumorInertia>(element, u, constants, *_load_tags,
                                                      boundaries.cavities.size(), components,
                                                      *boundaries.humor_density);
  }
}

void Problem::set_cavity_pressures(const std::vector<double>& pressures)
{
  for (std::size_t c = 0; c < pressures.size(); ++c)
    _p_cavities.at(c)->value = {pressures[c]};
}

void Problem::set_press_profile(
    const std::function<double(const std::array<double, 3>&)>& f)
{
  // P1: the dofs sit at the vertices.
  const std::vector<double>& x = _profile_points;
  auto values = press_profile->x()->mutable_array();
  for (std::size_t i = 0; i < values.size(); ++i)
    values[i] = f({x[3 * i], x[3 * i + 1], x[3 * i + 2]});
}

void Problem::residual(la::Vector<double>& b)
{
  std::fill(b.mutable_array().begin(), b.mutable_array().end(), 0.0);
  fem::assemble_vector<double>(b.mutable_array(), _dynamic ? *_R_dynamic : *_R);
  if (_dynamic && _viscoelasticity)
    _viscoelasticity->add_residual(b.mutable_array());
  if (_dynamic && _humor_inertia)
    _humor_inertia->add_residual(b.mutable_array());
  b.scatter_rev(std::plus<double>());
  if (_dynamic && _preload)
  {
    const auto preload = _preload->array();
    auto values = b.mutable_array();
    for (std::size_t i = 0; i < preload.size(); ++i)
      values[i] -= preload[i];
  }
  fem::set_bc<double>(b.mutable_array(), _bcs, u->x()->array(), -1.0);
}

void Problem::jacobian(Mat A)
{
  MatZeroEntries(A);
  const auto forms = jacobian_forms();
  for (const auto* J : forms)
    fem::assemble_matrix(la::petsc::Matrix::set_block_fn(A, ADD_VALUES), *J, _bcs);
  const auto& J = *forms.front();
  MatAssemblyBegin(A, MAT_FLUSH_ASSEMBLY);
  MatAssemblyEnd(A, MAT_FLUSH_ASSEMBLY);
  fem::set_diagonal<double>(la::petsc::Matrix::set_fn(A, INSERT_VALUES),
                            *J.function_spaces()[0], _bcs);
  MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY);
  MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY);
}

std::vector<const fem::Form<double>*> Problem::jacobian_forms() const
{
  if (!_dynamic)
    return {_J.get()};
  std::vector<const fem::Form<double>*> forms = {_J_dynamic.get()};
  if (_viscoelasticity)
    forms.push_back(&_viscoelasticity->jacobian_form());
  if (_humor_inertia)
    forms.push_back(&_humor_inertia->jacobian_form());
  return forms;
}

double Problem::viscous_work() const
{
  return _viscoelasticity ? _viscoelasticity->work() * _symmetry_factor : 0.0;
}

void Problem::cavity_load(std::size_t c, la::Vector<double>& b)
{
  std::fill(b.mutable_array().begin(), b.mutable_array().end(), 0.0);
  fem::assemble_vector<double>(b.mutable_array(),
                               _dynamic ? *_cavity_loads_dynamic.at(c) : *_cavity_loads.at(c));
  b.scatter_rev(std::plus<double>());
  fem::set_bc<double>(b.mutable_array(), _bcs, 0.0);
}

void Problem::humor_border(std::size_t j, la::Vector<double>& b)
{
  _humor_inertia->border(j, b);
  fem::set_bc<double>(b.mutable_array(), _bcs, 0.0);
}

void Problem::volume_derivative(std::size_t c, la::Vector<double>& b)
{
  std::fill(b.mutable_array().begin(), b.mutable_array().end(), 0.0);
  fem::assemble_vector<double>(b.mutable_array(), *_dvolumes.at(c));
  b.scatter_rev(std::plus<double>());
}

void Problem::set_time_step(const dynamics::TimeStep& step)
{
  // forms/dynamics.py: the parameters from the spectral radius rho_inf.
  const double r = step.rho_inf;
  const double am = (2 * r - 1) / (r + 1), af = r / (r + 1);
  _time["dt"]->value = {step.dt};
  _time["alpha_m"]->value = {am};
  _time["alpha_f"]->value = {af};
  _time["gamma"]->value = {0.5 - am + af};
  _time["beta"]->value = {0.25 * (1 - am + af) * (1 - am + af)};
  _time["damping"]->value = {step.damping};
}

void Problem::start_dynamics(const dynamics::TimeStep& step)
{
  if (_support && !_dynamic)
  {
    // The clamp's reaction: the quasi-static residual on the dofs the
    // springs free (owned), which the support keeps as a dead load.
    const auto held = dirichlet_marker(), still_held = dynamic_dirichlet_marker();
    la::Vector<double> b(u->x()->map(), u->x()->bs());
    fem::assemble_vector<double>(b.mutable_array(), *_R);
    b.scatter_rev(std::plus<double>());
    const std::size_t owned = b.map()->size_local() * b.bs();
    _preload.emplace(u->x()->map(), u->x()->bs());
    auto preload = _preload->mutable_array();
    std::fill(preload.begin(), preload.end(), 0.0);
    for (std::size_t i = 0; i < owned; ++i)
      if (held[i] && !still_held[i])
        preload[i] = b.array()[i];
    std::copy(u->x()->array().begin(), u->x()->array().end(),
              _u_support->x()->mutable_array().begin());
    release_support();
  }
  set_time_step(step);
  std::copy(u->x()->array().begin(), u->x()->array().end(),
            u_old->x()->mutable_array().begin());
  v_old->x()->set(0.0);
  a_old->x()->set(0.0);
  _dynamic = true;
  if (_viscoelasticity)
    _viscoelasticity->start();
  if (_humor_inertia)
  {
    auto volumes = cavity_volumes();
    for (double& v : volumes)
      v /= _symmetry_factor;
    _humor_inertia->start(volumes);
  }
}

void Problem::release_support()
{
  // Springs and dashpots per unit area of the whole model's cut.
  const double area = whole_model({_support_area})[0];
  _support_stiffness->value = {_support->stiffness / area};
  _support_damping->value = {_support->damping / area};
  _bcs = _symmetry_bcs;
}

void Problem::save(io::CheckpointWriter& checkpoint) const
{
  checkpoint.add_geometry("solid/geometry", *u->function_space()->mesh());
  checkpoint.add("solid/u", *u);
  if (!_dynamic)
    return;
  checkpoint.add("solid/u_old", *u_old);
  checkpoint.add("solid/v_old", *v_old);
  checkpoint.add("solid/a_old", *a_old);
  if (_viscoelasticity)
    _viscoelasticity->save(checkpoint);
  if (_humor_inertia)
    _humor_inertia->save(checkpoint);
  if (_support)
  {
    checkpoint.add("solid/u_support", *_u_support);
    const auto& V = *u->function_space();
    checkpoint.add("solid/preload", _preload->array(), _preload->bs(), checkpoint.keys(V),
                   V.dofmap()->index_map->size_local());
  }
}

void Problem::restore(const io::CheckpointReader& checkpoint, bool dynamic)
{
  auto mesh = std::const_pointer_cast<mesh::Mesh>(u->function_space()->mesh());
  checkpoint.read_geometry("solid/geometry", *mesh);
  update_reference();
  checkpoint.read("solid/u", *u);
  if (!dynamic)
    return;
  checkpoint.read("solid/u_old", *u_old);
  checkpoint.read("solid/v_old", *v_old);
  checkpoint.read("solid/a_old", *a_old);
  if (_viscoelasticity)
    _viscoelasticity->restore(checkpoint);
  if (_humor_inertia)
    _humor_inertia->restore(checkpoint);
  if (_support)
  {
    checkpoint.read("solid/u_support", *_u_support);
    _preload.emplace(u->x()->map(), u->x()->bs());
    auto preload = _preload->mutable_array();
    checkpoint.read("solid/preload", preload, _preload->bs(),
                    checkpoint.keys(*u->function_space()));
    const std::size_t owned = _preload->map()->size_local() * _preload->bs();
    std::fill(preload.begin() + owned, preload.end(), 0.0); // owned entries only
    release_support();
  }
  _dynamic = true;
}

namespace
{
/// a_{n+1} from the Newmark displacement update (forms/dynamics.py).
double newmark_acceleration(double u, double u_old, double v_old, double a_old, double dt,
                            double beta)
{
  return (u - u_old - dt * v_old) / (beta * dt * dt) - (1 - 2 * beta) / (2 * beta) * a_old;
}
} // namespace

void Problem::advance()
{
  if (_viscoelasticity)
    _viscoelasticity->advance();
  if (_humor_inertia)
    _humor_inertia->advance();
  const double dt = _time["dt"]->value[0], beta = _time["beta"]->value[0],
               gamma = _time["gamma"]->value[0];
  auto un = u->x()->array();
  auto uo = u_old->x()->mutable_array(), vo = v_old->x()->mutable_array(),
       ao = a_old->x()->mutable_array();
  for (std::size_t i = 0; i < un.size(); ++i)
  {
    const double a = newmark_acceleration(un[i], uo[i], vo[i], ao[i], dt, beta);
    vo[i] += dt * ((1 - gamma) * ao[i] + gamma * a);
    ao[i] = a;
    uo[i] = un[i];
  }
}

double Problem::local_error() const
{
  const double dt = _time.at("dt")->value[0], beta = _time.at("beta")->value[0];
  auto un = u->x()->array(), uo = u_old->x()->array(), vo = v_old->x()->array(),
       ao = a_old->x()->array();
  const std::size_t owned = u->x()->map()->size_local() * u->x()->bs();
  double e = 0;
  for (std::size_t i = 0; i < owned; ++i)
  {
    const double a = newmark_acceleration(un[i], uo[i], vo[i], ao[i], dt, beta);
    e = std::max(e, std::abs(a - ao[i]));
  }
  MPI_Allreduce(MPI_IN_PLACE, &e, 1, MPI_DOUBLE, MPI_MAX, u->function_space()->mesh()->comm());
  return std::abs(beta - 1.0 / 6) * dt * dt * e;
}

void Problem::predict()
{
  // The Newmark update at a_{n+1} = a_n: the constant-acceleration predictor.
  const double dt = _time["dt"]->value[0];
  auto un = u->x()->mutable_array();
  auto uo = u_old->x()->array(), vo = v_old->x()->array(), ao = a_old->x()->array();
  for (std::size_t i = 0; i < un.size(); ++i)
    un[i] = uo[i] + dt * vo[i] + 0.5 * dt * dt * ao[i];
}

double Problem::load_level() const { return _dynamic ? 1 - _time.at("alpha_f")->value[0] : 1.0; }

std::array<double, 3> Problem::velocity_coefficients() const
{
  const double dt = _time.at("dt")->value[0], beta = _time.at("beta")->value[0],
               gamma = _time.at("gamma")->value[0];
  return {gamma / (beta * dt), 1 - gamma / beta, dt * (1 - gamma / (2 * beta))};
}

std::vector<std::int8_t> Problem::dirichlet_marker() const
{
  const auto& dofmap = *u->function_space()->dofmap();
  std::vector<std::int8_t> marker(
      dofmap.index_map_bs() * (dofmap.index_map->size_local() + dofmap.index_map->num_ghosts()),
      0);
  for (const auto& bc : _bcs)
    bc->mark_dofs(marker);
  return marker;
}

std::vector<std::int8_t> Problem::dynamic_dirichlet_marker() const
{
  if (!_support || _dynamic)
    return dirichlet_marker();
  std::vector<std::int8_t> marker(dirichlet_marker().size(), 0);
  for (const auto& bc : _symmetry_bcs)
    bc->mark_dofs(marker);
  return marker;
}

std::vector<double>
Problem::whole_model(const std::vector<std::shared_ptr<fem::Form<double>>>& forms) const
{
  std::vector<double> v;
  for (auto& form : forms)
    v.push_back(fem::assemble_scalar(*form));
  MPI_Allreduce(MPI_IN_PLACE, v.data(), static_cast<int>(v.size()), MPI_DOUBLE, MPI_SUM,
                u->function_space()->mesh()->comm());
  for (double& x : v)
    x *= _symmetry_factor;
  return v;
}

double Problem::strain_energy() const { return whole_model({_strain_energy})[0]; }

double Problem::kinetic_energy() const { return whole_model({_kinetic_energy})[0]; }

std::vector<double> Problem::nodal_displacement() const
{
  auto P1 = _coordinate_space;
  fem::Function<double> w(P1);
  w.interpolate(*u);
  w.x()->scatter_fwd();
  const auto& mesh = *P1->mesh();
  const auto& xdofs = mesh.geometry().dofmap();
  const auto& dofs = *P1->dofmap();
  std::vector<double> out(mesh.geometry().x().size());
  const int tdim = mesh.topology().dim(), bs = w.x()->bs();
  const std::int32_t cells = mesh.topology().index_map(tdim)->size_local()
                             + mesh.topology().index_map(tdim)->num_ghosts();
  for (std::int32_t c = 0; c < cells; ++c)
  {
    auto nodes = xdofs.links(c);
    auto d = dofs.cell_dofs(c);
    if (nodes.size() != d.size())
      throw std::runtime_error("nodal values need a linear (P1) mesh geometry");
    for (std::size_t i = 0; i < nodes.size(); ++i)
      for (int j = 0; j < bs; ++j)
        out[3 * nodes[i] + j] = w.x()->array()[bs * d[i] + j];
  }
  return out;
}

void Problem::update_reference()
{
  _profile_points = press_profile->function_space()->tabulate_dof_coordinates(false);
  auto fresh = cell_fields(*_cells, _parts, _materials, _fibres, _dimension,
                           fields.at("c10")->function_space(),
                           fields.at("fibre_1")->function_space());
  for (const char* name : {"fibre_1", "fibre_2"})
    std::copy(fresh.at(name)->x()->array().begin(), fresh.at(name)->x()->array().end(),
              fields.at(name)->x()->mutable_array().begin());
}

Mat Problem::create_matrix(const std::string& type) const
{
  la::SparsityPattern pattern = fem::create_sparsity_pattern(*_J);
  pattern.assemble();
  Mat A = la::petsc::create_matrix(u->function_space()->mesh()->comm(), pattern, type);
  if (type == "sbaij")
  {
    // dolfinx preallocates whole rows, which SBAIJ reads as none: count
    // the blocks on and right of the diagonal instead.
    const auto& graph = pattern.graph();
    const common::IndexMap columns = pattern.column_index_map();
    const std::int64_t first = columns.local_range()[0];
    const std::int32_t owned = columns.size_local();
    const std::vector<std::int64_t> ghosts = columns.ghosts();
    std::vector<PetscInt> diagonal(graph.num_nodes(), 0), off(graph.num_nodes(), 0),
        d_upper(graph.num_nodes(), 0), o_upper(graph.num_nodes(), 0);
    for (std::int32_t i = 0; i < graph.num_nodes(); ++i)
      for (std::int32_t j : graph.links(i))
      {
        const std::int64_t column = j < owned ? first + j : ghosts[j - owned];
        auto [full, upper] = j < owned ? std::tie(diagonal[i], d_upper[i])
                                       : std::tie(off[i], o_upper[i]);
        ++full;
        if (column >= first + i)
          ++upper;
      }
    MatXAIJSetPreallocation(A, pattern.block_size(0), diagonal.data(), off.data(),
                            d_upper.data(), o_upper.data());
    MatSetOption(A, MAT_NEW_NONZERO_ALLOCATION_ERR, PETSC_TRUE);
    MatSetOption(A, MAT_KEEP_NONZERO_PATTERN, PETSC_TRUE);
    MatSetOption(A, MAT_IGNORE_LOWER_TRIANGULAR, PETSC_TRUE);
  }
  const auto& V = *u->function_space();
  {
    MatNullSpace modes = rigid_body_modes(V, _dimension);
    MatSetNearNullSpace(A, modes);
    MatNullSpaceDestroy(&modes);
  }
  return A;
}

std::vector<double> Problem::cavity_volumes() const { return whole_model(_volumes); }

std::vector<std::array<double, 3>>
Problem::displacement_at(const std::vector<std::array<double, 3>>& points) const
{
  return Probes(*this, points).displacement();
}

void Problem::update_von_mises() { von_mises->interpolate(*_von_mises); }

Problem::Place Problem::at_cell(std::int32_t cell, double value) const
{
  const auto& mesh = *u->function_space()->mesh();
  auto nodes = mesh.geometry().dofmap().links(cell);
  Place p{value, {0, 0, 0}, ""};
  for (auto n : nodes)
    for (int j = 0; j < 3; ++j)
      p.x[j] += mesh.geometry().x()[3 * n + j] / nodes.size();
  auto cells = _cells->indices();
  auto it = std::lower_bound(cells.begin(), cells.end(), cell);
  if (it != cells.end() && *it == cell)
    if (auto part = _parts.find(_cells->values()[it - cells.begin()]); part != _parts.end())
      p.part = part->second;
  return p;
}

Problem::Place Problem::gather(const Place& local) const
{
  MPI_Comm comm = u->function_space()->mesh()->comm();
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  struct
  {
    double value;
    int rank;
  } mine{local.value, rank}, best;
  MPI_Allreduce(&mine, &best, 1, MPI_DOUBLE_INT, MPI_MINLOC, comm);
  Place p = local;
  p.value = best.value;
  MPI_Bcast(p.x.data(), 3, MPI_DOUBLE, best.rank, comm);
  int n = static_cast<int>(p.part.size());
  MPI_Bcast(&n, 1, MPI_INT, best.rank, comm);
  p.part.resize(n);
  MPI_Bcast(p.part.data(), n, MPI_CHAR, best.rank, comm);
  return p;
}

Problem::Place Problem::smallest_jacobian() const
{
  const auto& mesh = *u->function_space()->mesh();
  const std::int32_t n = mesh.topology().index_map(mesh.topology().dim())->size_local();
  std::vector<std::int32_t> cells(n);
  std::iota(cells.begin(), cells.end(), 0);
  const std::size_t points = _det_F->X().second[0];
  struct Table
  {
    double& operator()(std::size_t i, std::size_t j) { return data[i * cols + j]; }
    std::vector<double> data;
    std::size_t cols;
  } values{std::vector<double>(n * points), points};
  _det_F->eval(std::span<const std::int32_t>(cells), values);
  // NaN counts as smallest: a NaN displacement is as inadmissible as a fold.
  std::int32_t worst = -1;
  double smallest = std::numeric_limits<double>::infinity();
  for (std::int32_t c = 0; c < n; ++c)
    for (std::size_t q = 0; q < points; ++q)
    {
      const double v = values(c, q);
      if (std::isnan(v) || v < smallest)
      {
        smallest = std::isnan(v) ? -std::numeric_limits<double>::infinity() : v;
        worst = c;
      }
    }
  return gather(worst < 0 ? Place{smallest, {0, 0, 0}, ""} : at_cell(worst, smallest));
}

Problem::Place Problem::largest_residual(const la::Vector<double>& b) const
{
  // The negative magnitude, so that the smallest wins in gather().
  const std::int32_t n = b.map()->size_local() * b.bs();
  std::int32_t worst = -1;
  double largest = -1;
  for (std::int32_t i = 0; i < n; ++i)
  {
    const double v = std::isfinite(b.array()[i]) ? std::abs(b.array()[i])
                                                 : std::numeric_limits<double>::infinity();
    if (v > largest)
      largest = v, worst = i;
  }
  Place p{-largest, {0, 0, 0}, ""};
  if (worst >= 0)
  {
    auto V = u->function_space();
    const auto x = V->tabulate_dof_coordinates(false);
    const int node = worst / b.bs();
    for (int j = 0; j < 3; ++j)
      p.x[j] = x[3 * node + j];
  }
  p = gather(p);
  p.value = -p.value;
  return p;
}

std::int64_t Problem::dofs() const
{
  auto V = u->function_space();
  return V->dofmap()->index_map->size_global() * V->dofmap()->index_map_bs();
}

} // namespace nct::solid
