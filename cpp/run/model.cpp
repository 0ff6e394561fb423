#include "run/model.h"

#include <cmath>
#include <functional>

#include "air/domain.h"
#include "eye/geometry.h"
#include "run/air_block.h"
#include "run/coupling_block.h"
#include "run/mesh_motion_block.h"
#include "run/solid_block.h"

namespace nct
{
namespace
{

/// A surface group's tag; the groups were checked with the scene.
std::int32_t group(const meshio::Groups& g, const std::string& name)
{
  auto it = g.surfaces.find(name);
  if (it == g.surfaces.end())
    throw std::logic_error("the mesh has no surface group '" + name + "'");
  return it->second;
}

/// Run `build` (gmsh meshing) on rank 0; what fails there stops every
/// rank: std::invalid_argument as a scene error, anything else as a
/// runtime error about meshing `what`.
void on_rank_0(MPI_Comm comm, const Input& in, const std::string& what,
               const std::function<void()>& build)
{
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  std::string error, bad_input;
  if (rank == 0)
  {
    try
    {
      build();
    }
    catch (const std::invalid_argument& e)
    {
      bad_input = e.what();
    }
    catch (const std::exception& e)
    {
      error = e.what();
    }
  }
  if (bad_input = meshio::broadcast(comm, bad_input); !bad_input.empty())
    throw scene::Error(in.scene.file().string() + ": " + bad_input);
  if (error = meshio::broadcast(comm, error); !error.empty())
    throw std::runtime_error("meshing " + what + " failed: " + error);
}

/// Count a whole model's cells of the air (`air_tags`) and of the rest.
void count_cells(MPI_Comm comm, const meshio::Model& whole,
                 const std::vector<std::int32_t>& air_tags, AirMesh& a)
{
  for (auto g : whole.cell_groups)
    ++(std::find(air_tags.begin(), air_tags.end(), g) != air_tags.end() ? a.air_cells
                                                                       : a.eye_cells);
  MPI_Bcast(&a.air_cells, 1, MPI_INT64_T, 0, comm);
  MPI_Bcast(&a.eye_cells, 1, MPI_INT64_T, 0, comm);
}

/// The eye's parts, boundaries, fibres and probes on its distributed mesh
/// (the quarter eye, or its axisymmetric section).
MeshSetup eye_setup(meshio::Tagged mesh, const eye::Geometry& g, const eye::Derived& d,
                    section::Dimension dimension)
{
  MeshSetup m{std::move(mesh), {}, {}, {}, {}, {}, {}, {}, {}, {}};
  for (auto& [name, tag] : m.mesh.groups.volumes)
    m.parts[tag] = name;
  const auto& gs = m.mesh.groups;
  const bool section = dimension == section::Dimension::axisymmetric;
  m.boundaries.fixed = {group(gs, "fixed")};
  if (section)
    m.boundaries.axis = {group(gs, "axis")};
  else
    m.boundaries.symmetry = {group(gs, "symmetry_x"), group(gs, "symmetry_z")};
  if (g.internal_structures)
  {
    m.boundaries.cavities = {{group(gs, "aqueous_wall")}, {group(gs, "vitreous_wall")}};
    m.cavity_names = {"aqueous", "vitreous"};
  }
  else
  {
    m.boundaries.cavities = {{group(gs, "cavity_wall")}};
    m.cavity_names = {"cavity"};
  }
  // The cut closes the cavity behind (the vitreous, or the one cavity)
  // with a lid: the quarter disc inside the inner scleral sphere (a
  // section's: that disc per radian, R^2 / 2).
  const double inner = g.sclera_outer_radius - g.sclera_thickness;
  const double lid_r2 = inner * inner - g.cut_y * g.cut_y;
  m.boundaries.lids.assign(m.boundaries.cavities.size(), 0.0);
  m.boundaries.lids.back() = section ? lid_r2 / 2 : M_PI * lid_r2 / 4;
  m.boundaries.press = {group(gs, "anterior_cornea")};
  m.fibres = [g](const std::string& part, const std::array<double, 3>& X)
  {
    static const std::map<std::string, eye::Part> by_name
        = {{"cornea", eye::Part::cornea},           {"limbus", eye::Part::limbus},
           {"sclera", eye::Part::sclera},           {"lens_cortex", eye::Part::lens_cortex},
           {"lens_nucleus", eye::Part::lens_nucleus}, {"zonule", eye::Part::zonule},
           {"vitreous_membrane", eye::Part::vitreous_membrane}};
    return eye::fibres(g, by_name.at(part), X);
  };
  m.volume_origin = {0.0, g.cut_y, 0.0};
  m.probes = {{0.0, d.apex_y, 0.0}};
  m.probe_names = {"apex"};
  return m;
}

/// The meshes of the idealised eye: the eye alone, the air alone about a
/// rigid eye or none (only the air's cells kept), or both in one gmsh
/// model (conforming on the eye's anterior surface), split in two.
std::pair<std::optional<MeshSetup>, std::optional<AirMesh>>
eye_meshes(MPI_Comm comm, const Input& in, bool solid, bool air)
{
  const Settings& s = in.settings;
  const eye::Geometry& g = s.mesh.geometry;
  const bool with_eye = solid || s.air.rigid_eye;
  // The humor's mesh, for its flow or Navier-Stokes.
  const bool flow = solid && s.solid.cavity.meshed_humor();
  meshio::GmshSession gmsh_session;
  const section::Dimension dimension = s.mesh.dimension;
  on_rank_0(comm, in, "the eye and the air",
            [&]
            {
              if (with_eye && dimension == section::Dimension::axisymmetric)
                eye::build_section(g, s.mesh.refinement, flow);
              else if (with_eye)
                eye::build(g, s.mesh.refinement, flow);
              if (air)
                (dimension == section::Dimension::axisymmetric ? air::build_section
                                                               : air::build)(
                    s.air.domain, in.built.eye.apex_y, g.cut_y,
                    with_eye ? g.sclera_outer_radius : 0.0, with_eye);
            });
  const meshio::Model whole = meshio::extract(comm);
  std::optional<AirMesh> a;
  if (air)
  {
    const std::vector<std::int32_t> air_tag{static_cast<std::int32_t>(air::Group::volume)};
    a.emplace();
    a->eye = in.built.eye;
    a->domain = s.air.domain;
    count_cells(comm, whole, air_tag, *a);
    a->mesh = meshio::distribute(comm, meshio::keep(whole, air_tag));
  }
  if (!solid)
    return {std::nullopt, std::move(a)};
  if (!air && !flow)
    return {eye_setup(meshio::distribute(comm, whole), g, in.built.eye, dimension),
            std::nullopt};
  // The humor: one chamber, or the aqueous' and the vitreous' (the
  // internal structures), each with its cavity's wall.
  const auto& gs = whole.groups;
  std::vector<std::int32_t> eye_tags, humors, walls;
  for (auto [name, wall] : {std::pair{"humor", "cavity_wall"},
                            std::pair{"aqueous_humor", "aqueous_wall"},
                            std::pair{"vitreous_humor", "vitreous_wall"}})
    if (gs.volumes.count(name))
      humors.push_back(gs.volumes.at(name)), walls.push_back(group(gs, wall));
  for (auto& [name, tag] : gs.volumes)
    if (tag != static_cast<std::int32_t>(air::Group::volume)
        && std::find(humors.begin(), humors.end(), tag) == humors.end())
      eye_tags.push_back(tag);
  MeshSetup m = eye_setup(meshio::distribute(comm, meshio::keep(whole, eye_tags)), g,
                          in.built.eye, dimension);
  if (flow)
  {
    m.humor = meshio::distribute(comm, meshio::keep(whole, humors));
    // A section's axis; the 3D quarter's symmetry planes.
    if (dimension == section::Dimension::axisymmetric)
      m.humor_boundaries.axis = {group(gs, "axis")};
    else
      m.humor_boundaries.symmetry = {group(gs, "symmetry_x"), group(gs, "symmetry_z")};
    m.humor_boundaries.lid = {group(gs, "humor_lid")};
    for (std::size_t c = 0; c < humors.size(); ++c)
    {
      m.humor_boundaries.volumes.push_back({humors[c]});
      m.humor_boundaries.walls.push_back({walls[c]});
    }
  }
  return {std::move(m), std::move(a)};
}

/// An external mesh (opened by the scene's check): the solid's volume
/// groups, and the fluid's in a mesh of their own, conforming on the
/// interface (boundary.interface, or found from the volume groups as
/// "interface").
std::pair<std::optional<MeshSetup>, std::optional<AirMesh>> file_meshes(MPI_Comm comm,
                                                                        const Input& in)
{
  const Settings& s = in.settings;
  const meshio::Groups& groups = in.built.file_mesh->groups();
  auto tags = [&](const std::vector<std::string>& names)
  {
    std::vector<std::int32_t> t;
    for (auto& name : names)
      t.push_back(group(groups, name));
    return t;
  };
  const auto& bs = s.mesh.boundary;
  solid::Boundaries b;
  b.fixed = tags(bs.fixed);
  b.symmetry = tags(bs.symmetry);
  b.axis = tags(bs.axis);
  if (auto walls = tags(bs.cavity_wall); !walls.empty())
    b.cavities = {walls};
  b.press = tags(bs.press);

  meshio::Model whole = in.built.file_mesh->extract(comm, s.mesh.size_max);
  const auto fluids = s.fluid_parts();
  const auto& humors = s.solid.cavity.humor_groups;
  std::vector<std::int32_t> fluid_tags, solid_tags, humor_tags;
  for (auto& [name, tag] : groups.volumes)
    (std::find(fluids.begin(), fluids.end(), name) != fluids.end()   ? fluid_tags
     : std::find(humors.begin(), humors.end(), name) != humors.end() ? humor_tags
                                                                     : solid_tags)
        .push_back(tag);
  // The humor's mesh, conforming to the cavity's wall (cavity.humor_inertia
  // = "flow" or "navier_stokes"; the other models leave it out).
  std::optional<meshio::Tagged> humor;
  if (!humor_tags.empty())
  {
    if (s.solid.cavity.meshed_humor())
      humor = meshio::distribute(comm, meshio::keep(whole, humor_tags));
    whole = meshio::keep(whole, [&]
                         {
                           std::vector<std::int32_t> rest = solid_tags;
                           rest.insert(rest.end(), fluid_tags.begin(), fluid_tags.end());
                           return rest;
                         }());
  }
  std::optional<AirMesh> fluid;
  if (!fluid_tags.empty())
  {
    if (bs.interface.empty() && !solid_tags.empty())
    {
      std::string error;
      try
      {
        meshio::add_interface(whole, fluid_tags, "interface");
      }
      catch (const std::invalid_argument& e)
      {
        error = e.what();
      }
      if (error = meshio::broadcast(comm, error); !error.empty())
        throw scene::Error(in.scene.file().string() + ": " + s.mesh.file.string() + ": "
                           + error);
    }
    fluid.emplace();
    count_cells(comm, whole, fluid_tags, *fluid);
    fluid->mesh = meshio::distribute(comm, meshio::keep(whole, fluid_tags));
    whole = meshio::keep(whole, solid_tags);
    if (solid_tags.empty())
      return {std::nullopt, std::move(fluid)}; // the fluid alone
  }
  MeshSetup m{meshio::distribute(comm, whole), {}, b, {}, {}, {}, {}, {}, std::move(humor), {}};
  if (!b.cavities.empty())
    m.cavity_names = {"cavity"};
  if (m.humor)
    m.humor_boundaries = {{humor_tags},       {tags(bs.cavity_wall)}, tags(bs.axis),
                          tags(bs.symmetry), tags(bs.humor_open), {}};
  for (auto& [name, tag] : groups.volumes)
    if (std::find(solid_tags.begin(), solid_tags.end(), tag) != solid_tags.end())
      m.parts[tag] = name;
  std::map<std::string, std::array<std::array<double, 3>, 2>> constant;
  for (auto& [name, material] : s.materials)
  {
    if (material.law == solid::Law::fluid)
      continue;
    std::array<std::array<double, 3>, 2> a{};
    const auto& dirs = material.fibre_directions;
    for (std::size_t i = 0; i < dirs.size(); ++i)
    {
      const double n = std::hypot(dirs[i][0], dirs[i][1], dirs[i][2]);
      for (int j = 0; j < 3; ++j)
        a[i][j] = dirs[i][j] / n;
    }
    constant[name] = a;
  }
  m.fibres = [constant](const std::string& part, const std::array<double, 3>&)
  { return constant.at(part); };
  m.volume_origin = s.solid.cavity.origin.at(0);
  return {std::move(m), std::move(fluid)};
}

/// What the air block needs of its mesh's boundaries: its conditions, its
/// fluid's properties, a typical speed [mm/ms], the solid's facet groups
/// on the interface.
struct FluidSide
{
  air::Boundaries boundaries;
  air::Fluid fluid;
  double velocity_scale = 1;
  std::vector<std::int32_t> solid_interface;
};

/// The idealised eye's air: the nozzle's jet onto the anterior cornea and
/// sclera, a wall (`rigid_eye`) or the interface.
FluidSide eye_fluid_side(const Settings& s, const AirMesh& a, const MeshSetup* solid)
{
  // No slip on the nozzle (and a rigid eye), the normal velocity zero on
  // the symmetry planes, the inlet's velocity, sigma n = 0 on the outlet.
  const auto& gs = a.mesh.groups;
  FluidSide f;
  if (s.mesh.dimension == section::Dimension::axisymmetric) // u_r = 0 on the axis
    f.boundaries.zero = {{group(gs, "nozzle"), {0, 1, 2}}, {group(gs, "air_axis"), {0}}};
  else
    f.boundaries.zero = {{group(gs, "nozzle"), {0, 1, 2}},
                         {group(gs, "air_symmetry_x"), {0}},
                         {group(gs, "air_symmetry_z"), {2}}};
  for (const char* wall : {"anterior_cornea", "anterior_sclera"})
    if (gs.surfaces.count(wall))
    {
      if (!solid)
        f.boundaries.zero.push_back({group(gs, wall), {0, 1, 2}});
      else
      {
        f.boundaries.interface.push_back(group(gs, wall));
        f.solid_interface.push_back(group(solid->mesh.groups, wall));
      }
    }
  f.boundaries.inlet = {group(gs, "inlet")};
  f.boundaries.outlet = {group(gs, "outlet")};
  f.fluid = s.air.fluid;
  f.velocity_scale = std::max(s.air.inlet.velocity, 1.0);
  return f;
}

/// A file mesh's fluid: its groups' conditions (boundary.*), the fluid
/// part's properties, the inlet's largest speed.
FluidSide file_fluid_side(const Settings& s, const Built& built, const AirMesh& a)
{
  const meshio::Tagged& m = a.mesh;
  const auto& bs = s.mesh.boundary;
  auto tags = [&](const std::vector<std::string>& names)
  {
    std::vector<std::int32_t> t;
    for (auto& name : names)
      t.push_back(group(m.groups, name));
    return t;
  };
  FluidSide f;
  for (auto g : tags(bs.wall))
    f.boundaries.zero.push_back({g, {0, 1, 2}});
  for (auto& name : bs.symmetry)
  {
    const std::int32_t g = group(m.groups, name);
    std::int64_t count = static_cast<std::int64_t>(m.facets->find(g).size());
    MPI_Allreduce(MPI_IN_PLACE, &count, 1, MPI_INT64_T, MPI_SUM, m.mesh->comm());
    if (count == 0)
      continue; // the solid's side only
    const int axis = meshio::normal_axis(*m.mesh, *m.facets, g);
    if (axis < 0)
      throw scene::Error("key 'boundary.symmetry': group '" + name
                         + "' is not a plane x, y or z = const in the fluid");
    f.boundaries.zero.push_back({g, {axis}});
  }
  for (auto& name : bs.axis) // an axisymmetric section's axis: u_r = 0
    f.boundaries.zero.push_back({group(m.groups, name), {0}});
  f.boundaries.inlet = tags(bs.inlet);
  f.boundaries.outlet = tags(bs.outlet);
  f.boundaries.interface = tags(bs.interface);
  if (f.boundaries.interface.empty() && m.groups.surfaces.count("interface"))
    f.boundaries.interface = {m.groups.surfaces.at("interface")}; // found from the volumes
  f.solid_interface = f.boundaries.interface;
  const solid::Material& fluid = s.materials.at(s.fluid_parts().at(0));
  f.fluid = {fluid.density, fluid.viscosity, s.air.fluid.backflow, s.air.fluid.stabilisation_time};
  double speed = 0; // the largest
  if (s.air.inlet.profile == InletSettings::Profile::table)
    for (const auto& p : built.inlet_table)
      speed = std::max(speed, std::abs(p[3]));
  else
    speed = s.air.inlet.velocity;
  f.velocity_scale = speed > 0 ? speed : 1.0;
  return f;
}

/// The solid block's settings: its keys, its materials, the time step, the
/// puff's load and frames, the prescribed pressure the check built.
SolidBlockSettings solid_block_settings(const Input& in)
{
  const Settings& s = in.settings;
  return {s.solid,           s.materials,  s.dynamics.dt,  s.puff.load,
          in.built.puff_pressure, s.puff.frame_rate, s.output.fields};
}

/// The air block's settings: [air] and [inlet], the puff's time course and
/// measured pulse, a file mesh's inlet table, the model's dimension.
AirBlockSettings air_block_settings(const Input& in)
{
  const Settings& s = in.settings;
  return {s.air,          s.puff.peak_time,     s.puff.width_t, in.built.pulse,
          in.built.inlet_table, s.mesh.dimension, s.output.fields};
}

} // namespace

Model::Model(Model&&) noexcept = default;
Model::~Model() = default;

std::vector<Block*> Model::blocks() const
{
  std::vector<Block*> b;
  for (Block* block : std::initializer_list<Block*>{solid.get(), air.get(), mesh_motion.get(),
                                                    coupling.get()})
    if (block)
      b.push_back(block);
  return b;
}

Model make_model(MPI_Comm comm, const Input& in)
{
  Model model;
  const Settings& s = in.settings;
  model.eye = s.mesh.eye();
  const PuffSettings::Load load = s.puff.load;
  const bool air = load == PuffSettings::Load::air || load == PuffSettings::Load::fsi;
  const bool solid = load != PuffSettings::Load::air;
  double t = MPI_Wtime();
  auto [solid_mesh, air_mesh]
      = model.eye ? eye_meshes(comm, in, solid, air) : file_meshes(comm, in);
  if (solid_mesh)
  {
    MeshSetup& m = *solid_mesh;
    if (s.solid.support.springs)
      m.boundaries.support = solid::Support{s.solid.support.stiffness, s.solid.support.damping};
    if (s.solid.cavity.humor_inertia == CavitySettings::HumorInertia::translation)
      m.boundaries.humor_density = s.solid.cavity.humor_density;
    for (auto& p : s.solid.probes)
    {
      m.probes.push_back(p);
      m.probe_names.push_back("probe_" + std::to_string(m.probe_names.size()));
    }
  }
  model.t_mesh = MPI_Wtime() - t;

  t = MPI_Wtime();
  if (solid_mesh)
    model.solid
        = std::make_unique<SolidBlock>(std::move(*solid_mesh), solid_block_settings(in), model.eye);
  if (air_mesh)
  {
    const FluidSide f = model.eye ? eye_fluid_side(s, *air_mesh, solid ? &model.solid->mesh : nullptr)
                                  : file_fluid_side(s, in.built, *air_mesh);
    std::shared_ptr<dolfinx::fem::Function<double>> d;
    if (solid)
    {
      // The mesh motion: held where the air's boundary is (the symmetry
      // planes: their normal component), driven on the interface; its
      // rows' scale, the air's dynamic pressure rho U^2.
      mesh_motion::Boundaries mb;
      for (auto& [g, components] : f.boundaries.zero)
        mb.fixed.push_back({g, components});
      for (auto g : f.boundaries.inlet)
        mb.fixed.push_back({g, {0, 1, 2}});
      for (auto g : f.boundaries.outlet)
        mb.fixed.push_back({g, {0, 1, 2}});
      mb.interface = f.boundaries.interface;
      mesh_motion::Settings ms = s.mesh_motion;
      ms.scale = f.fluid.density * f.velocity_scale * f.velocity_scale;
      model.mesh_motion = std::make_unique<MeshMotionBlock>(air_mesh->mesh, ms, mb);
      d = model.mesh_motion->problem.d;
    }
    const bool with_eye = solid || s.air.rigid_eye;
    model.air = std::make_unique<AirBlock>(std::move(*air_mesh), air_block_settings(in), f.fluid,
                                           f.boundaries, f.velocity_scale, d, model.eye,
                                           with_eye);
    if (solid)
      model.coupling = std::make_unique<CouplingBlock>(
          *model.solid, *model.air, *model.mesh_motion,
          fsi::Interface{f.solid_interface, f.boundaries.interface}, s.fsi);
  }
  model.t_setup = MPI_Wtime() - t;
  return model;
}

} // namespace nct
