#include "run/model.h"

#include <functional>

#include <cmath>
#include <gmsh.h>

#include "air/inlet.h"
#include "eye/geometry.h"
#include "puff/load.h"

namespace nct
{
namespace
{

std::int32_t surface_tag(const meshio::Groups& g, const std::string& name,
                         const std::string& file, const std::string& key)
{
  auto it = g.surfaces.find(name);
  if (it == g.surfaces.end())
  {
    std::string known;
    for (auto& [n, t] : g.surfaces)
      known += (known.empty() ? "" : ", ") + n;
    throw scene::Error(file + ": key '" + key + "': the mesh has no surface group '" + name
                       + "' (it has: " + known + ")");
  }
  return it->second;
}

/// gmsh for the span of a scope, quiet.
struct GmshSession
{
  GmshSession()
  {
    gmsh::initialize();
    gmsh::option::setNumber("General.Terminal", 0);
  }
  ~GmshSession() { gmsh::finalize(); }
};

/// The eye's shape from [geometry]: each key is the field of the same name.
eye::Geometry eye_geometry(const scene::Scene& s)
{
  using G = eye::Geometry;
  static const std::vector<std::pair<const char*, double G::*>> shell
      = {{"cornea_anterior_radius", &G::cornea_anterior_radius},
         {"cornea_posterior_radius", &G::cornea_posterior_radius},
         {"cornea_central_thickness", &G::cornea_central_thickness},
         {"limbus_diameter", &G::limbus_diameter},
         {"limbus_width", &G::limbus_width},
         {"sclera_outer_radius", &G::sclera_outer_radius},
         {"sclera_thickness", &G::sclera_thickness},
         {"cut_y", &G::cut_y}};
  static const std::vector<std::pair<const char*, double G::*>> internal
      = {{"anterior_chamber_depth", &G::anterior_chamber_depth},
         {"lens_thickness", &G::lens_thickness},
         {"lens_diameter", &G::lens_diameter},
         {"lens_anterior_radius", &G::lens_anterior_radius},
         {"lens_posterior_radius", &G::lens_posterior_radius},
         {"lens_nucleus_fraction", &G::lens_nucleus_fraction},
         {"ciliary_offset", &G::ciliary_offset}};
  G g;
  for (auto [key, field] : shell)
    g.*field = s.real(std::string("geometry.") + key);
  g.internal_structures = s.boolean("geometry.internal_structures");
  if (g.internal_structures)
    for (auto [key, field] : internal)
      g.*field = s.real(std::string("geometry.") + key);
  return g;
}

/// The eye's derived shape; an impossible geometry is a scene error.
eye::Derived eye_derived(const scene::Scene& s)
{
  try
  {
    return eye::derive(eye_geometry(s));
  }
  catch (const std::invalid_argument& e)
  {
    throw scene::Error(s.file().string() + ": " + e.what());
  }
}

/// The eye's mesh refinement from [mesh].
eye::Refinement eye_refinement(const scene::Scene& s, const eye::Geometry& g)
{
  eye::Refinement r;
  r.layers = s.integer("mesh.layers");
  r.size_cornea = s.real("mesh.size_cornea");
  r.size_limbus = s.real("mesh.size_limbus");
  r.size_sclera = s.real("mesh.size_sclera");
  if (g.internal_structures)
    r.size_lens = s.real("mesh.size_lens");
  return r;
}

/// Run `build` (gmsh meshing) on rank 0; what fails there stops every
/// rank: std::invalid_argument as a scene error, anything else as a
/// runtime error about meshing `what`.
void on_rank_0(MPI_Comm comm, const scene::Scene& s, const std::string& what,
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
    throw scene::Error(s.file().string() + ": " + bad_input);
  if (error = meshio::broadcast(comm, error); !error.empty())
    throw std::runtime_error("meshing " + what + " failed: " + error);
}

/// The air domain from [air]: each key is the field of the same name.
air::Domain air_domain(const scene::Scene& s)
{
  using D = air::Domain;
  D d;
  for (auto [key, field] : std::vector<std::pair<const char*, double D::*>>{
           {"radius", &D::radius},
           {"nozzle_diameter", &D::nozzle_diameter},
           {"nozzle_outer_diameter", &D::nozzle_outer_diameter},
           {"nozzle_distance", &D::nozzle_distance},
           {"nozzle_length", &D::nozzle_length},
           {"size_nozzle", &D::size_nozzle},
           {"size_jet", &D::size_jet},
           {"jet_radius", &D::jet_radius},
           {"size_far", &D::size_far}})
    d.*field = s.real(std::string("air.") + key);
  return d;
}

/// The .geo's parameters of mesh.parameters (numbers).
std::map<std::string, double> mesh_parameters(const scene::Scene& s)
{
  std::map<std::string, double> p;
  for (auto& [name, value] : s.options("mesh.parameters"))
  {
    double v = 0;
    std::size_t end = 0;
    try
    {
      v = std::stod(value, &end);
    }
    catch (const std::exception&)
    {
      end = 0;
    }
    if (end != value.size() || !std::isfinite(v))
      throw scene::Error(s.file().string() + ": key 'mesh.parameters." + name
                         + "': got '" + value + "'; expected a finite number");
    p[name] = v;
  }
  return p;
}

/// The volume groups of a file mesh that are fluid (material model "fluid").
std::vector<std::string> fluid_parts(const scene::Scene& s)
{
  std::vector<std::string> fluids;
  if (s.string("mesh.source") == "file")
    for (auto& name : s.tables("material"))
      if (s.string("material." + name + ".model") == "fluid")
        fluids.push_back(name);
  return fluids;
}

/// An external mesh's groups against the scene's materials and boundaries.
void check_file_groups(const scene::Scene& s, const meshio::Groups& groups)
{
  const std::string file = s.file().string();
  auto materials = s.tables("material");
  for (auto& [name, tag] : groups.volumes)
    if (std::find(materials.begin(), materials.end(), name) == materials.end())
      throw scene::Error(file + ": volume group '" + name + "' of " + s.string("mesh.file")
                         + " has no [material." + name + "] table");
  for (auto& name : materials)
    if (!groups.volumes.count(name))
      throw scene::Error(file + ": key 'material." + name
                         + "': the mesh has no volume group '" + name + "'");
  for (const char* key : {"boundary.fixed", "boundary.symmetry", "boundary.cavity_wall",
                          "boundary.surface_load", "boundary.inlet", "boundary.outlet",
                          "boundary.wall", "boundary.interface", "output.force_on"})
    if (s.has(key))
      for (auto& name : s.strings(key))
        if (!(name == "interface" && s.has("boundary.interface")
              && s.strings("boundary.interface").empty()))
          surface_tag(groups, name, file, key); // "interface": found from the volumes
  const auto fluids = fluid_parts(s);
  if (fluids.empty())
    return;
  // Each boundary on the side its physics lives on (where the geometry
  // tells the sides: a .geo, or a .msh with its entities).
  auto is_fluid = [&](const std::string& v)
  { return std::find(fluids.begin(), fluids.end(), v) != fluids.end(); };
  auto side_check = [&](const char* key, bool fluid_side, const char* what)
  {
    for (auto& name : s.strings(key))
    {
      auto it = groups.sides.find(name);
      if (it == groups.sides.end())
        continue;
      for (auto& v : it->second)
        if (is_fluid(v) != fluid_side && it->second.size() == 1)
          throw scene::Error(file + ": key '" + key + "': surface group '" + name
                             + "' bounds the " + (fluid_side ? "solid" : "fluid")
                             + " volume group '" + v + "' only; " + what);
    }
  };
  side_check("boundary.inlet", true, "an inlet must bound a fluid group");
  side_check("boundary.outlet", true, "an outlet must bound a fluid group");
  side_check("boundary.wall", true, "a wall must bound a fluid group");
  side_check("boundary.fixed", false, "a clamp must bound a solid group");
  for (auto& name : s.strings("boundary.interface"))
  {
    auto it = groups.sides.find(name);
    if (it == groups.sides.end())
      continue;
    bool fluid = false, solid = false;
    for (auto& v : it->second)
      (is_fluid(v) ? fluid : solid) = true;
    if (!fluid || !solid)
      throw scene::Error(file + ": key 'boundary.interface': surface group '" + name
                         + "' has no " + (fluid ? "solid" : "fluid")
                         + " side; the interface lies between a fluid and a solid group");
  }
  double density = 0, viscosity = 0;
  for (auto& f : fluids)
  {
    const double rho = s.real("material." + f + ".density"),
                 mu = s.real("material." + f + ".viscosity");
    if (density > 0 && (rho != density || mu != viscosity))
      throw scene::Error(file + ": key 'material." + f + "': the fluid groups must share "
                         "one density and viscosity (one fluid)");
    density = rho;
    viscosity = mu;
  }
  if (s.strings("boundary.inlet").empty())
    throw scene::Error(file + ": key 'boundary.inlet': the fluid needs an inlet group");
}

/// The eye's parts, boundaries, fibres and probes on its distributed mesh.
MeshSetup eye_setup(meshio::Tagged mesh, const eye::Geometry& g, const eye::Derived& d)
{
  MeshSetup m{std::move(mesh), {}, {}, {}, {}, {}, {}, {}};
  for (auto& [name, tag] : m.mesh.groups.volumes)
    m.parts[tag] = name;
  const auto& gs = m.mesh.groups;
  const std::string eye_model = "the eye model";
  m.boundaries.fixed = {surface_tag(gs, "fixed", eye_model, "mesh")};
  m.boundaries.symmetry = {surface_tag(gs, "symmetry_x", eye_model, "mesh"),
                           surface_tag(gs, "symmetry_z", eye_model, "mesh")};
  if (g.internal_structures)
  {
    m.boundaries.cavities = {{surface_tag(gs, "aqueous_wall", eye_model, "mesh")},
                             {surface_tag(gs, "vitreous_wall", eye_model, "mesh")}};
    m.cavity_names = {"aqueous", "vitreous"};
  }
  else
  {
    m.boundaries.cavities = {{surface_tag(gs, "cavity_wall", eye_model, "mesh")}};
    m.cavity_names = {"cavity"};
  }
  // The cut closes the cavity behind (the vitreous, or the one cavity)
  // with a lid: the quarter disc inside the inner scleral sphere.
  const double inner = g.sclera_outer_radius - g.sclera_thickness;
  m.boundaries.lids.assign(m.boundaries.cavities.size(), 0.0);
  m.boundaries.lids.back() = M_PI * (inner * inner - g.cut_y * g.cut_y) / 4;
  m.boundaries.surface_load = {surface_tag(gs, "anterior_cornea", eye_model, "mesh")};
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

MeshSetup eye_mesh(MPI_Comm comm, const scene::Scene& s)
{
  const eye::Geometry g = eye_geometry(s);
  const eye::Derived d = eye_derived(s);
  const eye::Refinement r = eye_refinement(s, g);
  on_rank_0(comm, s, "the eye", [&] { eye::build(g, r); });
  return eye_setup(meshio::distribute(comm, meshio::extract(comm)), g, d);
}

/// The eye and the air about it, meshed in one gmsh model (conforming on
/// the eye's anterior surface), then split into two distributed meshes.
std::pair<MeshSetup, AirMesh> eye_and_air(MPI_Comm comm, const scene::Scene& s)
{
  const eye::Geometry g = eye_geometry(s);
  const eye::Refinement r = eye_refinement(s, g);
  AirMesh a;
  a.eye = eye_derived(s);
  a.domain = air_domain(s);
  on_rank_0(comm, s, "the eye and the air", [&] {
    eye::build(g, r);
    air::build(a.domain, a.eye.apex_y, g.cut_y, g.sclera_outer_radius, true);
  });
  const meshio::Model whole = meshio::extract(comm);
  const std::int32_t air_tag = static_cast<std::int32_t>(air::Group::volume);
  std::vector<std::int32_t> eye_tags;
  for (auto& [name, tag] : whole.groups.volumes)
    if (tag != air_tag)
      eye_tags.push_back(tag);
  for (auto group : whole.cell_groups)
    ++(group == air_tag ? a.air_cells : a.eye_cells);
  MPI_Bcast(&a.air_cells, 1, MPI_INT64_T, 0, comm);
  MPI_Bcast(&a.eye_cells, 1, MPI_INT64_T, 0, comm);
  a.mesh = meshio::distribute(comm, meshio::keep(whole, {air_tag}));
  return {eye_setup(meshio::distribute(comm, meshio::keep(whole, eye_tags)), g, a.eye),
          std::move(a)};
}

/// An external mesh: the solid's volume groups, and (`fluid` not null)
/// the fluid's in a mesh of their own, conforming on the interface
/// (boundary.interface, or found from the volume groups as "interface").
MeshSetup file_mesh(MPI_Comm comm, const scene::Scene& s, std::optional<AirMesh>* fluid = nullptr)
{
  const std::string file = s.file().string();
  meshio::Groups groups = meshio::open(comm, s.path("mesh.file"), mesh_parameters(s));
  check_file_groups(s, groups);
  auto materials = s.tables("material");
  solid::Boundaries b;
  auto tags = [&](const std::string& key)
  {
    std::vector<std::int32_t> t;
    for (auto& name : s.strings(key))
      t.push_back(surface_tag(groups, name, file, key));
    return t;
  };
  b.fixed = tags("boundary.fixed");
  b.symmetry = tags("boundary.symmetry");
  if (auto walls = tags("boundary.cavity_wall"); !walls.empty())
    b.cavities = {walls};
  b.surface_load = tags("boundary.surface_load");

  meshio::Model whole = meshio::extract(comm, s.real("mesh.size_max"));
  const auto fluids = fluid_parts(s);
  std::vector<std::int32_t> fluid_tags, solid_tags;
  for (auto& [name, tag] : groups.volumes)
    (std::find(fluids.begin(), fluids.end(), name) != fluids.end() ? fluid_tags : solid_tags)
        .push_back(tag);
  if (fluid && !fluid_tags.empty())
  {
    if (s.strings("boundary.interface").empty() && !solid_tags.empty())
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
        throw scene::Error(file + ": " + s.string("mesh.file") + ": " + error);
    }
    AirMesh a;
    for (auto group : whole.cell_groups)
      ++(std::find(fluid_tags.begin(), fluid_tags.end(), group) != fluid_tags.end()
             ? a.air_cells
             : a.eye_cells);
    MPI_Bcast(&a.air_cells, 1, MPI_INT64_T, 0, comm);
    MPI_Bcast(&a.eye_cells, 1, MPI_INT64_T, 0, comm);
    a.mesh = meshio::distribute(comm, meshio::keep(whole, fluid_tags));
    whole = meshio::keep(whole, solid_tags);
    fluid->emplace(std::move(a));
    if (solid_tags.empty())
      return {}; // the fluid alone
  }
  MeshSetup m{meshio::distribute(comm, whole), {}, b, {}, {}, {}, {}, {}};
  if (!b.cavities.empty())
    m.cavity_names = {"cavity"};
  for (auto& [name, tag] : groups.volumes)
    if (std::find(solid_tags.begin(), solid_tags.end(), tag) != solid_tags.end())
      m.parts[tag] = name;
  std::map<std::string, std::array<std::array<double, 3>, 2>> constant;
  for (auto& name : materials)
  {
    if (std::find(fluids.begin(), fluids.end(), name) != fluids.end())
      continue;
    std::array<std::array<double, 3>, 2> a{};
    auto dirs = s.points("material." + name + ".fibre_directions");
    for (std::size_t i = 0; i < dirs.size(); ++i)
    {
      double n = std::hypot(dirs[i][0], dirs[i][1], dirs[i][2]);
      if (n == 0)
        throw scene::Error(file + ": key 'material." + name
                           + ".fibre_directions': a zero vector has no direction");
      for (int j = 0; j < 3; ++j)
        a[i][j] = dirs[i][j] / n;
    }
    constant[name] = a;
  }
  m.fibres = [constant](const std::string& part, const std::array<double, 3>&)
  { return constant.at(part); };
  m.volume_origin = s.points("cavity.origin").at(0);
  return m;
}

} // namespace

puff::PulseShape pulse_shape(const scene::Scene& s)
{
  const double peak = s.real("puff.peak");
  if (peak <= 0)
    throw scene::Error(s.file().string() + ": key 'puff.peak': the pulse needs a positive "
                       "peak, not " + std::to_string(peak) + " mmHg");
  try
  {
    return puff::PulseShape::from_descriptors(s.real("puff.rise_rate") / peak,
                                              s.real("puff.fall_rate") / peak,
                                              s.real("puff.pulse_duration"));
  }
  catch (const std::invalid_argument& e)
  {
    throw scene::Error(s.file().string() + ": keys 'puff.rise_rate', 'puff.fall_rate', "
                       "'puff.pulse_duration': " + e.what());
  }
}

std::unique_ptr<puff::Load> puff_load(const scene::Scene& s)
{
  const std::string load = s.string("puff.load");
  if (load == "gaussian")
    return std::make_unique<puff::Gaussian>(s.real("puff.peak"), s.real("puff.peak_time"),
                                            s.real("puff.width_t"), s.real("puff.width_r"));
  if (load == "pulse")
  {
    if (s.string("puff.profile").empty())
      throw scene::Error(s.file().string() + ": key 'puff.profile': puff.load = \"pulse\" "
                         "needs a CSV file (r_mm,p_mmHg)");
    const puff::PulseShape shape = pulse_shape(s);
    try
    {
      return std::make_unique<puff::Pulse>(s.real("puff.peak"), shape,
                                           puff::RadialProfile::read(s.path("puff.profile")));
    }
    catch (const std::invalid_argument& e)
    {
      throw scene::Error(s.file().string() + ": key 'puff.profile': " + e.what());
    }
  }
  if (load == "table")
  {
    if (s.string("puff.table").empty())
      throw scene::Error(s.file().string() + ": key 'puff.table': puff.load = \"table\" "
                         "needs a CSV file (t_ms,r_mm,p_mmHg)");
    try
    {
      return std::make_unique<puff::Table>(puff::Table::read(s.path("puff.table")));
    }
    catch (const std::invalid_argument& e)
    {
      throw scene::Error(s.file().string() + ": key 'puff.table': " + e.what());
    }
  }
  return nullptr;
}

void check(MPI_Comm comm, const scene::Scene& s)
{
  puff_load(s);
  if (s.has("air.inlet_history") && s.string("air.inlet_history") == "pulse")
    pulse_shape(s);
  if (s.has("inlet.profile") && s.string("inlet.profile") == "table")
  {
    if (s.string("inlet.table").empty())
      throw scene::Error(s.file().string() + ": key 'inlet.table': inlet.profile = \"table\" "
                         "needs a CSV file (x_mm,y_mm,z_mm,u_m_s)");
    try
    {
      air::Inlet::read_table(s.path("inlet.table"));
    }
    catch (const std::invalid_argument& e)
    {
      throw scene::Error(s.file().string() + ": key 'inlet.table': " + e.what());
    }
  }
  if (s.string("fem.formulation") == "mixed" && s.integer("fem.degree") != 2)
    throw scene::Error(s.file().string() + ": key 'fem.formulation': \"mixed\" (P2/P0) needs "
                       "fem.degree = 2, got " + std::to_string(s.integer("fem.degree")));
  if (s.string("mesh.source") == "eye")
  {
    const eye::Derived d = eye_derived(s);
    const std::string load = s.string("puff.load");
    if (load == "air" || load == "fsi")
      try
      {
        const bool with_eye = load == "fsi" || s.string("air.eye") == "rigid";
        air::validate(air_domain(s), d.apex_y, s.real("geometry.cut_y"),
                      with_eye ? s.real("geometry.sclera_outer_radius") : 0.0);
      }
      catch (const std::invalid_argument& e)
      {
        throw scene::Error(s.file().string() + ": " + e.what());
      }
  }
  else
  {
    GmshSession gmsh_session;
    meshio::Groups groups;
    const auto parameters = mesh_parameters(s);
    try
    {
      groups = meshio::open(comm, s.path("mesh.file"), parameters);
    }
    catch (const std::runtime_error& e) // every rank: open() broadcasts its error
    {
      throw scene::Error(s.file().string() + ": key 'mesh.file': " + e.what());
    }
    check_file_groups(s, groups);
  }
}

namespace
{

/// The air domain meshed about the idealised eye (air.eye = "rigid") or
/// in its place ("none"), in one gmsh model with the eye; only the air's
/// cells are kept.
AirMesh make_air_mesh(MPI_Comm comm, const scene::Scene& s)
{
  const double t = MPI_Wtime();
  AirMesh a;
  const eye::Geometry g = eye_geometry(s);
  a.eye = eye_derived(s);
  a.domain = air_domain(s);
  const bool with_eye = s.string("air.eye") == "rigid";
  const eye::Refinement r = eye_refinement(s, g);

  GmshSession gmsh_session;
  on_rank_0(comm, s, "the air", [&] {
    if (with_eye)
      eye::build(g, r);
    air::build(a.domain, a.eye.apex_y, g.cut_y, with_eye ? g.sclera_outer_radius : 0.0,
               with_eye);
  });
  const meshio::Model whole = meshio::extract(comm);
  const std::int32_t air_tag = static_cast<std::int32_t>(air::Group::volume);
  for (auto group : whole.cell_groups)
    ++(group == air_tag ? a.air_cells : a.eye_cells);
  MPI_Bcast(&a.air_cells, 1, MPI_INT64_T, 0, comm);
  MPI_Bcast(&a.eye_cells, 1, MPI_INT64_T, 0, comm);
  a.mesh = meshio::distribute(comm, meshio::keep(whole, {air_tag}));
  a.t_mesh = MPI_Wtime() - t;
  return a;
}

air::Fluid air_fluid(const scene::Scene& s)
{
  return {s.real("air.density"), s.real("air.viscosity"), s.real("air.backflow"),
          s.real("air.stabilisation_time")};
}

air::Boundaries air_boundaries(const meshio::Tagged& m, bool eye_is_wall)
{
  // No slip on the nozzle (and a rigid eye), the normal velocity zero on
  // the symmetry planes, the inlet's velocity, sigma n = 0 on the outlet.
  auto group = [&](const char* name) { return m.groups.surfaces.at(name); };
  air::Boundaries b;
  b.zero = {{group("nozzle"), {0, 1, 2}},
            {group("air_symmetry_x"), {0}},
            {group("air_symmetry_z"), {2}}};
  for (const char* wall : {"anterior_cornea", "anterior_sclera"})
    if (m.groups.surfaces.count(wall))
    {
      if (eye_is_wall)
        b.zero.push_back({group(wall), {0, 1, 2}});
      else
        b.interface.push_back(group(wall));
    }
  b.inlet = {group("inlet")};
  b.outlet = {group("outlet")};
  return b;
}

void set_air_inlet(air::Problem& problem, const scene::Scene& s, const air::Domain& domain)
{
  const double bore = domain.nozzle_diameter / 2;
  if (s.string("air.inlet_profile") == "plug")
    problem.set_inlet([](const auto&) { return std::array<double, 3>{0, -1, 0}; });
  else
    problem.set_inlet([bore](const auto& x) {
      const double r2 = (x[0] * x[0] + x[2] * x[2]) / (bore * bore);
      return std::array<double, 3>{0, -std::max(0.0, 1 - r2), 0};
    });
}

/// What the coupling needs of the fluid's side: its conditions, its
/// properties, a typical speed [mm/ms], the solid's facet groups on the
/// interface and the inlet's shape.
struct FluidSide
{
  air::Boundaries boundaries;
  air::Fluid fluid;
  double velocity_scale = 1;
  std::vector<std::int32_t> solid_interface;
  std::function<void(air::Problem&)> set_inlet;
};

/// The idealised eye's air: the nozzle's jet onto the anterior cornea and sclera.
FluidSide eye_fluid_side(const scene::Scene& s, const Model& model)
{
  const AirMesh& a = model.air_mesh.value();
  FluidSide f{air_boundaries(a.mesh, false), air_fluid(s),
              std::max(s.real("air.inlet_velocity"), 1.0), {}, {}};
  const auto& solid_groups = model.setup.mesh.groups.surfaces;
  for (const char* surface : {"anterior_cornea", "anterior_sclera"})
    f.solid_interface.push_back(solid_groups.at(surface));
  const air::Domain domain = a.domain;
  f.set_inlet = [&s, domain](air::Problem& p) { set_air_inlet(p, s, domain); };
  return f;
}

/// The inlet of a file mesh's fluid (inlet.*) at unit speed.
air::Inlet file_inlet(const scene::Scene& s, const meshio::Tagged& mesh,
                      const std::vector<std::int32_t>& inlet)
{
  air::Inlet in;
  auto unit = [&](std::array<double, 3> v, const std::string& key)
  {
    const double n = std::hypot(v[0], v[1], v[2]);
    if (n == 0)
      throw scene::Error(s.file().string() + ": key '" + key
                         + "': a zero vector has no direction");
    return std::array<double, 3>{v[0] / n, v[1] / n, v[2] / n};
  };
  if (auto d = s.points("inlet.direction"); !d.empty())
    in.direction = unit(d.at(0), "inlet.direction");
  else
  {
    auto n = meshio::outward_normal(*mesh.mesh, *mesh.facets, inlet);
    in.direction = unit({-n[0], -n[1], -n[2]}, "boundary.inlet");
  }
  in.speed = 1;
  in.ramp_time = s.real("inlet.ramp_time");
  if (s.string("inlet.profile") == "table")
  {
    in.profile = air::Inlet::Profile::table;
    if (s.string("inlet.table").empty())
      throw scene::Error(s.file().string() + ": key 'inlet.table': inlet.profile = \"table\" "
                         "needs a CSV file (x_mm,y_mm,z_mm,u_m_s)");
    try
    {
      in.points = air::Inlet::read_table(s.path("inlet.table"));
    }
    catch (const std::invalid_argument& e)
    {
      throw scene::Error(s.file().string() + ": key 'inlet.table': " + e.what());
    }
  }
  else if (s.string("inlet.profile") == "parabolic")
  {
    in.center = s.points("inlet.center").at(0);
    if (s.string("inlet.section") == "circle")
    {
      in.profile = air::Inlet::Profile::circle;
      in.radius = s.real("inlet.radius");
    }
    else
    {
      in.profile = air::Inlet::Profile::rectangle;
      const auto axes = s.points("inlet.axes");
      if (axes.size() != 2)
        throw scene::Error(s.file().string() + ": key 'inlet.axes': two directions across "
                           "the rectangle, got " + std::to_string(axes.size()));
      in.axes = {unit(axes[0], "inlet.axes"), unit(axes[1], "inlet.axes")};
      in.half_widths = {s.real("inlet.half_width_1"), s.real("inlet.half_width_2")};
    }
  }
  return in;
}

/// A file mesh's fluid: its groups' conditions (boundary.*), the fluid
/// part's properties, the inlet (inlet.*).
FluidSide file_fluid_side(const scene::Scene& s, const Model& model)
{
  const meshio::Tagged& m = model.air_mesh.value().mesh;
  const std::string file = s.file().string();
  auto tags = [&](const std::string& key)
  {
    std::vector<std::int32_t> t;
    for (auto& name : s.strings(key))
      t.push_back(surface_tag(m.groups, name, file, key));
    return t;
  };
  FluidSide f;
  for (auto g : tags("boundary.wall"))
    f.boundaries.zero.push_back({g, {0, 1, 2}});
  for (auto& name : s.strings("boundary.symmetry"))
  {
    const std::int32_t g = surface_tag(m.groups, name, file, "boundary.symmetry");
    std::int64_t count = static_cast<std::int64_t>(m.facets->find(g).size());
    MPI_Allreduce(MPI_IN_PLACE, &count, 1, MPI_INT64_T, MPI_SUM, m.mesh->comm());
    if (count == 0)
      continue; // the solid's side only
    const int axis = meshio::normal_axis(*m.mesh, *m.facets, g);
    if (axis < 0)
      throw scene::Error(file + ": key 'boundary.symmetry': group '" + name
                         + "' is not a plane x, y or z = const in the fluid");
    f.boundaries.zero.push_back({g, {axis}});
  }
  f.boundaries.inlet = tags("boundary.inlet");
  f.boundaries.outlet = tags("boundary.outlet");
  f.boundaries.interface = tags("boundary.interface");
  if (f.boundaries.interface.empty() && m.groups.surfaces.count("interface"))
    f.boundaries.interface = {m.groups.surfaces.at("interface")}; // found from the volumes
  f.solid_interface = f.boundaries.interface;
  const std::string part = fluid_parts(s).at(0);
  f.fluid = {s.real("material." + part + ".density"), s.real("material." + part + ".viscosity"),
             s.real("air.backflow"), s.real("air.stabilisation_time")};
  const air::Inlet inlet = file_inlet(s, m, f.boundaries.inlet);
  double speed = 0; // the largest
  if (inlet.profile == air::Inlet::Profile::table)
    for (const auto& p : inlet.points)
      speed = std::max(speed, std::abs(p[3]));
  else
    speed = s.real("inlet.velocity");
  f.velocity_scale = speed > 0 ? speed : 1.0;
  f.set_inlet = [inlet](air::Problem& p) { p.set_inlet([inlet](const auto& x) { return inlet.velocity(x); }); };
  return f;
}

/// The blocks of the coupled puff on the model's air mesh: the air on its
/// moving mesh, the mesh motion, and their coupling with the solid
/// (paired on the interface, before the solid's geometry moves).
void add_fsi(const scene::Scene& s, Model& model, const FluidSide& f)
{
  const AirMesh& a = model.air_mesh.value();
  const double U = f.velocity_scale;
  // The mesh motion: held where the air's boundary is (the symmetry
  // planes: their normal component), driven on the interface; its rows'
  // scale, the air's dynamic pressure rho U^2.
  mesh_motion::Boundaries mb;
  for (auto& [g, components] : f.boundaries.zero)
    mb.fixed.push_back({g, components});
  for (auto g : f.boundaries.inlet)
    mb.fixed.push_back({g, {0, 1, 2}});
  for (auto g : f.boundaries.outlet)
    mb.fixed.push_back({g, {0, 1, 2}});
  mb.interface = f.boundaries.interface;
  const mesh_motion::Settings ms{s.string("mesh_motion.model"), s.real("mesh_motion.stiffening"),
                                 s.string("mesh_motion.model") == "elastic"
                                     ? s.real("mesh_motion.poisson_ratio")
                                     : 0.3,
                                 s.real("mesh_motion.distance"), f.fluid.density * U * U};
  model.motion = std::make_unique<mesh_motion::Problem>(a.mesh, ms, mb);
  model.air = std::make_unique<air::Problem>(a.mesh, f.fluid, f.boundaries, U, model.motion->d);
  f.set_inlet(*model.air);
  fsi::Interface interface{f.solid_interface, f.boundaries.interface};
  model.coupled = std::make_unique<fsi::Coupled>(*model.problem, *model.air, *model.motion,
                                                 model.setup.mesh, a.mesh, interface,
                                                 s.boolean("fsi.shape_derivative"));
}

} // namespace

Model make_model(MPI_Comm comm, const scene::Scene& s)
{
  check(comm, s);
  Model model;
  model.eye = s.string("mesh.source") == "eye";
  const std::string load = s.string("puff.load");
  double t = MPI_Wtime();
  if (load == "air" && !model.eye)
  {
    // A file mesh's fluid alone (every volume group fluid) on its fixed mesh.
    {
      GmshSession gmsh_session;
      file_mesh(comm, s, &model.air_mesh);
    }
    model.t_mesh = MPI_Wtime() - t;
    t = MPI_Wtime();
    const FluidSide f = file_fluid_side(s, model);
    model.air = std::make_unique<air::Problem>(model.air_mesh->mesh, f.fluid, f.boundaries,
                                               f.velocity_scale);
    f.set_inlet(*model.air);
    model.t_setup = MPI_Wtime() - t;
    return model;
  }
  if (load == "air")
  {
    // The air alone, about a rigid eye or none.
    model.air_mesh = make_air_mesh(comm, s);
    model.t_mesh = MPI_Wtime() - t;
    t = MPI_Wtime();
    const air::Fluid fluid = air_fluid(s);
    model.air = std::make_unique<air::Problem>(
        model.air_mesh->mesh, fluid, air_boundaries(model.air_mesh->mesh, true),
        std::max(s.real("air.inlet_velocity"), 1.0));
    set_air_inlet(*model.air, s, model.air_mesh->domain);
    model.t_setup = MPI_Wtime() - t;
    return model;
  }
  {
    GmshSession gmsh_session;
    if (load == "fsi")
    {
      if (model.eye)
      {
        auto [setup, air] = eye_and_air(comm, s);
        model.setup = std::move(setup);
        model.air_mesh = std::move(air);
      }
      else
        model.setup = file_mesh(comm, s, &model.air_mesh);
    }
    else
      model.setup = model.eye ? eye_mesh(comm, s) : file_mesh(comm, s);
  }
  MeshSetup& m = model.setup;
  if (s.string("support.model") == "springs")
    m.boundaries.support = solid::Support{s.real("support.stiffness"), s.real("support.damping")};
  for (auto& p : s.points("output.probes"))
  {
    m.probes.push_back(p);
    m.probe_names.push_back("probe_" + std::to_string(m.probe_names.size()));
  }
  model.t_mesh = MPI_Wtime() - t;

  t = MPI_Wtime();
  std::map<std::string, solid::Material> materials;
  for (auto& [tag, part] : m.parts)
    materials[part] = solid::read_material(s, part);
  model.problem = std::make_unique<solid::Problem>(
      m.mesh,
      solid::Element{s.integer("fem.degree"), s.string("fem.quadrature") == "reduced",
                     s.string("fem.formulation") == "mixed"},
      m.parts, materials, m.fibres, m.boundaries, m.volume_origin);
  if (load == "fsi")
    add_fsi(s, model, model.eye ? eye_fluid_side(s, model) : file_fluid_side(s, model));
  model.t_setup = MPI_Wtime() - t;
  return model;
}

} // namespace nct
