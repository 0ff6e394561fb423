#include "humor/navier_stokes.h"

#include <algorithm>
#include <limits>
#include <map>

#include <dolfinx/mesh/utils.h>

#include "biomarkers/registry.h"

namespace nct::humor
{
namespace
{
using namespace dolfinx;

// The humor's facets, tagged afresh so that none is left free (a free
// facet would be an outlet): walls, the axis, each symmetry plane and the
// lid by the axis normal to it, any other facet a wall at rest.
enum Tag : std::int32_t
{
  wall = 1,
  axis = 2,
  rigid = 3,
  normal_x = 4 // + the normal's axis
};

meshio::Tagged retagged(const meshio::Tagged& humor, const Boundaries& b, std::vector<int>& normals)
{
  auto& mesh = *humor.mesh;
  const int fdim = mesh.topology().dim() - 1;
  mesh.topology_mutable().create_connectivity(fdim, fdim + 1);
  std::map<std::int32_t, std::int32_t> tag;
  for (auto f : mesh::exterior_facet_indices(mesh.topology()))
    tag[f] = rigid;
  auto put = [&](const std::vector<std::int32_t>& groups, auto value)
  {
    for (auto g : groups)
    {
      const std::int32_t t = value(g);
      for (auto f : humor.facets->find(g))
        tag[f] = t;
    }
  };
  auto plane = [&](std::int32_t g)
  {
    const int k = meshio::normal_axis(mesh, *humor.facets, g);
    if (k < 0)
      throw std::invalid_argument("humor::NavierStokes: a symmetry plane or lid (group "
                                  + std::to_string(g) + ") is not normal to an axis");
    normals.push_back(k);
    return normal_x + k;
  };
  put(b.axis, [](auto) { return axis; });
  put(b.symmetry, plane);
  put(b.lid, plane);
  for (const auto& walls : b.walls)
    put(walls, [](auto) { return wall; });
  std::vector<std::int32_t> facets, values;
  for (auto [f, t] : tag)
    facets.push_back(f), values.push_back(t);
  meshio::Tagged h = humor;
  h.facets = std::make_shared<mesh::MeshTags<std::int32_t>>(humor.mesh, fdim, facets, values);
  std::sort(normals.begin(), normals.end());
  normals.erase(std::unique(normals.begin(), normals.end()), normals.end());
  return h;
}

} // namespace

NavierStokes::NavierStokes(solid::Problem& solid, const meshio::Tagged& solid_mesh,
                           const std::vector<std::int32_t>& walls, const meshio::Tagged& humor,
                           const Boundaries& boundaries, double density, double viscosity,
                           double speed, double stabilisation_time)
    : Humor(solid)
{
  if (!boundaries.open.empty())
    throw std::invalid_argument("humor::NavierStokes: a closed humor only");
  std::vector<int> normals;
  const meshio::Tagged h = retagged(humor, boundaries, normals);
  const section::Dimension dimension = solid.dimension();
  // The mesh follows the walls, sliding on the axis and the planes.
  mesh_motion::Boundaries mb{{{rigid, {0, 1, 2}}, {axis, {0}}}, {wall}};
  air::Boundaries fb{{{rigid, {0, 1, 2}}, {axis, {0}}}, {}, {}, {wall}};
  for (int k : normals)
  {
    mb.fixed.push_back({normal_x + k, {k}});
    fb.zero.push_back({normal_x + k, {k}});
  }
  mesh_motion::Settings ms;
  ms.scale = density * speed * speed;
  _motion = std::make_unique<mesh_motion::Problem>(h, ms, mb);
  _motion->d->name = "humor_mesh_displacement";
  const air::Fluid fluid{density, viscosity, 1.0, stabilisation_time};
  _fluid = std::make_unique<air::Problem>(h, fluid, fb, speed, _motion->d, dimension);
  _fluid->velocity->name = "humor_velocity";
  _fluid->pressure->name = "humor_pressure";
  _coupled = std::make_unique<fsi::Coupled>(solid, *_fluid, *_motion, solid_mesh, h,
                                            fsi::Interface{walls, {wall}}, true, nullptr, "humor");
}

void NavierStokes::start()
{
  _coupled->start();
  _coupled->unknowns().pack();
}

void NavierStokes::describe(nlohmann::json& summary, io::RunFolder& folder) const
{
  describe_mesh(summary, folder, *_fluid->up->function_space()->mesh(), dofs(),
                "velocity and pressure", wall_nodes(), name());
}

void NavierStokes::write(io::MovingFields& files, double time)
{
  _coupled->unknowns().unpack();
  _fluid->update_fields();
  _fluid->d->x()->scatter_fwd();
  files.write(*_fluid->pressure, *_fluid->d, time);
  files.write(*_fluid->velocity, *_fluid->d, time);
}

void NavierStokes::summarise(nlohmann::json& summary) const
{
  constexpr double mmHg = 1.333224e-4; // MPa
  biomarkers::put(summary, "humor_pressure_range_max_mmHg", _range_max / mmHg);
  biomarkers::put(summary, "humor_speed_max_m_s", _speed_max);
}

void NavierStokes::set_time_step(const dynamics::TimeStep& step) { _coupled->set_time_step(step, 2); }

void NavierStokes::advance()
{
  _coupled->unknowns().unpack();
  MPI_Comm comm = _fluid->up->function_space()->mesh()->comm();
  // The pressure's range and the largest speed over the owned nodes.
  auto up = _fluid->up->x()->array();
  const std::int32_t owned = _fluid->up->x()->map()->size_local() * _fluid->up->x()->bs();
  const int g = _fluid->up->function_space()->mesh()->geometry().dim();
  double range[2] = {std::numeric_limits<double>::infinity(),
                     std::numeric_limits<double>::infinity()}; // -max, min
  for (auto i : _fluid->pressure_dofs())
    if (i < owned)
      range[0] = std::min(range[0], -up[i]), range[1] = std::min(range[1], up[i]);
  double speed = 0;
  const auto& v = _fluid->velocity_dofs();
  for (std::size_t n = 0; n + g <= v.size(); n += g)
    if (v[n] < owned)
    {
      double s = 0;
      for (int k = 0; k < g; ++k)
        s += up[v[n + k]] * up[v[n + k]];
      speed = std::max(speed, s);
    }
  MPI_Allreduce(MPI_IN_PLACE, range, 2, MPI_DOUBLE, MPI_MIN, comm);
  MPI_Allreduce(MPI_IN_PLACE, &speed, 1, MPI_DOUBLE, MPI_MAX, comm);
  _range_max = std::max(_range_max, -range[0] - range[1]);
  _speed_max = std::max(_speed_max, std::sqrt(speed));
  _jacobian_min = std::min(_jacobian_min, _fluid->smallest_mesh_jacobian().first);
  _coupled->advance();
}

nlohmann::json NavierStokes::save(io::CheckpointWriter& checkpoint) const
{
  return {{"coupled", _coupled->save(checkpoint)},
          {"extremes", {_range_max, _speed_max, _jacobian_min}}};
}

void NavierStokes::restore(const io::CheckpointReader& checkpoint, const nlohmann::json& state)
{
  _coupled->restore(checkpoint, state.at("coupled"));
  const auto& e = state.at("extremes");
  _range_max = e[0], _speed_max = e[1], _jacobian_min = e[2];
  _coupled->unknowns().pack();
}

} // namespace nct::humor
