#include "air/problem.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numeric>
#include <stdexcept>

#include <dolfinx/fem/assembler.h>
#include <dolfinx/fem/petsc.h>
#include <dolfinx/fem/utils.h>
#include <dolfinx/la/petsc.h>

#include "form_tags.h"
#include "air_ale_p1_full.h"
#include "air_ale_p1_full_axisymmetric.h"
#include "air_ale_p1_full_plane.h"
#include "air_p1_full.h"
#include "air_p1_full_axisymmetric.h"
#include "air_p1_full_plane.h"

namespace nct::air
{
namespace
{
using namespace dolfinx;

/// Facet tags of the outlet and the interface in forms/air.py and forms/air_ale.py.
constexpr std::int32_t outlet_tag = forms::tags::outlet, interface_tag = forms::tags::interface;

/// The compiled kernels of forms/air.py (fixed mesh) and forms/air_ale.py
/// (moving) for one dimension.
struct Kernels
{
  ufcx_function_space* (*space)(const char*);
  ufcx_form *R, *J;
  ufcx_function_space* (*space_ale)(const char*);
  ufcx_form *R_ale, *J_ale, *J_mesh, *force_x, *force_y, *force_z, *traction_power, *volume,
      *pressure_volume;
  ufcx_expression* mesh_jacobian;
};

#define NCT_AIR_KERNELS(d)                                                                 \
  Kernels{functionspace_form_air_p1_full##d##_R, form_air_p1_full##d##_R,                  \
          form_air_p1_full##d##_J, functionspace_form_air_ale_p1_full##d##_R,               \
          form_air_ale_p1_full##d##_R, form_air_ale_p1_full##d##_J,                         \
          form_air_ale_p1_full##d##_J_mesh, form_air_ale_p1_full##d##_force_x,              \
          form_air_ale_p1_full##d##_force_y, form_air_ale_p1_full##d##_force_z,             \
          form_air_ale_p1_full##d##_traction_power, form_air_ale_p1_full##d##_volume,        \
          form_air_ale_p1_full##d##_pressure_volume,                                       \
          expression_air_ale_p1_full##d##_mesh_jacobian}

Kernels kernels(section::Dimension d)
{
  switch (d)
  {
  case section::Dimension::axisymmetric:
    return NCT_AIR_KERNELS(_axisymmetric);
  case section::Dimension::plane:
    return NCT_AIR_KERNELS(_plane);
  default:
    return NCT_AIR_KERNELS();
  }
}

} // namespace

Problem::Problem(const meshio::Tagged& m, const Fluid& fluid, const Boundaries& boundaries,
                 double velocity_scale, std::shared_ptr<fem::Function<double>> mesh_displacement,
                 section::Dimension dimension)
    : d(std::move(mesh_displacement)), _gdim(section::mesh_dimension(dimension))
{
  if (m.mesh->geometry().dim() != _gdim)
    throw std::invalid_argument("a " + section::name(dimension) + " air needs a mesh of "
                                + std::to_string(_gdim) + " dimensions");
  const Kernels k = kernels(dimension);
  const auto space = moving() ? k.space_ale : k.space;
  auto W = std::make_shared<fem::FunctionSpace>(fem::create_functionspace(space, "up", m.mesh));
  auto Wm = std::make_shared<fem::FunctionSpace>(
      fem::create_functionspace(space, moving() ? "w_n" : "w", m.mesh));
  up = std::make_shared<fem::Function<double>>(W);
  up_n = std::make_shared<fem::Function<double>>(W);
  up_nm1 = std::make_shared<fem::Function<double>>(W);
  w = std::make_shared<fem::Function<double>>(Wm);
  w->name = "mesh_velocity";
  if (moving())
  {
    d_n = std::make_shared<fem::Function<double>>(d->function_space());
    d_nm1 = std::make_shared<fem::Function<double>>(d->function_space());
  }

  _facets = m.facets;
  auto [V, velocity_map] = W->sub({0})->collapse();
  auto [Q, pressure_map] = W->sub({1})->collapse();
  auto Vp = std::make_shared<fem::FunctionSpace>(std::move(V));
  auto Qp = std::make_shared<fem::FunctionSpace>(std::move(Q));
  _velocity_dofs = std::move(velocity_map);
  _pressure_dofs = std::move(pressure_map);
  velocity = std::make_shared<fem::Function<double>>(Vp);
  velocity->name = "air_velocity";
  pressure = std::make_shared<fem::Function<double>>(Qp);
  pressure->name = "air_pressure";
  _inlet_shape = std::make_shared<fem::Function<double>>(Vp);
  _inlet = std::make_shared<fem::Function<double>>(Vp);

  _bc_diagonal = fluid.density * velocity_scale * 1.0; // [g/ms]: rho U (1 mm)^2
  for (auto [name, value] :
       {std::pair{"rho", fluid.density}, std::pair{"mu", fluid.viscosity},
        std::pair{"beta", fluid.backflow},
        std::pair{"continuity_scale", fluid.density * velocity_scale},
        std::pair{"inv_dt", 0.0}, std::pair{"inv_tau_time", 1 / fluid.stabilisation_time},
        std::pair{"c0", 1.0}, std::pair{"c1", -1.0},
        std::pair{"c2", 0.0}})
    _constants[name] = std::make_shared<fem::Constant<double>>(value);

  std::map<std::int32_t, std::int32_t> facet_tag;
  for (auto g : boundaries.outlet)
    facet_tag[g] = outlet_tag;
  for (auto g : boundaries.interface)
    facet_tag[g] = interface_tag;
  auto facet_tags = std::make_shared<mesh::MeshTags<std::int32_t>>(
      meshio::retag(*m.facets, facet_tag));
  const std::map<fem::IntegralType, const mesh::MeshTags<int>*> subdomains
      = {{fem::IntegralType::exterior_facet, facet_tags.get()}};
  std::map<std::string, std::shared_ptr<const fem::Function<double>>> coeffs
      = {{"up", up}, {"up_n", up_n}, {"up_nm1", up_nm1}, {moving() ? "w_n" : "w", w}};
  if (moving())
    coeffs.insert({{"d", d}, {"d_n", d_n}, {"d_nm1", d_nm1}});
  const std::map<std::string, std::shared_ptr<const fem::Constant<double>>> constants(
      _constants.begin(), _constants.end());
  auto form = [&](const ufcx_form& f, std::vector<std::shared_ptr<const fem::FunctionSpace>> V)
  {
    return std::make_shared<fem::Form<double>>(fem::create_form<double>(
        f, V, coeffs, constants, subdomains, V.empty() ? m.mesh : nullptr));
  };
  if (moving())
  {
    _R = form(*k.R_ale, {W});
    _J = form(*k.J_ale, {W, W});
    _J_mesh = form(*k.J_mesh, {W, d->function_space()});
    _force = {form(*k.force_x, {}), form(*k.force_y, {}), form(*k.force_z, {})};
    _traction_power = form(*k.traction_power, {});
    _volume = form(*k.volume, {});
    _pressure_volume = form(*k.pressure_volume, {});
    _mesh_jacobian = std::make_shared<fem::Expression<double>>(
        fem::create_expression<double>(*k.mesh_jacobian, coeffs, {}, m.mesh));
  }
  else
  {
    _R = form(*k.R, {W});
    _J = form(*k.J, {W, W});
  }
  for (const ufcx_form* f : moving() ? std::vector{k.R_ale, k.J_ale} : std::vector{k.R, k.J})
    _forms_signature += std::string(f->signature) + " ";

  // Dirichlet conditions: the inlet first, so that walls win on its rim.
  auto W0 = W->sub({0});
  const int fdim = _gdim - 1;
  for (auto g : boundaries.inlet)
  {
    auto dofs = fem::locate_dofs_topological({*W0, *Vp}, fdim, m.facets->find(g));
    _bcs.push_back(std::make_shared<fem::DirichletBC<double>>(_inlet, std::move(dofs), W0));
  }
  // Components: dolfinx 0.5 cannot take W.sub(0).sub(2) of this mixed
  // space, so the velocity's dofs are found whole and filtered by
  // component (the collapsed space's dofs are unrolled, gdim per node).
  auto zero = std::make_shared<fem::Function<double>>(Vp);
  for (auto& [g, components] : boundaries.zero)
  {
    auto all = fem::locate_dofs_topological({*W0, *Vp}, fdim, m.facets->find(g));
    std::array<std::vector<std::int32_t>, 2> dofs;
    for (std::size_t j = 0; j < all[0].size(); ++j)
      if (std::find(components.begin(), components.end(), all[1][j] % _gdim)
          != components.end())
      {
        dofs[0].push_back(all[0][j]);
        dofs[1].push_back(all[1][j]);
      }
    _bcs.push_back(std::make_shared<fem::DirichletBC<double>>(zero, std::move(dofs), W0));
  }
}

void Problem::set_inlet(
    const std::function<std::array<double, 3>(const std::array<double, 3>&)>& shape)
{
  const std::vector<double> x
      = _inlet_shape->function_space()->tabulate_dof_coordinates(false);
  auto values = _inlet_shape->x()->mutable_array();
  for (std::size_t i = 0; i < values.size() / _gdim; ++i)
  {
    const auto v = shape({x[3 * i], x[3 * i + 1], x[3 * i + 2]});
    std::copy_n(v.begin(), _gdim, values.begin() + _gdim * i);
  }
}

void Problem::set_inlet_scale(double scale)
{
  auto shape = _inlet_shape->x()->array();
  auto values = _inlet->x()->mutable_array();
  for (std::size_t i = 0; i < values.size(); ++i)
    values[i] = scale * shape[i];
  auto x = up->x()->mutable_array();
  for (const auto& bc : _bcs)
    bc->set(x);
  up->x()->scatter_fwd();
}

void Problem::set_time_step(double dt, int order)
{
  _dt = dt;
  if (!std::isfinite(dt))
  {
    _constants["inv_dt"]->value = {0.0};
    return;
  }
  _constants["inv_dt"]->value = {1 / dt};
  std::array<double, 3> c{1, -1, 0};
  if (order == 2 && _last_dt > 0)
  {
    // Variable-step BDF2: omega = dt_{n+1} / dt_n.
    const double omega = dt / _last_dt;
    c = {(1 + 2 * omega) / (1 + omega), -(1 + omega), omega * omega / (1 + omega)};
  }
  _constants["c0"]->value = {c[0]};
  _constants["c1"]->value = {c[1]};
  _constants["c2"]->value = {c[2]};
}

void Problem::advance()
{
  if (moving())
  {
    // The step's mesh velocity (for the next step's tau), then the history.
    const double inv_dt = _constants["inv_dt"]->value[0], c0 = _constants["c0"]->value[0],
                 c1 = _constants["c1"]->value[0], c2 = _constants["c2"]->value[0];
    auto x = d->x()->array(), xn = d_n->x()->array(), xnm1 = d_nm1->x()->array();
    auto wv = w->x()->mutable_array();
    for (std::size_t i = 0; i < wv.size(); ++i)
      wv[i] = inv_dt * (c0 * x[i] + c1 * xn[i] + c2 * xnm1[i]);
    std::copy(xn.begin(), xn.end(), d_nm1->x()->mutable_array().begin());
    std::copy(x.begin(), x.end(), d_n->x()->mutable_array().begin());
  }
  std::copy(up_n->x()->array().begin(), up_n->x()->array().end(),
            up_nm1->x()->mutable_array().begin());
  std::copy(up->x()->array().begin(), up->x()->array().end(),
            up_n->x()->mutable_array().begin());
  _last_dt = _dt;
}

nlohmann::json Problem::save(io::CheckpointWriter& checkpoint) const
{
  checkpoint.add_geometry("air/geometry", *up->function_space()->mesh());
  for (auto [name, f] : {std::pair{"up", up}, {"up_n", up_n}, {"up_nm1", up_nm1}})
    checkpoint.add(std::string("air/") + name, *f);
  if (moving())
    for (auto [name, f] : {std::pair{"d", d}, {"d_n", d_n}, {"d_nm1", d_nm1}, {"w", w}})
      checkpoint.add(std::string("air/") + name, *f);
  return {{"last_dt", _last_dt}};
}

void Problem::restore(const io::CheckpointReader& checkpoint, const nlohmann::json& scalars)
{
  auto mesh = std::const_pointer_cast<mesh::Mesh>(up->function_space()->mesh());
  checkpoint.read_geometry("air/geometry", *mesh);
  for (auto [name, f] : {std::pair{"up", up}, {"up_n", up_n}, {"up_nm1", up_nm1}})
    checkpoint.read(std::string("air/") + name, *f);
  if (moving())
    for (auto [name, f] : {std::pair{"d", d}, {"d_n", d_n}, {"d_nm1", d_nm1}, {"w", w}})
      checkpoint.read(std::string("air/") + name, *f);
  _last_dt = scalars.at("last_dt");
}

void Problem::residual(la::Vector<double>& b)
{
  std::fill(b.mutable_array().begin(), b.mutable_array().end(), 0.0);
  fem::assemble_vector<double>(b.mutable_array(), *_R);
  b.scatter_rev(std::plus<double>());
  fem::set_bc<double>(b.mutable_array(), _bcs, up->x()->array(), -_bc_diagonal);
}

void Problem::jacobian(Mat A)
{
  MatZeroEntries(A);
  fem::assemble_matrix(la::petsc::Matrix::set_block_fn(A, ADD_VALUES), *_J, _bcs);
  MatAssemblyBegin(A, MAT_FLUSH_ASSEMBLY);
  MatAssemblyEnd(A, MAT_FLUSH_ASSEMBLY);
  fem::set_diagonal<double>(la::petsc::Matrix::set_fn(A, INSERT_VALUES),
                            *_J->function_spaces()[0], _bcs, _bc_diagonal);
  MatAssemblyBegin(A, MAT_FINAL_ASSEMBLY);
  MatAssemblyEnd(A, MAT_FINAL_ASSEMBLY);
}

Mat Problem::create_matrix() const { return fem::petsc::create_matrix(*_J, "aij"); }

void Problem::update_fields()
{
  auto x = up->x()->array();
  auto u = velocity->x()->mutable_array();
  for (std::size_t i = 0; i < _velocity_dofs.size(); ++i)
    u[i] = x[_velocity_dofs[i]];
  auto p = pressure->x()->mutable_array();
  for (std::size_t i = 0; i < _pressure_dofs.size(); ++i)
    p[i] = x[_pressure_dofs[i]];
}

std::vector<std::int8_t> Problem::dirichlet_marker() const
{
  const auto& map = *up->function_space()->dofmap()->index_map;
  std::vector<std::int8_t> marker(
      up->function_space()->dofmap()->index_map_bs() * (map.size_local() + map.num_ghosts()), 0);
  for (const auto& bc : _bcs)
    bc->mark_dofs(marker);
  return marker;
}

std::array<double, 3> Problem::interface_force() const
{
  std::array<double, 3> f;
  for (int i = 0; i < 3; ++i)
    f[i] = fem::assemble_scalar(*_force.at(i));
  MPI_Allreduce(MPI_IN_PLACE, f.data(), 3, MPI_DOUBLE, MPI_SUM, up->function_space()->mesh()->comm());
  return f;
}

double Problem::traction_power() const
{
  double p = fem::assemble_scalar(*_traction_power);
  MPI_Allreduce(MPI_IN_PLACE, &p, 1, MPI_DOUBLE, MPI_SUM, up->function_space()->mesh()->comm());
  return p;
}

double Problem::mean_pressure() const
{
  std::array<double, 2> v{fem::assemble_scalar(*_pressure_volume), fem::assemble_scalar(*_volume)};
  MPI_Allreduce(MPI_IN_PLACE, v.data(), 2, MPI_DOUBLE, MPI_SUM, up->function_space()->mesh()->comm());
  return v[0] / v[1];
}

std::vector<std::array<std::int32_t, 2>>
Problem::wall_dofs(const std::vector<std::int32_t>& groups) const
{
  std::vector<std::int32_t> facets;
  for (auto g : groups)
  {
    auto f = _facets->find(g);
    facets.insert(facets.end(), f.begin(), f.end());
  }
  std::sort(facets.begin(), facets.end());
  facets.erase(std::unique(facets.begin(), facets.end()), facets.end());
  auto W0 = up->function_space()->sub({0});
  auto dofs = fem::locate_dofs_topological({*W0, *velocity->function_space()}, _gdim - 1, facets);
  const auto& map = *up->function_space()->dofmap()->index_map;
  const std::int32_t owned = map.size_local() * up->function_space()->dofmap()->index_map_bs();
  std::vector<std::array<std::int32_t, 2>> wall;
  for (std::size_t j = 0; j < dofs[0].size(); ++j)
    if (dofs[0][j] < owned)
      wall.push_back({dofs[0][j], dofs[1][j] % _gdim});
  return wall;
}

std::array<double, 3> Problem::force_on(const std::vector<std::array<std::int32_t, 2>>& dofs) const
{
  la::Vector<double> b(up->x()->map(), up->x()->bs());
  fem::assemble_vector<double>(b.mutable_array(), *_R);
  b.scatter_rev(std::plus<double>());
  std::array<double, 3> force{0, 0, 0};
  for (auto [dof, component] : dofs)
    force[component] -= b.array()[dof];
  MPI_Allreduce(MPI_IN_PLACE, force.data(), 3, MPI_DOUBLE, MPI_SUM,
                up->function_space()->mesh()->comm());
  return force;
}

std::pair<double, std::array<double, 3>> Problem::smallest_mesh_jacobian() const
{
  const auto& mesh = *up->function_space()->mesh();
  const std::int32_t n = mesh.topology().index_map(_gdim)->size_local();
  std::vector<std::int32_t> cells(n);
  std::iota(cells.begin(), cells.end(), 0);
  struct Table
  {
    double& operator()(std::size_t i, std::size_t) { return data[i]; }
    std::vector<double> data;
  } values{std::vector<double>(n)};
  _mesh_jacobian->eval(std::span<const std::int32_t>(cells), values);
  struct
  {
    double value;
    int rank;
  } mine{std::numeric_limits<double>::infinity(), 0}, best;
  MPI_Comm_rank(mesh.comm(), &mine.rank);
  std::int32_t worst = -1;
  for (std::int32_t c = 0; c < n; ++c)
    if (std::isnan(values.data[c]) || values.data[c] < mine.value)
    {
      mine.value = std::isnan(values.data[c]) ? -std::numeric_limits<double>::infinity()
                                              : values.data[c];
      worst = c;
    }
  std::array<double, 3> place{0, 0, 0};
  if (worst >= 0)
    for (auto node : mesh.geometry().dofmap().links(worst))
      for (int j = 0; j < 3; ++j)
        place[j] += mesh.geometry().x()[3 * node + j] / (_gdim + 1);
  MPI_Allreduce(&mine, &best, 1, MPI_DOUBLE_INT, MPI_MINLOC, mesh.comm());
  MPI_Bcast(place.data(), 3, MPI_DOUBLE, best.rank, mesh.comm());
  return {best.value, place};
}

std::int64_t Problem::dofs() const
{
  auto W = up->function_space();
  return W->dofmap()->index_map->size_global() * W->dofmap()->index_map_bs();
}

} // namespace nct::air
