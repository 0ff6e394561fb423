// A scene read once: its keys (declared by the blocks' visit functions),
// their values, the checks no single key can make and those of the files
// the scene names, every problem reported at once.
#include "settings/settings.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <set>

#include <dolfinx/common/MPI.h>

#include "air/inlet.h"
#include "io/format.h"

namespace nct
{
namespace
{

/// The declared parts of [material.<part>] ("*": the rest).
const std::vector<std::string> declared_parts = {
    "cornea",      "limbus", "sclera", "lens_cortex", "lens_nucleus", "zonule",
    "vitreous_membrane", "*"};

/// The key a geometry's message starts with ("geometry.x = 3 is impossible").
std::string leading_key(const std::string& message)
{
  const auto end = message.find(' ');
  return message.substr(0, end);
}

using Errors = scene::Errors;
using Load = PuffSettings::Load;

/// A 2D section's keys: what it has (an axis) and what it cannot have
/// (points off its plane, a closed plane cavity).
void check_section(const scene::Scene& scene, const Settings& s, Errors& e)
{
  auto at = [&](const std::string& key, const std::string& what) { e.at(scene, key, what); };
  const section::Dimension d = s.mesh.dimension;
  const std::string name = "mesh.dimension = \"" + section::name(d) + "\"";
  if (d != section::Dimension::axisymmetric && !s.mesh.boundary.axis.empty())
    at("boundary.axis", "key 'boundary.axis': only an axisymmetric section has an axis; "
                        "the model is " + name);
  if (d == section::Dimension::three)
    return;
  if (s.mesh.eye() && d == section::Dimension::plane)
    at("mesh.dimension", "key 'mesh.dimension': the idealised eye is a body of revolution: "
                         "its section is \"axisymmetric\"; \"plane\" needs a file mesh");
  if (d == section::Dimension::plane && s.solid.cavity.closed
      && !s.mesh.boundary.cavity_wall.empty())
    at("cavity.model", "key 'cavity.model': a plane section's cavity is a prism of infinite "
                       "length, whose volume means nothing: \"closed\" needs an axisymmetric "
                       "section; a plane one takes \"constant_pressure\"");
  auto off_plane = [&](const std::string& key, const std::array<double, 3>& p, bool axis)
  {
    if (p[2] != 0)
      at(key, "key '" + key + "': a point of a 2D section lies in its plane z = 0, got z = "
                  + std::to_string(p[2]));
    else if (axis && p[0] != 0)
      at(key, "key '" + key + "': an axisymmetric cavity's volume is taken about a point on "
                  "the axis x = 0, got x = " + std::to_string(p[0]));
  };
  for (const auto& p : s.solid.probes)
    off_plane("output.probes", p, false);
  for (const auto& p : s.solid.cavity.origin)
    off_plane("cavity.origin", p, d == section::Dimension::axisymmetric);
}

/// Cross-checks of the settings that no single key can make: contradictory
/// effects, missing files.
/// One part's material: its law where it may be, its fibres, its Prony terms.
void check_material(const scene::Scene& scene, const std::string& part, const solid::Material& m,
                    bool eye, Errors& e)
{
  auto at = [&](const std::string& key, const std::string& what) { e.at(scene, key, what); };
  if (eye && m.law == solid::Law::fluid)
    at("material." + part + ".model",
       "key 'material." + part + ".model': \"fluid\" is for a file mesh's volume groups; the "
       "eye's air is the nozzle's (puff.load = \"air\" or \"fsi\")");
  if (m.fibre_directions.size() > 2)
    at("material." + part + ".fibre_directions",
       "key 'material." + part + ".fibre_directions': at most two fibre families");
  for (const auto& d : m.fibre_directions)
    if (std::hypot(d[0], d[1], d[2]) == 0)
      at("material." + part + ".fibre_directions",
         "key 'material." + part + ".fibre_directions': a zero vector has no direction");
  const std::string visco = "material." + part + ".viscoelasticity.";
  if (e.refused(visco + "relative_moduli") || e.refused(visco + "relaxation_times"))
    return; // already said
  if (m.relative_moduli.size() != m.relaxation_times.size())
    at(visco + "relaxation_times",
       "key '" + visco + "relaxation_times': one relaxation time per relative modulus ("
           + std::to_string(m.relative_moduli.size()) + " moduli, "
           + std::to_string(m.relaxation_times.size()) + " times)");
  else if (m.relative_moduli.size() > solid::max_prony_terms)
    at(visco + "relative_moduli", "key '" + visco + "relative_moduli': at most "
                                      + std::to_string(solid::max_prony_terms)
                                      + " Prony terms");
  if (!m.relative_moduli.empty() && m.law != solid::Law::hgo
      && m.law != solid::Law::neo_hookean)
    at(visco + "relative_moduli", "key '" + visco + "relative_moduli': the matrix relaxes in "
                                      "the hgo and neo_hookean laws only");
}

/// [cavity]'s humor (cavity.humor_inertia) against the rest of the scene.
void check_humor(const scene::Scene& scene, const Settings& s, Errors& e)
{
  const bool eye = s.mesh.eye();
  const Load load = s.puff.load;
  auto at = [&](const std::string& key, const std::string& what) { e.at(scene, key, what); };

  using HumorInertia = CavitySettings::HumorInertia;
  const HumorInertia humor = s.solid.cavity.humor_inertia;
  std::string humor_name = "\"";
  humor_name.append(scene.string("cavity.humor_inertia")).append("\"");
  const bool open_humor = !s.mesh.boundary.humor_open.empty();
  if (humor != HumorInertia::none && !s.solid.cavity.closed && !open_humor)
    at("cavity.humor_inertia", "key 'cavity.humor_inertia': " + humor_name + " moves an "
                               "incompressible humor, which needs cavity.model = \"closed\"" +
                               (humor == HumorInertia::flow
                                    ? std::string(" (or, open to a far field, boundary.humor_open)")
                                    : std::string()));
  if (open_humor && s.solid.cavity.closed)
    at("boundary.humor_open", "key 'boundary.humor_open': an open humor does not hold its "
                              "volume; it needs cavity.model = \"constant_pressure\"");
  if (humor != HumorInertia::none && !eye && s.mesh.boundary.cavity_wall.empty())
    at("cavity.humor_inertia", "key 'cavity.humor_inertia': " + humor_name + " needs a cavity, "
                               "but boundary.cavity_wall names no group");
  const bool meshed = humor == HumorInertia::flow || humor == HumorInertia::navier_stokes;
  if (meshed && eye && s.mesh.dimension == section::Dimension::plane)
    at("cavity.humor_inertia", "key 'cavity.humor_inertia': " + humor_name + " needs the humor's mesh, "
                               "which the idealised eye builds in 3D and on its axisymmetric "
                               "section, not on a plane one; or \"translation\"");
  if (meshed && eye && s.mesh.dimension == section::Dimension::three
      && s.mesh.geometry.internal_structures)
    at("cavity.humor_inertia", "key 'cavity.humor_inertia': " + humor_name + " in 3D meshes the "
                               "humor without the internal structures only (with them: "
                               "mesh.dimension = \"axisymmetric\", or \"translation\")");
  if (humor == HumorInertia::navier_stokes && eye && s.mesh.dimension == section::Dimension::three)
    at("cavity.humor_inertia", "key 'cavity.humor_inertia': \"navier_stokes\" is the flow "
                               "model's check on the axisymmetric section (mesh.dimension = "
                               "\"axisymmetric\")");
  if (meshed && !eye && s.solid.cavity.humor_groups.empty())
    at("cavity.humor_groups", "key 'cavity.humor_groups': cavity.humor_inertia = " + humor_name
                                  + " needs the humor's volume groups, but it names none");
  // The humor as Navier-Stokes: one fluid coupled at a time, its volume
  // held by its incompressibility, its lid (an eye's cut) a wall at rest.
  if (humor == HumorInertia::navier_stokes && !s.puff.prescribed() && load != Load::none)
    at("cavity.humor_inertia", "key 'cavity.humor_inertia': \"navier_stokes\" couples the "
                               "humor to the solid under a prescribed puff (puff.load = "
                               "\"gaussian\", \"pulse\" or \"table\"); with the air coupled "
                               "too (\"fsi\") the model is \"flow\"");
  if (humor == HumorInertia::navier_stokes && eye && s.mesh.geometry.internal_structures)
    at("cavity.humor_inertia", "key 'cavity.humor_inertia': \"navier_stokes\" meshes one "
                               "chamber; with the internal structures (two) the model is "
                               "\"flow\"");
  if (humor == HumorInertia::navier_stokes && open_humor)
    at("boundary.humor_open", "key 'boundary.humor_open': \"navier_stokes\" models a closed "
                              "humor only");
  if (humor == HumorInertia::navier_stokes && eye && s.solid.support.springs)
    at("support.model", "key 'support.model': cavity.humor_inertia = \"navier_stokes\" "
                        "needs the cut clamped (\"clamped\"): the humor's lid across the cut is "
                        "then a wall at rest; the lid moving with the eye is the \"flow\" "
                        "model's");
}

/// A file mesh's groups, materials and fluid (mesh.source = "file").
void check_file_mesh(const scene::Scene& scene, const Settings& s, Errors& e)
{
  const Load load = s.puff.load;
  auto at = [&](const std::string& key, const std::string& what) { e.at(scene, key, what); };
  const auto fluids = s.fluid_parts();
  const auto& b = s.mesh.boundary;
  if (s.mesh.file.empty())
    at("mesh.file", "key 'mesh.file': mesh.source = \"file\" needs a mesh file");
  else
  {
    std::error_code ec; // e.g. a name too long
    const std::string ext = s.mesh.file.extension().string();
    if (!std::filesystem::is_regular_file(s.mesh.file, ec))
      at("mesh.file", "key 'mesh.file': file '" + scene.string("mesh.file")
                          + "' not found (looked for " + s.mesh.file.string() + ")");
    else if (ext != ".msh" && ext != ".geo")
      at("mesh.file", "key 'mesh.file': '" + ext + "' files are not read; accepted: .msh, .geo");
    else if (ext == ".msh" && s.mesh.size_max > 0)
      at("mesh.size_max", "key 'mesh.size_max' applies when nct meshes a .geo; '"
                              + scene.string("mesh.file") + "' is already meshed");
  }
  if (s.materials.empty())
    at("material", "key 'material': a file mesh needs a [material.<group>] table per volume "
                   "group");
  // A fluid part is the coupled run's fluid, and that needs one.
  const bool flow = load == Load::fsi || load == Load::air;
  if (load == Load::fsi && fluids.empty())
    at("puff.load", "key 'puff.load': \"fsi\" on a file mesh needs a fluid volume group (a "
                    "[material.<group>] with model = \"fluid\")");
  if (!flow && !fluids.empty())
    at("material." + fluids[0] + ".model",
       "key 'material." + fluids[0] + ".model': a fluid part exists only in a run of the fluid "
       "(puff.load = \"fsi\" with a solid, \"air\" alone)");
  if (load == Load::fsi && !fluids.empty() && fluids.size() == s.materials.size())
    at("material", "key 'material': every volume group is fluid; the coupled run needs a solid "
                   "(the fluid alone: puff.load = \"air\")");
  const std::vector<std::pair<const char*, const std::vector<std::string>*>> groups
      = {{"fixed", &b.fixed},   {"symmetry", &b.symmetry}, {"axis", &b.axis},
         {"cavity_wall", &b.cavity_wall}, {"humor_open", &b.humor_open},
         {"press", &b.press},   {"inlet", &b.inlet},       {"outlet", &b.outlet},
         {"wall", &b.wall},     {"interface", &b.interface}};
  if (!flow)
    for (const auto& [name, list] : {std::pair{"inlet", &b.inlet}, std::pair{"outlet", &b.outlet},
                                     std::pair{"wall", &b.wall}, std::pair{"interface", &b.interface}})
      if (!list->empty())
        at(std::string("boundary.") + name,
           std::string("key 'boundary.") + name + "': a fluid boundary; it needs a fluid part "
           "and puff.load = \"fsi\" or \"air\"");
  if (load == Load::air && !b.interface.empty())
    at("boundary.interface", "key 'boundary.interface': the fluid alone (puff.load = \"air\") "
                             "has no interface");
  // A group has one boundary condition.
  std::map<std::string, std::string> owner;
  for (const auto& [name, list] : groups)
    for (const std::string& g : *list)
    {
      auto [it, fresh] = owner.emplace(g, name);
      if (!fresh)
        at(std::string("boundary.") + name, "group '" + g + "' is in both boundary."
                                                 + it->second + " and boundary." + name
                                                 + ": a facet group has one condition");
    }
  if (s.solid.cavity.iop > 0 && b.cavity_wall.empty() && load != Load::air)
    at("inflate.iop", "key 'inflate.iop' > 0 but boundary.cavity_wall names no group");
  if (s.solid.press.pressure != 0 && b.press.empty())
    at("press.pressure", "key 'press.pressure' != 0 but boundary.press names no group");
  if (!flow && load != Load::none && b.press.empty())
    at("puff.load", "key 'puff.load' is not \"none\" but boundary.press names no group");
  // The inlet of a file mesh's fluid.
  const auto& in = s.air.inlet;
  if (flow && in.profile == InletSettings::Profile::parabolic && !in.circle
      && in.axes.size() != 2)
    at("inlet.axes", "key 'inlet.axes': two directions across the rectangle, got "
                         + std::to_string(in.axes.size()));
  for (const auto& [key, points] :
       {std::pair{"inlet.direction", &in.direction}, std::pair{"inlet.axes", &in.axes}})
    for (const auto& d : *points)
      if (flow && std::hypot(d[0], d[1], d[2]) == 0)
        at(key, std::string("key '") + key + "': a zero vector has no direction");
}

void check_consistency(const scene::Scene& scene, const Settings& s, Errors& e)
{
  const bool eye = s.mesh.eye();
  const Load load = s.puff.load;
  auto at = [&](const std::string& key, const std::string& what) { e.at(scene, key, what); };

  // The biomarkers need the deepest frame and its neighbours.
  if ((s.puff.prescribed() || load == Load::fsi) && s.puff.duration * s.puff.frame_rate < 2e3)
    at("puff.duration", "key 'puff.duration': " + std::to_string(s.puff.duration)
                            + " ms holds fewer than 3 frames at puff.frame_rate = "
                            + std::to_string(s.puff.frame_rate) + "/s; needs at least "
                            + std::to_string(2e3 / s.puff.frame_rate) + " ms");
  if (s.solver.ldlt && s.solver.newton.jacobian == solver::Jacobian::krylov)
    at("solver.factorisation", "key 'solver.factorisation': \"ldlt\" factorises the symmetric "
                               "part only, but solver.jacobian = \"krylov\" needs the Jacobian "
                               "itself: \"lu\"");
  if (s.solid.element.mixed && s.solid.element.degree != 2)
    at("fem.formulation", "key 'fem.formulation': \"mixed\" (P2/P0) needs fem.degree = 2, got "
                              + std::to_string(s.solid.element.degree));
  check_humor(scene, s, e);
  if (const auto& c = s.step_control; c.tolerance > 0)
  {
    if (load == Load::air)
      at("dynamics.tolerance", "key 'dynamics.tolerance': adaptive steps follow the solid's "
                               "error estimate, and puff.load = \"air\" moves no solid; "
                               "use 0 (fixed steps)");
    if (c.dt_max < s.dynamics.dt)
      at("dynamics.dt_max", io::format("key 'dynamics.dt_max': %g ms is shorter than the first "
                                       "step, dynamics.dt = %g ms; needs >= dynamics.dt",
                                       c.dt_max, s.dynamics.dt));
  }
  if (s.solid.support.springs && !eye && s.mesh.boundary.fixed.empty())
    at("support.model", "key 'support.model': \"springs\" act on boundary.fixed, which names "
                        "no group");
  if (eye && s.air.inlet.profile == InletSettings::Profile::table
      && (load == Load::air || load == Load::fsi))
    at("inlet.profile", "key 'inlet.profile': \"table\" gives a file mesh's inlet; the eye's "
                        "nozzle takes \"uniform\" or \"parabolic\"");
  if (load == Load::air && !eye)
    for (const auto& [part, m] : s.materials)
      if (m.law != solid::Law::fluid)
      {
        at("puff.load", "key 'puff.load': \"air\" on a file mesh is its fluid alone, but '"
                            + part + "' is a solid (material." + part
                            + ".model); the fluid and a solid run coupled: \"fsi\"");
        break;
      }
  for (const auto& [part, m] : s.materials)
    check_material(scene, part, m, eye, e);
  check_section(scene, s, e);
  if (!eye)
    check_file_mesh(scene, s, e);
}

/// The measured pulse's shape from puff.peak, rise_rate, fall_rate and
/// pulse_duration, or none (a problem added).
std::optional<puff::PulseShape> pulse_shape(const scene::Scene& scene, const PuffSettings& p,
                                            Errors& e)
{
  if (p.peak <= 0)
  {
    e.at(scene, "puff.peak", "key 'puff.peak': the pulse needs a positive peak, not "
                                 + std::to_string(p.peak) + " mmHg");
    return std::nullopt;
  }
  try
  {
    return puff::PulseShape::from_descriptors(p.rise_rate / p.peak, p.fall_rate / p.peak,
                                              p.pulse_duration);
  }
  catch (const std::invalid_argument& x)
  {
    e.at(scene, "puff.rise_rate", std::string("keys 'puff.rise_rate', 'puff.fall_rate', "
                                              "'puff.pulse_duration': ") + x.what());
    return std::nullopt;
  }
}

/// Read the CSV file a key names with `read` (which throws
/// std::invalid_argument naming the file and line); `needs`: why it must
/// be given. A problem at the key instead.
template <class Read>
void read_table(const scene::Scene& scene, Errors& e, const std::string& key,
                const std::filesystem::path& file, const std::string& needs, Read&& read)
{
  if (file.empty())
    e.at(scene, key, "key '" + key + "': " + needs);
  else
    try
    {
      read(file);
    }
    catch (const std::invalid_argument& x)
    {
      e.at(scene, key, "key '" + key + "': " + x.what());
    }
}

/// The puff's prescribed pressure and the measured pulse (a prescribed
/// pulse's, the nozzle's history's), a file mesh's inlet table: built, the
/// files read.
void build_puff(const scene::Scene& scene, const Settings& s, Built& built, Errors& e)
{
  const PuffSettings& p = s.puff;
  const bool nozzle_pulse = s.mesh.eye() && (p.load == Load::air || p.load == Load::fsi)
                            && s.air.inlet.pulse;
  if (p.load == Load::pulse || nozzle_pulse)
    built.pulse = pulse_shape(scene, p, e);
  if (p.load == Load::gaussian)
    built.puff_pressure
        = std::make_shared<puff::Gaussian>(p.peak, p.peak_time, p.width_t, p.width_r);
  if (p.load == Load::pulse)
    read_table(scene, e, "puff.profile", p.profile,
               "puff.load = \"pulse\" needs a CSV file (r_mm,p_mmHg)", [&](const auto& file) {
                 auto profile = puff::RadialProfile::read(file);
                 if (built.pulse)
                   built.puff_pressure
                       = std::make_shared<puff::Pulse>(p.peak, *built.pulse, std::move(profile));
               });
  if (p.load == Load::table)
    read_table(scene, e, "puff.table", p.table,
               "puff.load = \"table\" needs a CSV file (t_ms,r_mm,p_mmHg)",
               [&](const auto& file)
               { built.puff_pressure = std::make_shared<puff::Table>(puff::Table::read(file)); });
  const auto& in = s.air.inlet;
  if (!s.mesh.eye() && (p.load == Load::air || p.load == Load::fsi)
      && in.profile == InletSettings::Profile::table)
    read_table(scene, e, "inlet.table", in.table,
               "inlet.profile = \"table\" needs a CSV file (x_mm,y_mm,z_mm,u_m_s)",
               [&](const auto& file) { built.inlet_table = air::Inlet::read_table(file); });
}

/// A file mesh's dimension and extent against mesh.dimension: a section
/// lies in z = 0, an axisymmetric one in x >= 0 with its axis named.
void check_section_mesh(const scene::Scene& scene, const Settings& s,
                        const meshio::Groups& groups, Errors& e)
{
  const std::string mesh_file = scene.string("mesh.file");
  const section::Dimension d = s.mesh.dimension;
  const std::string name = "mesh.dimension = \"" + section::name(d) + "\"";
  if (groups.dimension != section::mesh_dimension(d))
  {
    e.at(scene, "mesh.dimension", "key 'mesh.dimension': " + name + " needs a "
                                      + (d == section::Dimension::three ? "3D" : "2D")
                                      + " mesh, but " + mesh_file + " is "
                                      + std::to_string(groups.dimension) + "D");
    return;
  }
  if (d == section::Dimension::three)
    return;
  const auto& x = groups.bounds;
  // OpenCASCADE widens its boxes by its tolerance (about 1e-7).
  const double size = std::max({x[3] - x[0], x[4] - x[1], 1e-300}), tol = 1e-6 * size;
  if (x[2] < -tol || x[5] > tol)
    e.at(scene, "mesh.file", "key 'mesh.file': a 2D section lies in the plane z = 0, but "
                                 + mesh_file + " spans z from " + std::to_string(x[2]) + " to "
                                 + std::to_string(x[5]));
  if (d != section::Dimension::axisymmetric)
    return;
  if (x[0] < -tol)
    e.at(scene, "mesh.file", "key 'mesh.file': an axisymmetric section lies in r = x >= 0, but "
                                 + mesh_file + " reaches x = " + std::to_string(x[0]));
  else if (x[0] <= tol && s.mesh.boundary.axis.empty())
    e.at(scene, "boundary.axis", "key 'boundary.axis': " + mesh_file + " touches the axis "
                                     "r = x = 0; name the facet group that lies on it "
                                     "(u_r = 0 there)");
}

/// An external mesh's groups against the scene's materials and boundaries.
void check_file_groups(const scene::Scene& scene, const Settings& s, const meshio::Groups& groups,
                       Errors& e)
{
  const std::string mesh_file = scene.string("mesh.file");
  auto at = [&](const std::string& key, const std::string& what) { e.at(scene, key, what); };
  const auto& humor = s.solid.cavity.humor_groups;
  auto is_humor = [&](const std::string& name)
  { return std::find(humor.begin(), humor.end(), name) != humor.end(); };
  for (auto& [name, tag] : groups.volumes)
    if (!s.materials.count(name) && !is_humor(name))
      at("mesh.file", "volume group '" + name + "' of " + mesh_file + " has no [material." + name
                          + "] table");
  for (auto& name : humor)
  {
    if (!groups.volumes.count(name))
      at("cavity.humor_groups", "key 'cavity.humor_groups': the mesh has no volume group '"
                                    + name + "'");
    if (s.materials.count(name))
      at("material." + name + ".model", "key 'material." + name + "': volume group '" + name
                                            + "' is the humor (cavity.humor_groups), not a solid");
  }
  for (auto& [name, m] : s.materials)
    if (!groups.volumes.count(name))
      at("material." + name + ".model",
         "key 'material." + name + "': the mesh has no volume group '" + name + "'");
  std::string known;
  for (auto& [n, t] : groups.surfaces)
    known += (known.empty() ? "" : ", ") + n;
  const auto& b = s.mesh.boundary;
  check_section_mesh(scene, s, groups, e);
  for (const auto& [key, list] :
       std::vector<std::pair<std::string, const std::vector<std::string>*>>{
           {"boundary.fixed", &b.fixed},
           {"boundary.symmetry", &b.symmetry},
           {"boundary.axis", &b.axis},
           {"boundary.cavity_wall", &b.cavity_wall},
           {"boundary.humor_open", &b.humor_open},
           {"boundary.press", &b.press},
           {"boundary.inlet", &b.inlet},
           {"boundary.outlet", &b.outlet},
           {"boundary.wall", &b.wall},
           {"boundary.interface", &b.interface},
           {"output.force_on", &s.air.force_on}})
    for (auto& name : *list)
      if (!groups.surfaces.count(name)
          && !(name == "interface" && key == "output.force_on" && b.interface.empty()))
        at(key, "key '" + key + "': the mesh has no surface group '" + name + "' (it has: "
                    + known + ")");
  const auto fluids = s.fluid_parts();
  if (fluids.empty())
    return;
  // Each boundary on the side its physics lives on (where the geometry
  // tells the sides: a .geo, or a .msh with its entities).
  auto is_fluid = [&](const std::string& v)
  { return std::find(fluids.begin(), fluids.end(), v) != fluids.end(); };
  auto side_check = [&](const char* key, const std::vector<std::string>& names, bool fluid_side,
                        const char* what)
  {
    for (auto& name : names)
    {
      auto it = groups.sides.find(name);
      if (it == groups.sides.end())
        continue;
      for (auto& v : it->second)
        if (is_fluid(v) != fluid_side && it->second.size() == 1)
          at(key, std::string("key '") + key + "': surface group '" + name + "' bounds the "
                      + (fluid_side ? "solid" : "fluid") + " volume group '" + v + "' only; "
                      + what);
    }
  };
  side_check("boundary.inlet", b.inlet, true, "an inlet must bound a fluid group");
  side_check("boundary.outlet", b.outlet, true, "an outlet must bound a fluid group");
  side_check("boundary.wall", b.wall, true, "a wall must bound a fluid group");
  side_check("boundary.fixed", b.fixed, false, "a clamp must bound a solid group");
  for (auto& name : b.interface)
  {
    auto it = groups.sides.find(name);
    if (it == groups.sides.end())
      continue;
    bool fluid = false, solid = false;
    for (auto& v : it->second)
      (is_fluid(v) ? fluid : solid) = true;
    if (!fluid || !solid)
      at("boundary.interface", "key 'boundary.interface': surface group '" + name + "' has no "
                                   + (fluid ? "solid" : "fluid")
                                   + " side; the interface lies between a fluid and a solid "
                                     "group");
  }
  double density = 0, viscosity = 0;
  for (auto& f : fluids)
  {
    const auto& m = s.materials.at(f);
    if (density > 0 && (m.density != density || m.viscosity != viscosity))
      at("material." + f + ".density", "key 'material." + f + "': the fluid groups must share "
                                       "one density and viscosity (one fluid)");
    density = m.density;
    viscosity = m.viscosity;
  }
  if (b.inlet.empty())
    at("boundary.inlet", "key 'boundary.inlet': the fluid needs an inlet group");
}

/// The checks that need more than the keys: the eye's geometry and its
/// air, a file mesh (opened, its groups against the scene). Collective.
void check_meshes(MPI_Comm comm, const scene::Scene& scene, const Settings& s, Built& built,
                  Errors& e)
{
  const Load load = s.puff.load;
  if (s.mesh.eye())
  {
    try
    {
      built.eye = eye::derive(s.mesh.geometry);
    }
    catch (const std::invalid_argument& x)
    {
      e.at(scene, leading_key(x.what()), x.what());
      return;
    }
    if (load == Load::air || load == Load::fsi)
      try
      {
        const bool with_eye = load == Load::fsi || s.air.rigid_eye;
        air::validate(s.air.domain, built.eye.apex_y, s.mesh.geometry.cut_y,
                      with_eye ? s.mesh.geometry.sclera_outer_radius : 0.0);
      }
      catch (const std::invalid_argument& x)
      {
        e.at(scene, leading_key(x.what()), x.what());
      }
    return;
  }
  // The .geo's constants are numbers.
  for (auto& [name, value] : s.mesh.parameters)
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
      e.at(scene, "mesh.parameters." + name, "key 'mesh.parameters." + name + "': got '" + value
                                                 + "'; expected a finite number");
    else
      built.geo_constants[name] = v;
  }
  for (const char* key : {"mesh.file", "mesh.size_max", "mesh.parameters"})
    if (e.refused(key))
      return;
  std::error_code ec;
  if (!std::filesystem::is_regular_file(s.mesh.file, ec))
    return; // said by the consistency check
  const std::string ext = s.mesh.file.extension().string();
  if (ext != ".msh" && ext != ".geo")
    return;
  try
  {
    built.file_mesh = std::make_shared<OpenMesh>(comm, s.mesh.file, built.geo_constants);
  }
  catch (const std::runtime_error& x) // every rank: open() broadcasts its error
  {
    e.at(scene, "mesh.file", std::string("key 'mesh.file': ") + x.what());
    return;
  }
  check_file_groups(scene, s, built.file_mesh->groups(), e);
}

} // namespace

OpenMesh::OpenMesh(MPI_Comm comm, const std::filesystem::path& file,
                   const std::map<std::string, double>& parameters)
    : _gmsh(std::make_unique<meshio::GmshSession>()),
      _groups(meshio::open(comm, file, parameters))
{
}

meshio::Model OpenMesh::extract(MPI_Comm comm, double size_max) const
{
  if (!_gmsh)
    throw std::logic_error("OpenMesh::extract: the mesh was extracted before");
  meshio::Model model = meshio::extract(comm, size_max);
  _gmsh.reset();
  return model;
}

std::vector<std::string> Settings::fluid_parts() const
{
  std::vector<std::string> fluids;
  if (!mesh.eye())
    for (const auto& [name, m] : materials)
      if (m.law == solid::Law::fluid)
        fluids.push_back(name);
  return fluids;
}

void visit(scene::Visitor& v, Settings& s)
{
  visit(v, s.mesh);
  v.tables("material", declared_parts,
           [&](const std::string& part) { solid::visit(v, s.materials[part], part); });
  visit(v, s.solid);
  dynamics::visit(v, s.dynamics);
  dynamics::visit(v, s.step_control);
  visit(v, s.puff);
  visit(v, s.air);
  mesh_motion::visit(v, s.mesh_motion);
  visit(v, s.fsi);
  visit(v, s.solver);
  visit(v, s.checkpoint);
  visit(v, s.output);
}

Input read(MPI_Comm comm, const std::filesystem::path& file,
           const std::vector<std::string>& overrides)
{
  scene::Errors errors(file);
  scene::Scene scene = scene::Scene::load(file, overrides, errors);
  Settings s;
  scene::Reader reader(scene);
  visit(reader, s);
  s.materials.erase("*"); // declared only
  s.solid.element.dimension = s.mesh.dimension;
  check_consistency(scene, s, errors);
  Built built;
  build_puff(scene, s, built, errors);
  check_meshes(comm, scene, s, built, errors);
  errors.raise();
  if (dolfinx::MPI::rank(comm) == 0)
    for (const std::string& note : scene.notes())
      std::cerr << "note: " << note << "\n";
  return {std::move(scene), std::move(s), std::move(built)};
}

} // namespace nct

namespace nct::scene
{

const std::vector<Key>& keys()
{
  static const std::vector<Key> all = []
  {
    Declarer d;
    Settings s;
    visit(d, s);
    return d.keys;
  }();
  return all;
}

} // namespace nct::scene
