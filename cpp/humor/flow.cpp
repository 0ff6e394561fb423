#include "humor/flow.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include <dolfinx/fem/assembler.h>
#include <dolfinx/fem/utils.h>
#include <dolfinx/mesh/utils.h>

#include "humor_flow_p1_full.h"
#include "humor_flow_p1_full_axisymmetric.h"
#include "humor_flow_p1_full_plane.h"
#include "humor_flow_p2_full.h"
#include "humor_flow_p2_full_axisymmetric.h"
#include "humor_flow_p2_full_plane.h"
#include "biomarkers/registry.h"
#include "form_tags.h"
#include "io/format.h"
#include "io/laps.h"

namespace nct::humor
{
namespace
{
using namespace dolfinx;
using io::format;
using Place = std::array<double, 3>;

/// The compiled forms of forms/humor_flow.py for one solid element.
struct Kernels
{
  ufcx_function_space* (*space)(const char*);        ///< the solid mesh's (p_1)
  ufcx_function_space* (*humor_space)(const char*);  ///< the humor mesh's (p)
  ufcx_form *load, *load_u, *load_p_1, *load_p_2, *flux_1, *flux_2, *flux_1_u, *flux_2_u,
      *cut_normal, *cut_area, *cut_flux, *cut_motion, *laplace, *laplace_p, *lid_area;
};

#define NCT_FLOW_KERNELS(v)                                                                  \
  Kernels{functionspace_form_humor_flow_##v##_load,                                          \
          functionspace_form_humor_flow_##v##_laplace,                                       \
          form_humor_flow_##v##_load,                                                        \
          form_humor_flow_##v##_load_u,                                                      \
          form_humor_flow_##v##_load_p_1,                                                    \
          form_humor_flow_##v##_load_p_2,                                                    \
          form_humor_flow_##v##_flux_1,                                                      \
          form_humor_flow_##v##_flux_2,                                                      \
          form_humor_flow_##v##_flux_1_u,                                                    \
          form_humor_flow_##v##_flux_2_u,                                                    \
          form_humor_flow_##v##_cut_normal,                                                  \
          form_humor_flow_##v##_cut_area,                                                    \
          form_humor_flow_##v##_cut_flux,                                                    \
          form_humor_flow_##v##_cut_motion,                                                  \
          form_humor_flow_##v##_laplace,                                                     \
          form_humor_flow_##v##_laplace_p,                                                   \
          form_humor_flow_##v##_lid_area}

#define NCT_FLOW_KERNELS_OF(degree, d)                                                       \
  return degree == 1 ? NCT_FLOW_KERNELS(p1_full##d) : NCT_FLOW_KERNELS(p2_full##d);

Kernels kernels(int degree, section::Dimension dimension)
{
  switch (dimension)
  {
  case section::Dimension::three:
    NCT_FLOW_KERNELS_OF(degree, )
  case section::Dimension::axisymmetric:
    NCT_FLOW_KERNELS_OF(degree, _axisymmetric)
  case section::Dimension::plane:
    NCT_FLOW_KERNELS_OF(degree, _plane)
  }
  throw std::invalid_argument("humor_flow: unknown dimension");
}

std::string where(const Place& x)
{
  return format("at x = (%.3f, %.3f, %.3f) mm", x[0], x[1], x[2]);
}

void sum(MPI_Comm comm, std::vector<double>& v)
{
  MPI_Allreduce(MPI_IN_PLACE, v.data(), static_cast<int>(v.size()), MPI_DOUBLE, MPI_SUM, comm);
}

/// The local facets of `groups` (their union).
std::vector<std::int32_t> facets_of(const meshio::Tagged& m, const std::vector<std::int32_t>& groups)
{
  std::vector<std::int32_t> f;
  for (auto g : groups)
  {
    auto found = m.facets->find(g);
    f.insert(f.end(), found.begin(), found.end());
  }
  std::sort(f.begin(), f.end());
  f.erase(std::unique(f.begin(), f.end()), f.end());
  return f;
}

/// Signed volume (area on a section) of each local cell of an affine mesh.
std::vector<double> cell_volumes(const mesh::Mesh& mesh)
{
  const std::int32_t cells = mesh.topology().index_map(mesh.topology().dim())->size_local();
  std::vector<double> v(cells);
  for (std::int32_t c = 0; c < cells; ++c)
    v[c] = meshio::determinant(meshio::cell_edges(mesh, c));
  return v;
}

/// The solid's displacement degree (1 or 2), from its element's layout.
int degree_of(const fem::FunctionSpace& V)
{
  const int tdim = V.mesh()->topology().dim();
  return V.dofmap()->element_dof_layout().num_dofs() == tdim + 1 ? 1 : 2;
}

/// Per (block) dof of a P1 space on an affine mesh, the place of its
/// geometry node, copied: places of the same gmsh node match exactly on
/// the meshes split from one model (tabulate_dof_coordinates' push-forward
/// does not).
std::vector<double> vertex_places(const fem::FunctionSpace& V)
{
  const auto& mesh = *V.mesh();
  const int tdim = mesh.topology().dim();
  const auto& map = *V.dofmap()->index_map;
  std::vector<double> places(3 * (map.size_local() + map.num_ghosts()), 0.0);
  const auto x = mesh.geometry().x();
  const std::int32_t cells = mesh.topology().index_map(tdim)->size_local()
                             + mesh.topology().index_map(tdim)->num_ghosts();
  for (std::int32_t c = 0; c < cells; ++c)
  {
    auto nodes = mesh.geometry().dofmap().links(c);
    auto dofs = V.dofmap()->cell_dofs(c);
    for (std::size_t i = 0; i < dofs.size(); ++i)
      std::copy_n(x.begin() + 3 * nodes[i], 3, places.begin() + 3 * dofs[i]);
  }
  return places;
}

} // namespace

Flow::Flow(solid::Problem& solid, const meshio::Tagged& humor, const Boundaries& boundaries,
           double density)
    : Humor(solid), _humor_mesh(humor.mesh), _x_built(humor.mesh->geometry().x().begin(),
                                                       humor.mesh->geometry().x().end()),
      _cell_volume_built(cell_volumes(*humor.mesh)), _density(density)
{
  const std::size_t cavities = boundaries.walls.size();
  if (cavities == 0 || cavities > 2 || boundaries.volumes.size() != cavities)
    throw std::invalid_argument("humor_flow: needs one or two cavities, with their walls");
  const int gdim = humor.mesh->geometry().dim();
  const Kernels k = kernels(degree_of(*solid.u->function_space()), solid.dimension());
  auto S = std::make_shared<fem::FunctionSpace>(
      fem::create_functionspace(
          k.space, "p_1",
          std::const_pointer_cast<mesh::Mesh>(solid.u->function_space()->mesh())));
  auto Q = std::make_shared<fem::FunctionSpace>(
      fem::create_functionspace(k.humor_space, "p", humor.mesh));
  for (auto& w : _p_wall)
    w = std::make_shared<fem::Function<double>>(S);
  p = std::make_shared<fem::Function<double>>(Q);
  p->name = "humor_pressure";

  // The humor mesh's extension: sliding on the axis and the symmetry
  // planes, held on every other boundary facet but the walls.
  {
    const int fdim = gdim - 1;
    humor.mesh->topology_mutable().create_connectivity(fdim, gdim);
    const auto exterior = mesh::exterior_facet_indices(humor.mesh->topology());
    std::vector<std::int32_t> wall_groups;
    for (auto& w : boundaries.walls)
      wall_groups.insert(wall_groups.end(), w.begin(), w.end());
    std::map<std::int32_t, std::int32_t> tag; // facet -> new tag
    for (auto f : exterior)
      tag[f] = 1; // rigid
    for (auto f : facets_of(humor, boundaries.axis))
      tag[f] = 2;
    for (auto f : facets_of(humor, boundaries.open))
      tag[f] = 1;
    mesh_motion::Boundaries mb{{{1, {0, 1, 2}}, {2, {0}}}, {0}};
    for (auto g : boundaries.symmetry)
    {
      const int axis = meshio::normal_axis(*humor.mesh, *humor.facets, g);
      for (auto f : facets_of(humor, {g}))
        tag[f] = 3 + axis;
      mb.fixed.push_back({3 + axis, {axis}});
    }
    for (auto f : facets_of(humor, wall_groups))
      tag[f] = 0;
    // The lid moves with the cut: given, like the wall.
    const auto lid = facets_of(humor, boundaries.lid);
    for (auto f : lid)
      tag[f] = 0;
    if (!lid.empty() || !boundaries.lid.empty())
      _lid_tags = std::make_shared<mesh::MeshTags<std::int32_t>>(
          humor.mesh, fdim, lid, std::vector<std::int32_t>(lid.size(), forms::tags::humor_lid));
    std::vector<std::int32_t> facets, values;
    for (auto [f, t] : tag)
      facets.push_back(f), values.push_back(t);
    meshio::Tagged h = humor;
    h.facets = std::make_shared<mesh::MeshTags<std::int32_t>>(humor.mesh, fdim, facets, values);
    mesh_motion::Settings ms;
    _motion = std::make_unique<mesh_motion::Problem>(h, ms, mb);
    _motion->d->name = "humor_mesh_displacement";
  }

  choose_held_nodes(humor, boundaries);
  _humor_owned = Q->dofmap()->index_map->size_local();
  for (std::int32_t b = 0; b < _humor_owned; ++b)
    if (!std::binary_search(_held.begin(), _held.end(), b))
      _active.push_back(b);
  _scalar_owned = S->dofmap()->index_map->size_local();
  pair(humor, boundaries);
  _solid_held = solid.dynamic_dirichlet_marker(); // the systems run in the dynamics
  _b_solid = std::make_unique<la::Vector<double>>(solid.u->x()->map(), solid.u->x()->bs());
  _b_wall = std::make_unique<la::Vector<double>>(solid.u->x()->map(), solid.u->x()->bs());
  _solid_owned = solid.u->x()->map()->size_local() * solid.u->x()->bs();
  _b_humor = std::make_unique<la::Vector<double>>(p->x()->map(), 1);
  _b_scalar = std::make_unique<la::Vector<double>>(S->dofmap()->index_map, 1);
  // The solid with the humor alone (no air): a system of its own.
  _own_unknowns = std::make_unique<solver::Monolithic>(
      humor.mesh->comm(),
      std::vector<solver::Monolithic::Field>{{"solid", solid.u, std::nullopt}, field()});
  _own = place(*_own_unknowns, 0, 1);
  make_forms();
}

void Flow::choose_held_nodes(const meshio::Tagged& humor, const Boundaries& boundaries)
{
  // p~ = 0 on the openings; in a humor without one, at the node off its
  // walls nearest the centroid of its nodes (any node would do; an inner
  // one keeps the incompatible flux of the neglected order rho |w|^2 off
  // the wall).
  auto& Q = *p->function_space();
  const int tdim = humor.mesh->topology().dim();
  const auto X = vertex_places(Q);
  const std::int32_t owned = Q.dofmap()->index_map->size_local();
  MPI_Comm comm = humor.mesh->comm();
  int rank;
  MPI_Comm_rank(comm, &rank);
  std::vector<std::int8_t> open(X.size() / 3, 0);
  for (auto b : fem::locate_dofs_topological(Q, tdim - 1, facets_of(humor, boundaries.open)))
    open[b] = 1;
  for (std::int32_t b = 0; b < owned; ++b)
    if (open[b])
      _held.push_back(b);
  for (std::size_t c = 0; c < boundaries.walls.size(); ++c)
  {
    std::vector<std::int8_t> in(X.size() / 3, 0), wall(X.size() / 3, 0);
    for (auto g : boundaries.volumes[c])
      for (auto cell : humor.cells->find(g))
        for (auto b : Q.dofmap()->cell_dofs(cell))
          in[b] = 1;
    int opens = 0;
    for (std::int32_t b = 0; b < owned; ++b)
      opens += in[b] && open[b];
    MPI_Allreduce(MPI_IN_PLACE, &opens, 1, MPI_INT, MPI_SUM, comm);
    if (opens > 0)
      continue;
    for (auto b : fem::locate_dofs_topological(Q, tdim - 1, facets_of(humor, boundaries.walls[c])))
      wall[b] = 1;
    std::vector<double> centre{0, 0, 0, 0};
    for (std::int32_t b = 0; b < owned; ++b)
      if (in[b])
        for (int j = 0; j < 3; ++j)
          centre[j] += X[3 * b + j], centre[3] += j == 0;
    sum(comm, centre);
    if (centre[3] == 0)
      throw std::runtime_error(format("humor_flow: cavity %zu has no humor cells", c + 1));
    // The nearest: (distance, x, y, z, rank) smallest over the ranks.
    struct
    {
      double d;
      int rank;
    } best{std::numeric_limits<double>::infinity(), rank};
    std::int32_t mine = -1;
    for (std::int32_t b = 0; b < owned; ++b)
    {
      if (!in[b] || wall[b])
        continue;
      const double d = std::hypot(X[3 * b] - centre[0] / centre[3],
                                  X[3 * b + 1] - centre[1] / centre[3],
                                  X[3 * b + 2] - centre[2] / centre[3]);
      if (d < best.d)
        best.d = d, mine = b;
    }
    MPI_Allreduce(MPI_IN_PLACE, &best, 1, MPI_DOUBLE_INT, MPI_MINLOC, comm);
    if (!std::isfinite(best.d))
      throw std::runtime_error(format("humor_flow: cavity %zu's humor has no node off its wall",
                                      c + 1));
    if (best.rank == rank)
      _held.push_back(mine);
  }
  std::sort(_held.begin(), _held.end());
}

void Flow::pair(const meshio::Tagged& humor, const Boundaries& boundaries)
{
  MPI_Comm comm = humor.mesh->comm();
  auto& Q = *p->function_space();
  const int fdim = humor.mesh->topology().dim() - 1;
  const auto XQ = vertex_places(Q);

  // Every humor wall node (owned), the same list on every rank, by cavity and place.
  std::vector<double> mine;
  for (std::size_t c = 0; c < boundaries.walls.size(); ++c)
    for (auto b : fem::locate_dofs_topological(Q, fdim, facets_of(humor, boundaries.walls[c])))
      if (b < _humor_owned)
        mine.insert(mine.end(), {double(c), XQ[3 * b], XQ[3 * b + 1], XQ[3 * b + 2]});
  const auto all = meshio::all_gather(comm, mine);
  for (std::size_t i = 0; i < all.size() / 4; ++i)
    _pairs.push_back({int(all[4 * i]), {all[4 * i + 1], all[4 * i + 2], all[4 * i + 3]}});
  std::sort(_pairs.begin(), _pairs.end(), [](const Pair& a, const Pair& b)
            { return std::tie(a.cavity, a.place) < std::tie(b.cavity, b.place); });
  std::map<std::pair<int, Place>, std::size_t> at;
  for (std::size_t k = 0; k < _pairs.size(); ++k)
    at[{_pairs[k].cavity, _pairs[k].place}] = k;
  for (std::size_t c = 0; c < boundaries.walls.size(); ++c)
    for (auto b : fem::locate_dofs_topological(Q, fdim, facets_of(humor, boundaries.walls[c])))
      _humor_dofs.push_back({b, at.at({int(c), {XQ[3 * b], XQ[3 * b + 1], XQ[3 * b + 2]}})});

  // The solid's P1 wall dofs, each with its geometry node and its pair.
  auto& S = *_p_wall[0]->function_space();
  const auto& solid_mesh = *S.mesh();
  const int tdim = solid_mesh.topology().dim();
  const auto XS = vertex_places(S);
  std::vector<std::int32_t> node_of(XS.size() / 3, -1);
  const std::int32_t cells = solid_mesh.topology().index_map(tdim)->size_local()
                             + solid_mesh.topology().index_map(tdim)->num_ghosts();
  for (std::int32_t cell = 0; cell < cells; ++cell)
  {
    auto nodes = solid_mesh.geometry().dofmap().links(cell);
    auto dofs = S.dofmap()->cell_dofs(cell);
    for (std::size_t i = 0; i < dofs.size(); ++i)
      node_of[dofs[i]] = nodes[i];
  }
  std::vector<double> found(_pairs.size(), 0.0);
  std::string missing;
  for (std::size_t c = 0; c < boundaries.walls.size(); ++c)
  {
    // The solid's facets of the wall: its load tags are the forms' (forms/tags.py).
    std::vector<std::int32_t> facets;
    for (auto f : _solid.load_tags().find(c == 0 ? forms::tags::cavity_1_wall
                                                 : forms::tags::cavity_2_wall))
      facets.push_back(f);
    for (auto b : fem::locate_dofs_topological(S, tdim - 1, facets))
    {
      const Place x{XS[3 * b], XS[3 * b + 1], XS[3 * b + 2]};
      auto it = at.find({int(c), x});
      if (it == at.end())
      {
        missing = where(x);
        continue;
      }
      _solid_dofs[c].push_back({b, node_of[b], it->second});
      if (b < _scalar_owned)
        found[it->second] = 1;
    }
  }
  sum(comm, found);
  for (std::size_t k = 0; k < _pairs.size() && missing.empty(); ++k)
    if (found[k] != 1)
      missing = "humor " + where(_pairs[k].place);
  if (missing = meshio::broadcast(comm, missing); !missing.empty())
    throw std::runtime_error("humor_flow: the humor mesh does not conform to the cavity's wall: "
                             "no partner for the wall node "
                             + missing);

  // The humor mesh displacement's wall nodes.
  auto& D = *_motion->d->function_space();
  const auto XD = vertex_places(D);
  std::map<Place, std::size_t> by_place;
  for (std::size_t k = 0; k < _pairs.size(); ++k)
    by_place[_pairs[k].place] = k;
  for (std::int32_t b = 0; b < D.dofmap()->index_map->size_local(); ++b)
    if (auto it = by_place.find({XD[3 * b], XD[3 * b + 1], XD[3 * b + 2]}); it != by_place.end())
      _mesh_dofs.push_back({b, it->second});
  if (_lid_tags)
    for (auto b : fem::locate_dofs_topological(D, fdim, _lid_tags->indices()))
      if (b < D.dofmap()->index_map->size_local())
        _lid_mesh_dofs.push_back(b);
}

void Flow::make_forms()
{
  const Kernels k = kernels(degree_of(*_solid.u->function_space()), _solid.dimension());
  auto V = _solid.u->function_space();
  auto S = _p_wall[0]->function_space();
  auto Q = p->function_space();
  _compliance = std::make_shared<fem::Constant<double>>(0.0);
  std::map<std::string, std::shared_ptr<const fem::Constant<double>>> constants
      = {{"compliance", _compliance}};
  for (const char* name : {"dt", "alpha_m", "beta"})
    constants[name] = _solid.time_constant(name);
  const std::map<std::string, std::shared_ptr<const fem::Function<double>>> coefficients
      = {{"u", _solid.u},           {"u_old", _solid.u_old}, {"v_old", _solid.v_old},
         {"a_old", _solid.a_old},   {"p_1", _p_wall[0]},     {"p_2", _p_wall[1]},
         {"p", p}};
  const std::map<fem::IntegralType, const mesh::MeshTags<int>*> walls
      = {{fem::IntegralType::exterior_facet, &_solid.load_tags()}};
  // A form takes only the coefficients and constants it names; a
  // functional (no spaces) is on the solid's mesh.
  auto make = [&](const ufcx_form* form, std::vector<std::shared_ptr<const fem::FunctionSpace>> spaces,
                  const std::map<fem::IntegralType, const mesh::MeshTags<int>*>& subdomains)
  {
    std::map<std::string, std::shared_ptr<const fem::Function<double>>> w;
    for (int i = 0; i < form->num_coefficients; ++i)
      w[form->coefficient_name_map()[i]] = coefficients.at(form->coefficient_name_map()[i]);
    std::map<std::string, std::shared_ptr<const fem::Constant<double>>> c;
    for (int i = 0; i < form->num_constants; ++i)
      c[form->constant_name_map()[i]] = constants.at(form->constant_name_map()[i]);
    return std::make_shared<fem::Form<double>>(fem::create_form<double>(
        *form, spaces, w, c, subdomains, spaces.empty() ? V->mesh() : nullptr));
  };
  _load = make(k.load, {V}, walls);
  _load_u = make(k.load_u, {V, V}, walls);
  _load_p = {make(k.load_p_1, {V, S}, walls), make(k.load_p_2, {V, S}, walls)};
  _flux = {make(k.flux_1, {S}, walls), make(k.flux_2, {S}, walls)};
  _flux_u = {make(k.flux_1_u, {S, V}, walls), make(k.flux_2_u, {S, V}, walls)};
  _laplace = make(k.laplace, {Q}, {});
  _laplace_p = make(k.laplace_p, {Q, Q}, {});
  if (_lid_tags)
  {
    _cut_normal = make(k.cut_normal, {V}, walls);
    _lid_area = make(k.lid_area, {Q}, {{fem::IntegralType::exterior_facet, _lid_tags.get()}});
    _cut_area = make(k.cut_area, {}, walls);
    _cut_flux = make(k.cut_flux, {}, walls);
    _cut_motion = make(k.cut_motion, {}, walls);
  }
}

double Flow::total(const fem::Form<double>& form) const
{
  double v = fem::assemble_scalar(form);
  MPI_Allreduce(MPI_IN_PLACE, &v, 1, MPI_DOUBLE, MPI_SUM, _humor_mesh->comm());
  return v;
}

void Flow::measure_cut()
{
  _cut_area_value = total(*_cut_area);
  auto& n = *_b_wall;
  std::fill(n.mutable_array().begin(), n.mutable_array().end(), 0.0);
  fem::assemble_vector(n.mutable_array(), *_cut_normal);
  n.scatter_rev(std::plus<double>());
  const int bs = _b_solid->bs();
  _n_block.assign(n.array().begin(), n.array().begin() + _solid_owned);
  // n dotted with the unit fields e_k: the cut's integral of N_k.
  _cut_normal_mean = {0, 0, 0};
  for (std::int32_t i = 0; i < _solid_owned; ++i)
    _cut_normal_mean[i % bs] += _n_block[i];
  MPI_Allreduce(MPI_IN_PLACE, _cut_normal_mean.data(), 3, MPI_DOUBLE, MPI_SUM,
                _humor_mesh->comm());
  for (double& x : _cut_normal_mean)
    x /= _cut_area_value;
}

void Flow::measure_lid()
{
  auto& L = *_b_humor;
  std::fill(L.mutable_array().begin(), L.mutable_array().end(), 0.0);
  fem::assemble_vector(L.mutable_array(), *_lid_area);
  L.scatter_rev(std::plus<double>());
  _L_block.assign(L.array().begin(), L.array().begin() + _humor_owned);
}

void Flow::set_compliance()
{
  const double dt = _solid.time_constant("dt")->value[0],
               alpha_m = _solid.time_constant("alpha_m")->value[0],
               beta = _solid.time_constant("beta")->value[0];
  const double c = (1 - alpha_m) / (beta * dt * dt);
  _compliance->value = {1.0 / (_density * c)};
}

void Flow::set_wall_pressures()
{
  std::vector<double> values(_pairs.size(), 0.0);
  const auto x = p->x()->array();
  for (auto [b, k] : _humor_dofs)
    if (b < _humor_owned)
      values[k] = x[b];
  sum(_humor_mesh->comm(), values);
  for (std::size_t c = 0; c < 2; ++c)
  {
    auto w = _p_wall[c]->x()->mutable_array();
    for (auto& d : _solid_dofs[c])
      w[d.dof] = values[d.k];
  }
}

solver::Monolithic::Field Flow::field() const { return {"humor_flow", p, _active}; }

Flow::Placement Flow::place(const solver::Monolithic& U, std::size_t solid, std::size_t humor) const
{
  const int gdim = _humor_mesh->geometry().dim();
  Placement at{&U, solid, humor, {U.global(solid), U.global(solid), {}, gdim, gdim},
               {U.global(humor), U.global(humor), {}, 1, 1}, {}, {}};
  for (std::size_t i = 0; i < _solid_held.size(); ++i)
    if (_solid_held[i])
      at.solid_block.rows[i] = at.solid_block.cols[i] = -1;
  // Each wall node's p~ in this system.
  std::vector<double> rows(_pairs.size(), 0.0);
  for (auto [b, k] : _humor_dofs)
    if (b < _humor_owned)
      rows[k] = double(U.global(humor)[b]);
  sum(_humor_mesh->comm(), rows);
  const std::size_t scalars = _b_scalar->map()->size_local() + _b_scalar->map()->num_ghosts();
  for (std::size_t c = 0; c < 2; ++c)
  {
    std::vector<std::int64_t> row(scalars, -1);
    for (auto& d : _solid_dofs[c])
      row[d.dof] = std::int64_t(rows[d.k]);
    at.load_p[c] = {at.solid_block.rows, row, {}, gdim, 1};
    at.flux_u[c] = {row, at.solid_block.cols, {}, 1, gdim};
  }
  return at;
}

void Flow::add_residual(std::span<double> bs, std::span<double> bh)
{
  io::Laps lap(_timings);
  set_loads();
  // The wall's load, on the solid's free rows.
  auto& load = *_b_scalar; // reused below for the flux
  auto& wall = *_b_wall;
  std::fill(wall.mutable_array().begin(), wall.mutable_array().end(), 0.0);
  fem::assemble_vector(wall.mutable_array(), *_load);
  wall.scatter_rev(std::plus<double>());
  for (std::int32_t i = 0; i < _solid_owned; ++i)
    if (!_solid_held[i])
      bs[i] += wall.array()[i];
  // The humor's rows: its Laplacian, and the wall's flux moved onto them.
  std::fill(_b_humor->mutable_array().begin(), _b_humor->mutable_array().end(), 0.0);
  fem::assemble_vector(_b_humor->mutable_array(), *_laplace);
  _b_humor->scatter_rev(std::plus<double>());
  std::copy_n(_b_humor->array().begin(), _humor_owned, bh.begin());
  lap("humor");
  std::vector<double> flux(_pairs.size(), 0.0);
  for (std::size_t c = 0; c < 2; ++c)
  {
    std::fill(load.mutable_array().begin(), load.mutable_array().end(), 0.0);
    fem::assemble_vector(load.mutable_array(), *_flux[c]);
    load.scatter_rev(std::plus<double>());
    for (auto& d : _solid_dofs[c])
      if (d.dof < _scalar_owned)
        flux[d.k] += load.array()[d.dof];
  }
  sum(_humor_mesh->comm(), flux);
  for (auto [d, k] : _humor_dofs)
    if (d < _humor_owned)
      bh[d] += flux[k];
  if (_lid_tags && _cut_area_value > 0)
  {
    // The lid: R_lid = -L(p~) / A_cut n, G_lid = W L.
    double Lp = 0;
    const auto x = p->x()->array();
    for (std::int32_t b = 0; b < _humor_owned; ++b)
      Lp += _L_block[b] * x[b];
    MPI_Allreduce(MPI_IN_PLACE, &Lp, 1, MPI_DOUBLE, MPI_SUM, _humor_mesh->comm());
    for (std::int32_t i = 0; i < _solid_owned; ++i)
      if (!_solid_held[i])
        bs[i] -= Lp / _cut_area_value * _n_block[i];
    const double W = -total(*_cut_flux) / _cut_area_value;
    for (std::int32_t b = 0; b < _humor_owned; ++b)
      bh[b] += W * _L_block[b];
  }
  // Held p~: no rows (their entries are left out of the system).
  lap("wall");
}

void Flow::add_jacobian(const Placement& at, Mat A)
{
  io::Laps lap(_timings);
  set_loads();
  fem::assemble_matrix(solver::add_block(A, at.humor_block), *_laplace_p, {});
  lap("humor");
  fem::assemble_matrix(solver::add_block(A, at.solid_block), *_load_u, {});
  for (std::size_t c = 0; c < 2; ++c)
  {
    fem::assemble_matrix(solver::add_block(A, at.load_p[c]), *_load_p[c], {});
    fem::assemble_matrix(solver::add_block(A, at.flux_u[c]), *_flux_u[c], {});
  }
  if (_lid_tags && _cut_area_value > 0)
  {
    // The lid's rank-one blocks -n (x) L / A_cut and its transpose, each
    // rank its own rows.
    const auto& U = *at.U;
    std::vector<double> n_mine, L_mine;
    for (std::int32_t i = 0; i < _solid_owned; ++i)
      if (!_solid_held[i] && _n_block[i] != 0)
        n_mine.insert(n_mine.end(), {double(U.global(at.solid)[i]), _n_block[i]});
    for (std::int32_t b = 0; b < _humor_owned; ++b)
      if (_L_block[b] != 0 && U.global(at.humor)[b] >= 0)
        L_mine.insert(L_mine.end(), {double(U.global(at.humor)[b]), _L_block[b]});
    const auto n_all = meshio::all_gather(_humor_mesh->comm(), n_mine),
               L_all = meshio::all_gather(_humor_mesh->comm(), L_mine);
    auto add = [&](const std::vector<double>& rows, const std::vector<double>& cols)
    {
      std::vector<PetscInt> c;
      std::vector<PetscScalar> v(cols.size() / 2);
      for (std::size_t j = 0; j < cols.size(); j += 2)
        c.push_back(static_cast<PetscInt>(cols[j]));
      for (std::size_t i = 0; i < rows.size(); i += 2)
      {
        const PetscInt r = static_cast<PetscInt>(rows[i]);
        for (std::size_t j = 0; j < c.size(); ++j)
          v[j] = -rows[i + 1] * cols[2 * j + 1] / _cut_area_value;
        MatSetValues(A, 1, &r, static_cast<PetscInt>(c.size()), c.data(), v.data(), ADD_VALUES);
      }
    };
    add(n_mine, L_all);
    add(L_mine, n_all);
  }
  lap("wall");
}

void Flow::residual(la::Vector<double>& b)
{
  const double t = MPI_Wtime();
  _solid.residual(*_b_solid);
  _timings["solid"] += MPI_Wtime() - t;
  std::vector<double> bh(_humor_owned);
  add_residual(_b_solid->mutable_array(), bh);
  std::fill(b.mutable_array().begin(), b.mutable_array().end(), 0.0);
  _own_unknowns->insert(0, _b_solid->array().subspan(0, _solid_owned), b);
  _own_unknowns->insert(1, bh, b);
}

void Flow::own_jacobian(Mat A)
{
  const double t = MPI_Wtime();
  for (const auto* J : _solid.jacobian_forms())
    fem::assemble_matrix(solver::add_block(A, _own.solid_block), *J, {});
  const auto& U = *_own_unknowns;
  for (std::int32_t i = 0; i < U.owned(0); ++i)
    if (_solid_held[i] && U.global(0)[i] >= 0)
      MatSetValue(A, U.global(0)[i], U.global(0)[i], 1.0, ADD_VALUES);
  _timings["solid"] += MPI_Wtime() - t;
  add_jacobian(_own, A);
}

Mat Flow::create_matrix()
{
  return _own_unknowns->create_matrix([this](Mat P) { own_jacobian(P); });
}

solver::System Flow::system(cavity::Closed* closed, cavity::Open&)
{
  solver::System s = solver::bordered(
      *_own_unknowns, closed, *_b_solid, [this](la::Vector<double>& b) { residual(b); },
      [this](Mat A) { own_jacobian(A); });
  s.inadmissible = [this]
  {
    const auto w = _solid.smallest_jacobian();
    if (w.value > 0)
      return inadmissible();
    return (w.value == -std::numeric_limits<double>::infinity()
                ? std::string("det F is NaN ")
                : format("an element inverted: det F = %.3g ", w.value))
           + format("at X = (%.3f, %.3f, %.3f) mm", w.x[0], w.x[1], w.x[2])
           + (w.part.empty() ? std::string() : " in the " + w.part);
  };
  s.locate = [this](const la::Vector<double>& b)
  {
    std::vector<double> block(_own_unknowns->owned(0));
    _own_unknowns->extract(0, b, block);
    std::copy(block.begin(), block.end(), _b_solid->mutable_array().begin());
    const auto w = _solid.largest_residual(*_b_solid);
    std::vector<double> humor(_own_unknowns->owned(1));
    _own_unknowns->extract(1, b, humor);
    double m = 0;
    for (double v : humor)
      m = std::max(m, std::isfinite(v) ? std::abs(v) : std::numeric_limits<double>::infinity());
    MPI_Allreduce(MPI_IN_PLACE, &m, 1, MPI_DOUBLE, MPI_MAX, _humor_mesh->comm());
    return format("(%.3e N) at X = (%.3f, %.3f, %.3f) mm", w.value, w.x[0], w.x[1], w.x[2])
           + (w.part.empty() ? std::string() : " in the " + w.part)
           + format("; the humor's rows' largest %.3e mm^3", m);
  };
  return s;
}

void Flow::follow_wall()
{
  extend_to_wall();
  move_humor_mesh();
  if (_lid_tags)
    measure_lid();
}

void Flow::extend_to_wall()
{
  const double t = MPI_Wtime();
  // The solid's wall nodes where they are now.
  const auto u = _solid.nodal_displacement();
  const auto& xs = _solid.u->function_space()->mesh()->geometry().x();
  std::vector<double> now(3 * _pairs.size(), 0.0);
  for (std::size_t c = 0; c < 2; ++c)
    for (auto& d : _solid_dofs[c])
      if (d.dof < _scalar_owned)
        for (int j = 0; j < 3; ++j)
          now[3 * d.k + j] = xs[3 * d.node + j] + u[3 * d.node + j];
  sum(_humor_mesh->comm(), now);
  // Their displacement from the humor mesh as built, extended into it
  // (on the mesh as built: the extension's operator is its).
  std::span<double> x = _humor_mesh->geometry().x();
  std::copy(_x_built.begin(), _x_built.end(), x.begin());
  std::vector<std::pair<std::int32_t, std::array<double, 3>>> g;
  if (_lid_tags && _cut_area_value > 0)
  {
    // The lid moves with the cut face's mean normal displacement.
    const double m = total(*_cut_motion) / _cut_area_value;
    for (auto b : _lid_mesh_dofs)
      g.push_back({b, {m * _cut_normal_mean[0], m * _cut_normal_mean[1],
                       m * _cut_normal_mean[2]}});
  }
  for (auto [b, k] : _mesh_dofs)
    g.push_back({b, {now[3 * k] - _pairs[k].place[0], now[3 * k + 1] - _pairs[k].place[1],
                     now[3 * k + 2] - _pairs[k].place[2]}});
  _motion->extend(g);
  _timings["mesh_motion"] += MPI_Wtime() - t;
}

void Flow::move_humor_mesh()
{
  // x = X + d at the mesh's nodes (P1: the geometry's nodes are d's).
  auto& D = *_motion->d->function_space();
  std::span<double> x = _humor_mesh->geometry().x();
  const auto& mesh = *_humor_mesh;
  const int tdim = mesh.topology().dim(), bs = D.dofmap()->index_map_bs();
  const std::int32_t cells = mesh.topology().index_map(tdim)->size_local()
                             + mesh.topology().index_map(tdim)->num_ghosts();
  const auto d = _motion->d->x()->array();
  for (std::int32_t c = 0; c < cells; ++c)
  {
    auto nodes = mesh.geometry().dofmap().links(c);
    auto dofs = D.dofmap()->cell_dofs(c);
    for (std::size_t i = 0; i < nodes.size(); ++i)
      for (int j = 0; j < bs; ++j)
        x[3 * nodes[i] + j] = _x_built[3 * nodes[i] + j] + d[bs * dofs[i] + j];
  }
}

std::string Flow::inadmissible()
{
  // The humor's mesh as it would follow the wall now, its geometry kept.
  std::span<double> x = _humor_mesh->geometry().x();
  const std::vector<double> kept(x.begin(), x.end());
  extend_to_wall();
  move_humor_mesh();
  const auto [ratio, at] = smallest_cell_ratio();
  std::copy(kept.begin(), kept.end(), x.begin());
  if (ratio > 0)
    return "";
  return format("the humor's mesh would fold: a cell %s would keep %.3g of its volume as "
                "built (the wall moved further into the humor than the mesh motion's extension "
                "can follow)",
                where(at).c_str(), ratio);
}

void Flow::start()
{
  if (_lid_tags)
    measure_cut();
  follow_wall();
  std::fill(p->x()->mutable_array().begin(), p->x()->mutable_array().end(), 0.0);
  _own_unknowns->pack();
  std::fill(_w.begin(), _w.end(), 0.0);
  _range_max = _bernoulli_max = 0;
}

void Flow::measure_linearisation()
{
  // grad p~ per cell of the step's geometry (P1 on affine cells: the
  // vertices' values), then w -= dt grad p~ / rho.
  const auto& mesh = *_humor_mesh;
  const int tdim = mesh.topology().dim();
  const std::int32_t cells = mesh.topology().index_map(tdim)->size_local();
  const auto values = p->x()->array();
  const double dt = _solid.time_constant("dt")->value[0];
  _w.resize(3 * cells, 0.0);
  double bernoulli = 0, lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (std::int32_t b = 0; b < _humor_owned; ++b)
    lo = std::min(lo, values[b]), hi = std::max(hi, values[b]);
  for (std::int32_t c = 0; c < cells; ++c)
  {
    auto dofs = p->function_space()->dofmap()->cell_dofs(c);
    // The edges' rows (a triangle's third is e_z, gradient 0) times grad p~
    // are the value differences along them: Cramer's rule.
    const auto e = meshio::cell_edges(mesh, c);
    std::array<double, 3> dp{0, 0, 0};
    for (int i = 0; i < tdim; ++i)
      dp[i] = values[dofs[i + 1]] - values[dofs[0]];
    const double d = meshio::determinant(e);
    double speed2 = 0;
    for (int k = 0; k < 3; ++k)
    {
      auto ek = e;
      for (int i = 0; i < 3; ++i)
        ek[i][k] = dp[i];
      _w[3 * c + k] -= dt * meshio::determinant(ek) / d / _density;
      speed2 += _w[3 * c + k] * _w[3 * c + k];
    }
    bernoulli = std::max(bernoulli, 0.5 * _density * speed2);
  }
  MPI_Comm comm = _humor_mesh->comm();
  MPI_Allreduce(MPI_IN_PLACE, &bernoulli, 1, MPI_DOUBLE, MPI_MAX, comm);
  MPI_Allreduce(MPI_IN_PLACE, &lo, 1, MPI_DOUBLE, MPI_MIN, comm);
  MPI_Allreduce(MPI_IN_PLACE, &hi, 1, MPI_DOUBLE, MPI_MAX, comm);
  _bernoulli_max = std::max(_bernoulli_max, bernoulli);
  _range_max = std::max(_range_max, hi - lo);
}

double Flow::kinetic_energy() const
{
  const auto v = cell_volumes(*_humor_mesh);
  const auto& mesh = *_humor_mesh;
  const auto x = mesh.geometry().x();
  const bool axisymmetric = _solid.dimension() == section::Dimension::axisymmetric;
  double e = 0;
  for (std::size_t c = 0; c < v.size() && 3 * c + 2 < _w.size(); ++c)
  {
    // A section's cell: its area times its centroid's radius (per radian).
    double volume = std::abs(v[c]) / (mesh.topology().dim() == 2 ? 2.0 : 6.0);
    if (axisymmetric)
    {
      double r = 0;
      auto nodes = mesh.geometry().dofmap().links(c);
      for (auto n : nodes)
        r += x[3 * n] / double(nodes.size());
      volume *= r;
    }
    e += 0.5 * _density * volume
         * (_w[3 * c] * _w[3 * c] + _w[3 * c + 1] * _w[3 * c + 1] + _w[3 * c + 2] * _w[3 * c + 2]);
  }
  MPI_Allreduce(MPI_IN_PLACE, &e, 1, MPI_DOUBLE, MPI_SUM, _humor_mesh->comm());
  return e;
}

void Flow::advance()
{
  _own_unknowns->unpack();
  _solid.advance();
  follow();
}

void Flow::predict()
{
  _own_unknowns->unpack();
  _solid.predict();
  _own_unknowns->pack();
}

void Flow::describe(nlohmann::json& summary, io::RunFolder& folder) const
{
  describe_mesh(summary, folder, *_humor_mesh, dofs(), "pressure", wall_nodes(), name());
}

void Flow::summarise(nlohmann::json& summary) const
{
  constexpr double mmHg = 1.333224e-4; // MPa
  biomarkers::put(summary, "humor_pressure_range_max_mmHg", _range_max / mmHg);
  biomarkers::put(summary, "humor_bernoulli_max_mmHg", _bernoulli_max / mmHg);
}

void Flow::follow()
{
  measure_linearisation();
  follow_wall();
  // The Newton solve's inadmissible() keeps a folding step from converging.
  const auto [ratio, x] = smallest_cell_ratio();
  if (!(ratio > 0))
    throw std::runtime_error(format("humor_flow: a humor cell folded (volume %.3g of its own "
                                    "as built) ",
                                    ratio)
                             + where(x) + ": the wall moved further into the humor than its "
                                          "mesh's extension can follow");
}

std::pair<double, std::array<double, 3>> Flow::smallest_cell_ratio() const
{
  const auto v = cell_volumes(*_humor_mesh);
  const auto& x = _humor_mesh->geometry().x();
  struct
  {
    double value;
    int rank;
  } best{std::numeric_limits<double>::infinity(), 0};
  MPI_Comm_rank(_humor_mesh->comm(), &best.rank);
  std::int32_t cell = -1;
  for (std::size_t c = 0; c < v.size(); ++c)
    if (const double r = v[c] / _cell_volume_built[c]; !(r >= best.value))
      best.value = std::isnan(r) ? -std::numeric_limits<double>::infinity() : r,
      cell = static_cast<std::int32_t>(c);
  const int rank = best.rank;
  MPI_Allreduce(MPI_IN_PLACE, &best, 1, MPI_DOUBLE_INT, MPI_MINLOC, _humor_mesh->comm());
  std::array<double, 3> at{0, 0, 0};
  if (best.rank == rank && cell >= 0)
  {
    auto nodes = _humor_mesh->geometry().dofmap().links(cell);
    for (auto n : nodes)
      for (int j = 0; j < 3; ++j)
        at[j] += x[3 * n + j] / double(nodes.size());
  }
  MPI_Bcast(at.data(), 3, MPI_DOUBLE, best.rank, _humor_mesh->comm());
  return {best.value, at};
}

void Flow::write(io::MovingFields& files, double time)
{
  // The files take the mesh as built and its displacement.
  std::span<double> x = _humor_mesh->geometry().x();
  const std::vector<double> now(x.begin(), x.end());
  std::copy(_x_built.begin(), _x_built.end(), x.begin());
  p->x()->scatter_fwd();
  files.write(*p, *_motion->d, time);
  std::copy(now.begin(), now.end(), x.begin());
}

std::int64_t Flow::dofs() const { return _own_unknowns->size_global(1); }

} // namespace nct::humor
