#include "run/run.h"

#include <cmath>
#include <cstdio>
#include <gmsh.h>
#include <sstream>

#include <dolfinx/common/log.h>
#include <dolfinx/fem/utils.h>
#include <dolfinx/la/petsc.h>

#include "eye/geometry.h"
#include "io/output.h"
#include "meshio/model.h"
#include "solid/problem.h"
#include "solver/newton.h"

namespace nct
{
namespace
{

constexpr double mmHg = 1.333224e-4; // MPa

std::string format(const char* fmt, auto... args)
{
  char buf[512];
  std::snprintf(buf, sizeof buf, fmt, args...);
  return buf;
}

/// Everything a scene's mesh brings: the distributed mesh, its parts and
/// boundaries, how fibres are laid, where volumes and probes are taken.
struct MeshSetup
{
  meshio::Tagged mesh;
  std::map<std::int32_t, std::string> parts;
  solid::Boundaries boundaries;
  solid::FibreRule fibres;
  std::array<double, 3> volume_origin;
  std::vector<std::array<double, 3>> probes;
  std::vector<std::string> probe_names;
  std::vector<std::string> cavity_names; ///< one per entry of boundaries.cavities
};

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
                          "boundary.surface_load"})
    for (auto& name : s.strings(key))
      surface_tag(groups, name, file, key);
}

MeshSetup eye_mesh(MPI_Comm comm, const scene::Scene& s)
{
  const eye::Geometry g = eye_geometry(s);
  const eye::Derived d = eye_derived(s);
  eye::Refinement r;
  r.layers = s.integer("mesh.layers");
  r.size_cornea = s.real("mesh.size_cornea");
  r.size_limbus = s.real("mesh.size_limbus");
  r.size_sclera = s.real("mesh.size_sclera");
  if (g.internal_structures)
    r.size_lens = s.real("mesh.size_lens");

  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  // Meshing runs on rank 0; what fails there stops every rank.
  std::string error, bad_input;
  if (rank == 0)
  {
    try
    {
      eye::build(g, r);
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
    throw std::runtime_error("meshing the eye failed: " + error);
  MeshSetup m{meshio::distribute(comm, meshio::extract(comm)), {}, {}, {}, {}, {}, {}, {}};
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

MeshSetup file_mesh(MPI_Comm comm, const scene::Scene& s)
{
  const std::string file = s.file().string();
  meshio::Groups groups = meshio::open(comm, s.path("mesh.file"));
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

  MeshSetup m{meshio::distribute(comm, meshio::extract(comm, s.real("mesh.size_max"))),
              {}, b, {}, {}, {}, {}, {}};
  if (!b.cavities.empty())
    m.cavity_names = {"cavity"};
  for (auto& [name, tag] : groups.volumes)
    m.parts[tag] = name;
  std::map<std::string, std::array<std::array<double, 3>, 2>> constant;
  for (auto& name : materials)
  {
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

nlohmann::json vec(const std::array<double, 3>& v) { return {v[0], v[1], v[2]}; }

} // namespace

Runtime::Runtime(const char* program)
{
  int argc = 1;
  char* argv[] = {const_cast<char*>(program), nullptr};
  char** pargv = argv;
  PetscInitialize(&argc, &pargv, nullptr, nullptr);
  dolfinx::init_logging(argc, pargv);
}

Runtime::~Runtime() { PetscFinalize(); }

void check(MPI_Comm comm, const scene::Scene& s)
{
  if (s.string("mesh.source") == "eye")
    eye_derived(s);
  else
  {
    GmshSession gmsh_session;
    check_file_groups(s, meshio::open(comm, s.path("mesh.file")));
  }
}

nlohmann::json run(MPI_Comm comm, const scene::Scene& s, const RunOptions& options)
{
  check(comm, s);
  const double t_start = MPI_Wtime();
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  io::RunFolder folder(comm, options.out);
  folder.write_text("scene.toml", s.to_toml());
  folder.log("nct: " + s.file().string() + " on " + std::to_string(ranks)
             + " rank(s) -> " + options.out.string());

  // Linear solver options: defaults, then the scene's, then the command line's.
  auto petsc = s.options("solver.petsc");
  petsc.insert(petsc.end(), options.petsc.begin(), options.petsc.end());
  solver::set_petsc_options(petsc);

  // Mesh
  double t = MPI_Wtime();
  const bool eye = s.string("mesh.source") == "eye";
  MeshSetup m = [&]
  {
    GmshSession gmsh_session;
    return eye ? eye_mesh(comm, s) : file_mesh(comm, s);
  }();
  for (auto& p : s.points("output.probes"))
  {
    m.probes.push_back(p);
    m.probe_names.push_back("probe_" + std::to_string(m.probe_names.size()));
  }
  const double t_mesh = MPI_Wtime() - t;

  // Problem
  t = MPI_Wtime();
  std::map<std::string, solid::Material> materials;
  for (auto& [tag, part] : m.parts)
    materials[part] = solid::read_material(s, part);
  const int degree = s.integer("fem.degree");
  solid::Problem problem(m.mesh, degree, s.string("fem.quadrature") == "reduced", m.parts, materials, m.fibres, m.boundaries,
                         m.volume_origin);
  dolfinx::la::petsc::Matrix A(problem.create_matrix(), false);
  solver::Newton newton(comm, A.mat());
  const double t_setup = MPI_Wtime() - t;

  const std::int64_t cells = m.mesh.mesh->topology().index_map(3)->size_global();
  folder.log(format("mesh: %lld tetrahedra, degree %d, %lld dofs (%.2f s); setup %.2f s",
                    (long long)cells, degree, (long long)problem.dofs(), t_mesh, t_setup));

  const solver::NewtonSettings settings{
      s.integer("solver.max_iterations"), s.real("solver.rtol"), s.real("solver.atol"),
      s.string("solver.line_search") == "energy", s.string("solver.jacobian") == "reuse"};
  const double iop = s.real("loading.iop"), surface = s.real("loading.surface_pressure");
  const int steps = s.integer("loading.steps"), max_cuts = s.integer("solver.max_step_cuts");

  // Output of one state
  double t_output = 0;
  io::Fields fields(folder, m.mesh.mesh, problem.coordinate_space());
  auto write_fields = [&](double time)
  {
    if (!s.boolean("output.fields"))
      return;
    double t0 = MPI_Wtime();
    problem.update_von_mises();
    fields.write(*problem.u, time);
    fields.write(*problem.von_mises, time);
    t_output += MPI_Wtime() - t0;
  };
  if (s.boolean("output.fields"))
  {
    fields.write(*problem.fields.at("fibre_1"), 0.0);
    fields.write(*problem.fields.at("fibre_2"), 0.0);
  }
  write_fields(0.0);

  nlohmann::json summary;
  summary["scene"] = s.file().string();
  summary["ranks"] = ranks;
  summary["cells"] = cells;
  summary["dofs"] = problem.dofs();
  summary["degree"] = degree;
  summary["symmetry_factor"] = problem.symmetry_factor();
  {
    auto volumes = problem.cavity_volumes();
    for (std::size_t c = 0; c < volumes.size(); ++c)
      summary[m.cavity_names[c] + "_volume_reference_mm3"] = volumes[c];
  }
  nlohmann::json& history = summary["steps"] = nlohmann::json::array();

  // Load ramp with step cutting: a failed step is retried at half the
  // increment; after two successes the increment doubles back.
  dolfinx::la::Vector<double> saved(*problem.u->x());
  double done = 0, increment = 1.0 / steps;
  int cuts = 0, consecutive_cuts = 0, successes = 0, newton_total = 0;
  auto finish = [&](const std::string& status)
  {
    summary["status"] = status;
    summary["newton_iterations"] = newton_total;
    summary["linear_solves"] = newton.timings.linear_solves;
    summary["jacobians"] = newton.timings.jacobians;
    summary["step_cuts"] = cuts;
    summary["wall_s"] = MPI_Wtime() - t_start;
    summary["timings_s"] = {{"mesh", t_mesh},
                            {"setup", t_setup},
                            {"assemble", newton.timings.assemble},
                            {"linear_solve", newton.timings.solve},
                            {"output", t_output}};
    folder.write_text("summary.json", summary.dump(2) + "\n");
  };
  while (done < 1.0 - 1e-12)
  {
    const double target = std::min(1.0, done + increment);
    problem.set_pressures(std::vector<double>(m.cavity_names.size(), target * iop * mmHg),
                          target * surface * mmHg);
    const double t_step = MPI_Wtime();
    auto report = newton.solve(
        *problem.u->x(), [&](auto& b) { problem.residual(b); },
        [&](Mat J) { problem.jacobian(J); }, settings);
    newton_total += report.iterations;
    if (!report.converged)
    {
      std::string residuals;
      for (double r : report.residuals)
        residuals += format(" %.3e", r);
      folder.log(format("  load %.4f: Newton failed after %d iterations: %s; residuals:%s",
                        target, report.iterations, report.reason.c_str(),
                        residuals.c_str()));
      std::copy(saved.array().begin(), saved.array().end(),
                problem.u->x()->mutable_array().begin());
      ++cuts;
      if (++consecutive_cuts > max_cuts)
      {
        std::string msg = format(
            "inflation diverged: load fraction %.6f (IOP %.3f mmHg) failed after %d "
            "step cuts (solver.max_step_cuts); last Newton: %s; residuals:%s",
            target, target * iop, max_cuts, report.reason.c_str(), residuals.c_str());
        summary["error"] = msg;
        finish("failed");
        throw Diverged(msg);
      }
      increment /= 2;
      successes = 0;
      continue;
    }
    done = target;
    consecutive_cuts = 0;
    std::copy(problem.u->x()->array().begin(), problem.u->x()->array().end(),
              saved.mutable_array().begin());
    if (++successes >= 2 && increment < 1.0 / steps)
      increment = std::min(2 * increment, 1.0 / steps), successes = 0;

    const auto volumes = problem.cavity_volumes();
    auto probes = problem.displacement_at(m.probes);
    nlohmann::json step = {{"load_fraction", done},
                           {"iop_mmHg", done * iop},
                           {"surface_pressure_mmHg", done * surface},
                           {"newton_iterations", report.iterations},
                           {"residual_N", report.residuals.back()}};
    std::string volume_text;
    for (std::size_t c = 0; c < volumes.size(); ++c)
    {
      step[m.cavity_names[c] + "_volume_mm3"] = volumes[c];
      step[m.cavity_names[c] + "_pressure_mmHg"] = done * iop;
      volume_text += format("  V_%s %.4f mm3", m.cavity_names[c].c_str(), volumes[c]);
    }
    for (std::size_t i = 0; i < probes.size(); ++i)
      step[m.probe_names[i] + "_displacement_mm"] = vec(probes[i]);
    history.push_back(step);
    write_fields(done);
    folder.log(format("step %3zu  load %.4f  IOP %7.3f mmHg  newton %2d  |R| %.2e  "
                      "%s u %+.5f %+.5f %+.5f mm%s  wall %.2f s",
                      history.size(), done, done * iop, report.iterations,
                      report.residuals.back(), m.probe_names[0].c_str(), probes[0][0],
                      probes[0][1], probes[0][2], volume_text.c_str(),
                      MPI_Wtime() - t_step));
  }

  const auto& last = history.back();
  if (eye)
    summary["apex_displacement_mm"] = last["apex_displacement_mm"][1];
  summary["iop_mmHg"] = iop;
  for (const auto& name : m.cavity_names)
    summary[name + "_volume_mm3"] = last[name + "_volume_mm3"];
  finish("converged");
  folder.log(format("done: %zu load steps, %d Newton iterations, %d step cuts; assemble "
                    "%.2f s, linear solve %.2f s, output %.2f s, total %.2f s",
                    history.size(), newton_total, cuts, newton.timings.assemble,
                    newton.timings.solve, t_output, summary["wall_s"].get<double>()));
  return summary;
}

} // namespace nct
