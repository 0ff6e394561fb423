#include "fsi/coupled.h"

#include <algorithm>
#include <cmath>
#include <limits>
#include <map>
#include <numeric>
#include <set>
#include <stdexcept>
#include <unordered_map>

#include <dolfinx/fem/assembler.h>

#include "io/format.h"
#include "io/laps.h"
#include "solver/bordered.h"

namespace nct::fsi
{
namespace
{
using namespace dolfinx;
using io::format;
using Place = std::array<double, 3>;

void sum(MPI_Comm comm, std::vector<double>& v)
{
  MPI_Allreduce(MPI_IN_PLACE, v.data(), static_cast<int>(v.size()), MPI_DOUBLE, MPI_SUM, comm);
}

/// The local vertices of the facets in `groups`.
std::vector<std::int32_t> group_vertices(const meshio::Tagged& m,
                                         const std::vector<std::int32_t>& groups)
{
  const int fdim = m.mesh->topology().dim() - 1;
  m.mesh->topology_mutable().create_connectivity(fdim, 0);
  const auto f2v = m.mesh->topology().connectivity(fdim, 0);
  std::set<std::int32_t> vertices;
  for (auto g : groups)
    for (auto f : m.facets->find(g))
      for (auto v : f2v->links(f))
        vertices.insert(v);
  return {vertices.begin(), vertices.end()};
}

/// Per vertex: the block dof of `V` at it, and its place.
std::pair<std::vector<std::int32_t>, std::vector<Place>>
vertex_dofs(const fem::FunctionSpace& V, const std::vector<std::int32_t>& vertices)
{
  auto& mesh = *V.mesh();
  const int tdim = mesh.topology().dim();
  mesh.topology_mutable().create_connectivity(0, tdim);
  mesh.topology_mutable().create_connectivity(tdim, 0);
  const auto v2c = mesh.topology().connectivity(0, tdim);
  const auto c2v = mesh.topology().connectivity(tdim, 0);
  const auto& layout = V.dofmap()->element_dof_layout();
  const auto& x = mesh.geometry().x();
  std::pair<std::vector<std::int32_t>, std::vector<Place>> out;
  for (auto v : vertices)
  {
    const std::int32_t c = v2c->links(v)[0];
    auto cv = c2v->links(c);
    const int i = static_cast<int>(std::find(cv.begin(), cv.end(), v) - cv.begin());
    out.first.push_back(V.dofmap()->cell_dofs(c)[layout.entity_dofs(0, i)[0]]);
    const auto node = mesh.geometry().dofmap().links(c)[i];
    out.second.push_back({x[3 * node], x[3 * node + 1], x[3 * node + 2]});
  }
  return out;
}

std::string where(const Place& x)
{
  return format("at X = (%.3f, %.3f, %.3f) mm", x[0], x[1], x[2]);
}

} // namespace

Coupled::Coupled(solid::Problem& solid, air::Problem& air, mesh_motion::Problem& motion,
                 const meshio::Tagged& solid_mesh, const meshio::Tagged& air_mesh,
                 const Interface& interface, bool shape_derivative, Joined* joined,
                 const std::string& fluid)
    : _solid(solid), _air(air), _motion(motion), _joined(joined), _air_mesh(air_mesh.mesh),
      _shape_derivative(shape_derivative), _gdim(solid_mesh.mesh->geometry().dim())
{
  if (!air.moving() || air.d != motion.d)
    throw std::invalid_argument("fsi::Coupled: the air must move with the mesh motion's d");
  std::vector<solver::Monolithic::Field> fields{{"solid", solid.u, std::nullopt},
                                                {fluid, air.up, std::nullopt},
                                                {"mesh_motion", motion.d, motion.active()}};
  if (joined)
    fields.push_back(joined->field());
  _unknowns = std::make_unique<solver::Monolithic>(solid_mesh.mesh->comm(), fields);
  _solid_held = solid.dynamic_dirichlet_marker(); // the coupled system runs in the dynamics
  _air_held = air.dirichlet_marker();
  _b_solid = std::make_unique<la::Vector<double>>(solid.u->x()->map(), solid.u->x()->bs());
  _b_air = std::make_unique<la::Vector<double>>(air.up->x()->map(), air.up->x()->bs());
  _b_mesh = std::make_unique<la::Vector<double>>(motion.d->x()->map(), motion.d->x()->bs());
  pair(solid_mesh, air_mesh, interface);
  const std::size_t n = 3 * _nodes.size();
  _u0.assign(n, 0.0);
  _lambda.assign(n, 0.0);
  _lambda_n.assign(n, 0.0);

  // Rows and columns of each block in the stacked system: held rows and
  // columns out (their diagonal is set apart), the air's coupled momentum
  // rows onto the solid's, the mesh's interface rows replaced.
  const auto& U = *_unknowns;
  _solid_block = {U.global(0), U.global(0), {}, _gdim, _gdim};
  for (std::size_t i = 0; i < _solid_held.size(); ++i)
    if (_solid_held[i])
      _solid_block.rows[i] = _solid_block.cols[i] = -1;
  std::unordered_map<std::int64_t, std::int64_t> air_to_solid;
  for (const auto& node : _nodes)
    for (int k = 0; k < 3; ++k)
      if (node.air[k] >= 0)
        air_to_solid[node.air[k]] = node.solid[k];
  _air_block = {U.global(1), U.global(1), std::vector<double>(U.global(1).size(), 1.0), 1, 1};
  for (std::size_t i = 0; i < _air_held.size(); ++i)
  {
    if (_air_held[i])
      _air_block.rows[i] = _air_block.cols[i] = -1;
    else if (auto it = air_to_solid.find(_air_block.rows[i]); it != air_to_solid.end())
    {
      _air_block.rows[i] = it->second;
      _moved_rows.push_back(i); // scaled by 1 - alpha_f (set_time_step)
    }
  }
  _mesh_block = {U.global(2), U.global(2), {}, _gdim, _gdim};
  for (std::size_t i = 0; i < _motion.fixed().size(); ++i)
  {
    if (_motion.fixed()[i])
      _mesh_block.cols[i] = -1;
    if (_motion.fixed()[i] || _motion.interface()[i])
      _mesh_block.rows[i] = -1;
  }
  _air_mesh_block = {_air_block.rows, _mesh_block.cols, _air_block.row_factor, 1, _gdim};
  if (joined)
    joined->place(U, 0, 3);
}

void Coupled::pair(const meshio::Tagged& solid_mesh, const meshio::Tagged& air_mesh,
                   const Interface& interface)
{
  MPI_Comm comm = solid_mesh.mesh->comm();
  const auto& U = *_unknowns;
  // Owned interface nodes of each side: place, and 3 global indices (-1
  // for a section's third component).
  const int g = _gdim;
  std::vector<double> solid_places, air_places, mesh_places;
  std::vector<std::int64_t> solid_globals, air_globals, mesh_globals;
  std::map<Place, std::int32_t> solid_local, mesh_local;
  std::map<Place, std::array<std::int32_t, 3>> air_local;

  const auto [solid_dofs, solid_at] = vertex_dofs(*_solid.u->function_space(),
                                                  group_vertices(solid_mesh, interface.solid));
  const std::int32_t solid_owned = _solid.u->function_space()->dofmap()->index_map->size_local();
  for (std::size_t i = 0; i < solid_dofs.size(); ++i)
  {
    const std::int32_t b = solid_dofs[i];
    if (b >= solid_owned)
      continue;
    solid_places.insert(solid_places.end(), solid_at[i].begin(), solid_at[i].end());
    for (int k = 0; k < 3; ++k)
      solid_globals.push_back(k >= g || _solid_held[g * b + k] ? -1 : U.global(0)[g * b + k]);
    solid_local[solid_at[i]] = b;
  }

  const auto air_vertices = group_vertices(air_mesh, interface.air);
  const auto [velocity_dofs, air_at] = vertex_dofs(*_air.velocity->function_space(), air_vertices);
  const std::int32_t velocity_owned
      = _air.velocity->function_space()->dofmap()->index_map->size_local();
  for (std::size_t i = 0; i < velocity_dofs.size(); ++i)
  {
    const std::int32_t b = velocity_dofs[i];
    if (b >= velocity_owned)
      continue;
    air_places.insert(air_places.end(), air_at[i].begin(), air_at[i].end());
    std::array<std::int32_t, 3> dofs{-1, -1, -1};
    for (int k = 0; k < 3; ++k)
    {
      if (k < g)
        dofs[k] = _air.velocity_dofs()[g * b + k];
      air_globals.push_back(k >= g || _air_held[dofs[k]] ? -1 : U.global(1)[dofs[k]]);
    }
    air_local[air_at[i]] = dofs;
  }
  const auto [mesh_dofs, mesh_at] = vertex_dofs(*_motion.d->function_space(), air_vertices);
  const std::int32_t mesh_owned = _motion.d->function_space()->dofmap()->index_map->size_local();
  for (std::size_t i = 0; i < mesh_dofs.size(); ++i)
  {
    const std::int32_t b = mesh_dofs[i];
    if (b >= mesh_owned)
      continue;
    mesh_places.insert(mesh_places.end(), mesh_at[i].begin(), mesh_at[i].end());
    for (int k = 0; k < 3; ++k)
      mesh_globals.push_back(k >= g || _motion.fixed()[g * b + k] ? -1 : U.global(2)[g * b + k]);
    mesh_local[mesh_at[i]] = b;
  }

  // Every rank: match the air's nodes to the solid's and the mesh's by place.
  auto index = [](const std::vector<double>& places)
  {
    std::map<Place, std::size_t> at;
    for (std::size_t i = 0; i < places.size() / 3; ++i)
      at[{places[3 * i], places[3 * i + 1], places[3 * i + 2]}] = i;
    return at;
  };
  using meshio::all_gather;
  const auto all_air = all_gather(comm, air_places), all_solid = all_gather(comm, solid_places),
             all_mesh = all_gather(comm, mesh_places);
  const auto all_air_g = all_gather(comm, air_globals),
             all_solid_g = all_gather(comm, solid_globals),
             all_mesh_g = all_gather(comm, mesh_globals);
  const auto solid_at_place = index(all_solid), mesh_at_place = index(all_mesh);
  for (std::size_t i = 0; i < all_air.size() / 3; ++i)
  {
    const Place x{all_air[3 * i], all_air[3 * i + 1], all_air[3 * i + 2]};
    const auto s = solid_at_place.find(x);
    const auto m = mesh_at_place.find(x);
    if (s == solid_at_place.end() || m == mesh_at_place.end())
      throw std::runtime_error("fsi: the air's interface node " + where(x)
                               + " is not a node of the solid's interface");
    Node node;
    node.air_place = x;
    for (int k = 0; k < 3; ++k)
    {
      node.air[k] = all_air_g[3 * i + k];
      node.solid[k] = all_solid_g[3 * s->second + k];
      node.mesh[k] = all_mesh_g[3 * m->second + k];
    }
    if (auto it = solid_local.find(x); it != solid_local.end())
      node.solid_block = it->second;
    if (auto it = air_local.find(x); it != air_local.end())
      node.air_dof = it->second;
    if (auto it = mesh_local.find(x); it != mesh_local.end())
      node.mesh_block = it->second;
    _nodes.push_back(node);
  }
  if (_nodes.empty())
    throw std::runtime_error("fsi: the interface has no nodes");
  _order.resize(_nodes.size());
  std::iota(_order.begin(), _order.end(), 0);
  std::sort(_order.begin(), _order.end(),
            [&](auto i, auto j) { return _nodes[i].air_place < _nodes[j].air_place; });
}

nlohmann::json Coupled::save(io::CheckpointWriter& checkpoint) const
{
  std::vector<double> u0, lambda_n;
  for (auto n : _order)
    for (int k = 0; k < 3; ++k)
      u0.push_back(_u0[3 * n + k]), lambda_n.push_back(_lambda_n[3 * n + k]);
  return {{"air", _air.save(checkpoint)}, {"u0", u0}, {"lambda_n", lambda_n}};
}

void Coupled::restore(const io::CheckpointReader& checkpoint, const nlohmann::json& state)
{
  _air.restore(checkpoint, state.at("air"));
  const auto u0 = state.at("u0").get<std::vector<double>>(),
             lambda_n = state.at("lambda_n").get<std::vector<double>>();
  if (u0.size() != 3 * _nodes.size())
    throw io::CheckpointError("the checkpoint's interface has another number of nodes");
  for (std::size_t i = 0; i < _order.size(); ++i)
    for (int k = 0; k < 3; ++k)
      _u0[3 * _order[i] + k] = u0[3 * i + k], _lambda_n[3 * _order[i] + k] = lambda_n[3 * i + k];
  _unknowns->pack();
  _started = true;
}

void Coupled::set_time_step(const dynamics::TimeStep& step, int bdf_order)
{
  _solid.set_time_step(step);
  _air.set_time_step(step.dt, bdf_order);
  _alpha_f = 1 - _solid.load_level();
  for (auto i : _moved_rows)
    _air_block.row_factor[i] = _air_mesh_block.row_factor[i] = 1 - _alpha_f;
}

void Coupled::solid_state(std::vector<double>& u, std::vector<double>& v) const
{
  const auto c = _solid.velocity_coefficients();
  auto un = _solid.u->x()->array(), uo = _solid.u_old->x()->array(),
       vo = _solid.v_old->x()->array(), ao = _solid.a_old->x()->array();
  u.assign(3 * _nodes.size(), 0.0);
  v.assign(3 * _nodes.size(), 0.0);
  for (std::size_t n = 0; n < _nodes.size(); ++n)
    if (const std::int32_t b = _nodes[n].solid_block; b >= 0)
      for (int k = 0; k < _gdim; ++k)
      {
        const std::int32_t i = _gdim * b + k;
        u[3 * n + k] = un[i];
        v[3 * n + k] = c[0] * (un[i] - uo[i]) + c[1] * vo[i] + c[2] * ao[i];
      }
  MPI_Comm comm = _solid.u->function_space()->mesh()->comm();
  sum(comm, u);
  sum(comm, v);
}

void Coupled::residual(la::Vector<double>& b)
{
  io::Laps lap(_timings);
  _solid.residual(*_b_solid);
  lap("solid");
  std::vector<double> bh(_joined ? _unknowns->owned(3) : 0);
  if (_joined)
    _joined->add_residual(_b_solid->mutable_array(), bh);
  lap("humor_flow");
  _air.residual(*_b_air);
  lap("air");
  _motion.residual(*_b_mesh);
  lap("mesh_motion");
  std::vector<double> u, v;
  solid_state(u, v);
  auto bs = _b_solid->mutable_array(), bf = _b_air->mutable_array(), bm = _b_mesh->mutable_array();
  // The air's reaction at the coupled rows, moved onto the solid's.
  std::fill(_lambda.begin(), _lambda.end(), 0.0);
  for (std::size_t n = 0; n < _nodes.size(); ++n)
    for (int k = 0; k < 3; ++k)
      if (_nodes[n].air_dof[k] >= 0 && _nodes[n].air[k] >= 0)
        _lambda[3 * n + k] = bf[_nodes[n].air_dof[k]];
  sum(_solid.u->function_space()->mesh()->comm(), _lambda);
  const double D_f = _air.bc_diagonal(), D_m = _motion.diagonal();
  auto up = _air.up->x()->array(), d = _motion.d->x()->array();
  for (std::size_t n = 0; n < _nodes.size(); ++n)
  {
    const Node& node = _nodes[n];
    for (int k = 0; k < 3; ++k)
    {
      const std::size_t p = 3 * n + k;
      const bool solid_free = node.solid[k] >= 0;
      if (node.solid_block >= 0 && solid_free && node.air[k] >= 0)
        bs[_gdim * node.solid_block + k] += (1 - _alpha_f) * _lambda[p] + _alpha_f * _lambda_n[p];
      if (node.air_dof[k] >= 0 && node.air[k] >= 0)
        bf[node.air_dof[k]] = D_f * (up[node.air_dof[k]] - (solid_free ? v[p] : 0.0));
      if (node.mesh_block >= 0 && node.mesh[k] >= 0)
      {
        const std::int32_t i = _gdim * node.mesh_block + k;
        bm[i] = D_m * (d[i] - (solid_free ? u[p] - _u0[p] : 0.0));
      }
    }
  }
  std::fill(b.mutable_array().begin(), b.mutable_array().end(), 0.0);
  _unknowns->insert(0, bs, b);
  _unknowns->insert(1, bf, b);
  _unknowns->insert(2, bm, b);
  if (_joined)
    _unknowns->insert(3, bh, b);
  lap("interface");
}

void Coupled::add_jacobian(Mat A)
{
  const auto& U = *_unknowns;
  io::Laps lap(_timings);
  for (const auto* J : _solid.jacobian_forms())
    fem::assemble_matrix(solver::add_block(A, _solid_block), *J, {});
  lap("solid");
  fem::assemble_matrix(solver::add_block(A, _air_block), _air.jacobian_form(), {});
  lap("air");
  if (_shape_derivative)
    fem::assemble_matrix(solver::add_block(A, _air_mesh_block), _air.jacobian_mesh_form(), {});
  lap("air_shape");
  fem::assemble_matrix(solver::add_block(A, _mesh_block), _motion.jacobian_form(), {});
  lap("mesh_motion");
  if (_joined)
    _joined->add_jacobian(A);
  lap("humor_flow");
  // Held rows: the diagonal of their residual d (x - 0).
  auto diagonal = [&](std::size_t f, const std::vector<std::int8_t>& held, double value)
  {
    for (std::int32_t i = 0; i < U.owned(f); ++i)
      if (held[i] && U.global(f)[i] >= 0)
        MatSetValue(A, U.global(f)[i], U.global(f)[i], value, ADD_VALUES);
  };
  diagonal(0, _solid_held, 1.0);
  diagonal(1, _air_held, _air.bc_diagonal());
  diagonal(2, _motion.fixed(), _motion.diagonal());
  // The interface's constraint rows.
  const double D_f = _air.bc_diagonal(), D_m = _motion.diagonal();
  const double c_u = _solid.velocity_coefficients()[0];
  for (const auto& node : _nodes)
    for (int k = 0; k < 3; ++k)
    {
      if (node.air_dof[k] >= 0 && node.air[k] >= 0)
      {
        MatSetValue(A, node.air[k], node.air[k], D_f, ADD_VALUES);
        if (node.solid[k] >= 0)
          MatSetValue(A, node.air[k], node.solid[k], -D_f * c_u, ADD_VALUES);
      }
      if (node.mesh_block >= 0 && node.mesh[k] >= 0)
      {
        MatSetValue(A, node.mesh[k], node.mesh[k], D_m, ADD_VALUES);
        if (node.solid[k] >= 0)
          MatSetValue(A, node.mesh[k], node.solid[k], -D_m, ADD_VALUES);
      }
    }
  lap("interface");
}

Mat Coupled::create_matrix()
{
  return _unknowns->create_matrix([this](Mat P) { add_jacobian(P); });
}

solver::System Coupled::system(cavity::Closed* closed)
{
  solver::System s = solver::bordered(
      *_unknowns, closed, *_b_solid, [this](la::Vector<double>& b) { residual(b); },
      [this](Mat A) { add_jacobian(A); }, &_timings["matrix_communication"]);
  s.inadmissible = [this] { return inadmissible(); };
  s.locate = [this](const la::Vector<double>& b)
  {
    // The field with the largest entry; within the solid, its place.
    std::string text;
    double largest = -1;
    for (std::size_t f = 0; f < _unknowns->fields(); ++f)
    {
      std::vector<double> block(_unknowns->owned(f));
      _unknowns->extract(f, b, block);
      double m = 0;
      for (double v : block)
        m = std::max(m, std::isfinite(v) ? std::abs(v) : std::numeric_limits<double>::infinity());
      MPI_Allreduce(MPI_IN_PLACE, &m, 1, MPI_DOUBLE, MPI_MAX, _solid.u->function_space()->mesh()->comm());
      if (m > largest)
      {
        largest = m;
        text = format("(%.3e) in the %s rows", m, _unknowns->field(f).name.c_str());
        if (f == 0)
        {
          std::copy(block.begin(), block.end(), _b_solid->mutable_array().begin());
          const auto w = _solid.largest_residual(*_b_solid);
          text.append(" ").append(where(w.x));
          if (!w.part.empty())
            text.append(" in the ").append(w.part);
        }
      }
    }
    return text;
  };
  return s;
}

std::string Coupled::inadmissible() const
{
  const auto w = _solid.smallest_jacobian();
  if (!(w.value > 0))
    return (w.value == -std::numeric_limits<double>::infinity()
                ? std::string("det F is NaN ")
                : format("an element inverted: det F = %.3g ", w.value))
           + where(w.x) + (w.part.empty() ? std::string() : std::string(" in the ") + w.part);
  const auto [J, x] = _air.smallest_mesh_jacobian();
  if (!(J > 0))
    return format("an air cell folded: the mesh motion's det F = %.3g ", J) + where(x);
  return _joined ? _joined->inadmissible() : "";
}

void Coupled::start()
{
  MPI_Comm comm = _solid.u->function_space()->mesh()->comm();
  // The solid's interface place now (reference + u), per node.
  const auto X = _solid.u->function_space()->tabulate_dof_coordinates(false);
  auto u = _solid.u->x()->array();
  std::vector<double> place(3 * _nodes.size(), 0.0);
  for (std::size_t n = 0; n < _nodes.size(); ++n)
    if (const auto b = _nodes[n].solid_block; b >= 0)
      for (int k = 0; k < 3; ++k)
        place[3 * n + k] = X[3 * b + k] + (k < _gdim ? u[_gdim * b + k] : 0.0);
  sum(comm, place);
  // Move the air mesh onto it: the offsets extended into the air.
  std::vector<std::pair<std::int32_t, Place>> offset;
  for (std::size_t n = 0; n < _nodes.size(); ++n)
    if (const auto b = _nodes[n].mesh_block; b >= 0)
    {
      const Place& a = _nodes[n].air_place;
      offset.push_back({b, {place[3 * n] - a[0], place[3 * n + 1] - a[1], place[3 * n + 2] - a[2]}});
    }
  _motion.extend(offset);
  auto& mesh = *_air_mesh;
  std::span<double> x = mesh.geometry().x();
  const std::vector<double> x_old(x.begin(), x.end());
  const auto& dofmap = *_motion.d->function_space()->dofmap();
  auto d = _motion.d->x()->array();
  const int tdim = mesh.topology().dim();
  const std::int32_t cells = mesh.topology().index_map(tdim)->size_local()
                             + mesh.topology().index_map(tdim)->num_ghosts();
  for (std::int32_t c = 0; c < cells; ++c)
  {
    auto nodes = mesh.geometry().dofmap().links(c);
    auto dofs = dofmap.cell_dofs(c);
    for (std::size_t i = 0; i < nodes.size(); ++i)
      for (int j = 0; j < _gdim; ++j)
        x[3 * nodes[i] + j] = x_old[3 * nodes[i] + j] + d[_gdim * dofs[i] + j];
  }
  for (std::size_t n = 0; n < _nodes.size(); ++n)
    for (int k = 0; k < 3; ++k)
      _nodes[n].air_place[k] = place[3 * n + k];

  // From rest: the air, the mesh displacement and its history at zero.
  for (auto f : {_motion.d, _air.up, _air.up_n, _air.up_nm1, _air.d_n, _air.d_nm1, _air.w})
    f->x()->set(0.0);
  std::vector<double> v;
  solid_state(_u0, v);
  std::fill(_lambda_n.begin(), _lambda_n.end(), 0.0);
  _unknowns->pack();
  _started = true;
}

void Coupled::advance()
{
  _lambda_n = _lambda;
  _solid.advance();
  _air.advance();
  if (_joined)
    _joined->advance();
}

Power Coupled::power()
{
  MPI_Comm comm = _solid.u->function_space()->mesh()->comm();
  // The load the solid receives: the coupled residual's solid rows less
  // the solid's own, with the opposite sign (R = internal - external).
  _unknowns->unpack();
  la::Vector<double> b(_unknowns->x().map(), 1);
  residual(b);
  std::vector<double> coupled(_unknowns->owned(0));
  _unknowns->extract(0, b, coupled);
  _solid.residual(*_b_solid);
  const auto c = _solid.velocity_coefficients();
  auto un = _solid.u->x()->array(), uo = _solid.u_old->x()->array(),
       vo = _solid.v_old->x()->array(), ao = _solid.a_old->x()->array();
  Power p;
  for (std::size_t i = 0; i < coupled.size(); ++i)
  {
    const double load = -(coupled[i] - _b_solid->array()[i]);
    const double v = c[0] * (un[i] - uo[i]) + c[1] * vo[i] + c[2] * ao[i];
    p.solid += load * ((1 - _alpha_f) * v + _alpha_f * vo[i]);
  }
  // What leaves the air: its force on the wall, -lambda, times its velocity.
  auto up = _air.up->x()->array(), up_n = _air.up_n->x()->array();
  for (std::size_t n = 0; n < _nodes.size(); ++n)
    for (int k = 0; k < 3; ++k)
      if (const auto i = _nodes[n].air_dof[k]; i >= 0 && _nodes[n].air[k] >= 0)
      {
        const std::size_t q = 3 * n + k;
        p.air -= ((1 - _alpha_f) * _lambda[q] + _alpha_f * _lambda_n[q])
                 * ((1 - _alpha_f) * up[i] + _alpha_f * up_n[i]);
      }
  std::array<double, 2> both{p.air, p.solid};
  MPI_Allreduce(MPI_IN_PLACE, both.data(), 2, MPI_DOUBLE, MPI_SUM, comm);
  return {both[0], both[1]};
}

} // namespace nct::fsi
