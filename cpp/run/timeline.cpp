#include "run/timeline.h"

#include <cmath>
#include <set>

#include "io/format.h"

namespace nct
{
namespace
{

constexpr double mmHg = 1.333224e-4; // MPa
using io::format;

nlohmann::json vec(const std::array<double, 3>& v) { return {v[0], v[1], v[2]}; }

} // namespace

SolidOutput::SolidOutput(const scene::Scene& scene, io::RunFolder& folder, Model& model,
                         nlohmann::json& steps, const std::vector<std::array<double, 3>>& probes,
                         double t0, const nlohmann::json* fields)
    : _scene(scene), _folder(folder), _model(model), _steps(steps),
      _probes(*model.problem, probes),
      _fields(folder, model.setup.mesh.mesh, model.problem->coordinate_space()),
      _t_step(MPI_Wtime())
{
  if (fields)
    _fields.resume(*fields);
  else if (scene.boolean("output.fields"))
  {
    _fields.write(*model.problem->fields.at("fibre_1"), t0);
    _fields.write(*model.problem->fields.at("fibre_2"), t0);
  }
  if (!fields)
    write_fields(t0);
}

void SolidOutput::write_fields(double time)
{
  if (!_scene.boolean("output.fields"))
    return;
  const double t = MPI_Wtime();
  _model.problem->update_von_mises();
  _fields.write(*_model.problem->u, time);
  _fields.write(*_model.problem->von_mises, time);
  t_output += MPI_Wtime() - t;
}

const nlohmann::json& SolidOutput::step(nlohmann::json step, double time,
                                        const solver::NewtonReport& report,
                                        const biomarkers::Columns& cavities,
                                        const std::string& extra)
{
  const auto& names = _model.setup.probe_names;
  const auto u = _probes.displacement();
  step["time"] = time;
  step["newton_iterations"] = report.iterations;
  step["residual_N"] = report.residuals.back();
  step["newton_residuals"] = report.residuals;
  std::string text;
  for (std::size_t c = 0; 2 * c < cavities.size(); ++c)
    text += format("  %s %.3f mmHg %.4f mm3", _model.setup.cavity_names[c].c_str(),
                   cavities[2 * c].second, cavities[2 * c + 1].second);
  for (const auto& [name, value] : cavities)
    step[name] = value;
  for (std::size_t i = 0; i < u.size(); ++i)
    step[names[i] + "_displacement_mm"] = vec(u[i]);
  _steps.push_back(step);
  write_fields(time);
  if (!u.empty())
    text = format("  %s u %+.5f %+.5f %+.5f mm", names[0].c_str(), u[0][0], u[0][1], u[0][2])
           + text;
  _folder.log(format("step %3zu  %-7s t %+8.4f  newton %2d  |R| %.2e%s%s  wall %.2f s",
                     _steps.size(), step["phase"].get<std::string>().c_str(), time,
                     report.iterations, report.residuals.back(), text.c_str(), extra.c_str(),
                     MPI_Wtime() - _t_step));
  _t_step = MPI_Wtime();
  return _steps.back();
}

solver::NewtonSettings newton_settings(const scene::Scene& s)
{
  solver::NewtonSettings n;
  n.max_iterations = s.integer("solver.max_iterations");
  n.rtol = s.real("solver.rtol");
  n.atol = s.real("solver.atol");
  n.increment_tol = s.real("solver.increment_tol");
  n.line_search = s.string("solver.line_search") == "energy";
  const std::string jacobian = s.string("solver.jacobian");
  n.jacobian = jacobian == "reuse"    ? solver::Jacobian::reuse
               : jacobian == "krylov" ? solver::Jacobian::krylov
                                      : solver::Jacobian::every_iteration;
  n.reuse_contraction = s.real("solver.reuse_contraction");
  n.reuse_iterations = s.integer("solver.reuse_iterations");
  n.anderson = s.integer("solver.anderson");
  n.krylov_refactorise = s.integer("solver.krylov_refactorise");
  n.max_growth = s.real("solver.max_growth");
  return n;
}

Stepper make_stepper(const scene::Scene& s, const solver::NewtonSettings& settings,
                     io::RunFolder& folder)
{
  return Stepper(settings, s.integer("solver.max_step_cuts"),
                 s.string("solver.predictor") == "extrapolate" ? Stepper::Predictor::extrapolate
                                                                : Stepper::Predictor::previous,
                 folder);
}

RunState::RunState(MPI_Comm comm, const scene::Scene& s, io::RunFolder& folder, Model& model,
                   std::vector<std::pair<std::string, std::string>> petsc)
    : comm(comm), scene(s), folder(folder), model(model),
      settings(newton_settings(s)),
      stepper(make_stepper(s, settings, folder)), wall_start(MPI_Wtime()),
      _petsc(std::move(petsc)), _last_checkpoint(wall_start)
{
  summary["scene"] = s.file().string();
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  summary["ranks"] = ranks;
  summary["steps"] = nlohmann::json::array();
  if (const int every = s.integer("checkpoint.steps"); every > 0)
  {
    if (model.problem)
      _mesh_as_built = io::mesh_fingerprint(*model.setup.mesh.mesh);
    if (model.air_mesh)
      _mesh_as_built += "; air " + io::mesh_fingerprint(*model.air_mesh->mesh.mesh);
    stepper.boundaries = {every, [this](const Stepper::MarchState& m) { checkpoint(m); }};
  }
  if (!model.problem)
    return;
  open.emplace(*model.problem);
  open_pressures.assign(model.problem->cavities(), 0.0);
  press_peak = s.real("press.pressure") * mmHg;
  press_profile = [](const auto&) { return 1.0; };
  if (s.string("press.profile") == "gaussian")
  {
    const double w = s.real("press.width");
    press_profile = [w](const std::array<double, 3>& x)
    { return std::exp(-(x[0] * x[0] + x[2] * x[2]) / (2 * w * w)); };
  }
  prescribed = puff_load(s);
  probes = model.setup.probes;
}

solver::Newton& RunState::newton(const std::string& name, const std::function<Mat()>& create,
                                 const std::string& prefix)
{
  auto [it, fresh] = _solvers.try_emplace(name);
  if (fresh)
  {
    it->second.A = std::make_unique<dolfinx::la::petsc::Matrix>(create(), false);
    it->second.newton = std::make_unique<solver::Newton>(comm, it->second.A->mat(), prefix);
    // Resumed: the counts and times of the run before.
    if (auto before = _resumed_timings.find(name); before != _resumed_timings.end())
      it->second.newton->timings = before->second;
  }
  return *it->second.newton;
}

solver::Newton& RunState::solid_newton()
{
  // LDL^T (solver.factorisation): the upper triangle and MUMPS' LDL^T of
  // the symmetric matrix it stands for (the follower pressures' skew part
  // is left to the Newton iteration). A preconditioner named on the command
  // line other than a factorisation (--petsc "-pc_type gamg") wins over
  // it: the AIJ matrix PETSc's multigrids take, with the rigid-body modes.
  char pc_type[64] = "lu";
  PetscOptionsGetString(nullptr, nullptr, "-pc_type", pc_type, sizeof(pc_type), nullptr);
  const bool factorised = std::string(pc_type) == "lu" || std::string(pc_type) == "cholesky";
  const bool ldlt = factorised && scene.string("solver.factorisation") == "ldlt";
  const bool fresh = _solvers.find("solid") == _solvers.end();
  auto& n = newton("solid", [&]
                   { return model.problem->create_matrix(!factorised ? "aij" : ldlt ? "sbaij" : "baij"); });
  if (fresh && ldlt)
  {
    PC pc;
    KSPGetPC(n.ksp(), &pc);
    PCSetType(pc, PCCHOLESKY);
    PCFactorSetMatSolverType(pc, MATSOLVERMUMPS);
  }
  return n;
}

solver::Timings RunState::timings() const
{
  solver::Timings t;
  for (auto& [name, u] : solver_timings())
    t += u;
  return t;
}

std::map<std::string, solver::Timings> RunState::solver_timings() const
{
  std::map<std::string, solver::Timings> t = _resumed_timings;
  for (auto& [name, s] : _solvers)
    t[name] = s.newton->timings;
  return t;
}

solver::System RunState::solid_system() { return closed ? closed->system() : open->system(); }

void RunState::set_surface_load(double t)
{
  auto& problem = *model.problem;
  problem.set_surface_pressure(mmHg);
  const double press = press_peak / mmHg;
  problem.set_surface_profile(
      [&, t, press](const std::array<double, 3>& X)
      {
        const double air = t < 0 || !prescribed ? 0.0 : (*prescribed)(std::hypot(X[0], X[2]), t);
        return press * press_profile(X) + air;
      });
}

biomarkers::Columns RunState::cavity_state() const
{
  const auto volumes = model.problem->cavity_volumes();
  const auto& pressures = closed ? closed->pressures() : open_pressures;
  biomarkers::Columns state;
  for (std::size_t c = 0; c < volumes.size(); ++c)
  {
    state.push_back({model.setup.cavity_names[c] + "_pressure_mmHg", pressures[c] / mmHg});
    state.push_back({model.setup.cavity_names[c] + "_volume_mm3", volumes[c]});
  }
  return state;
}

SolidOutput& RunState::output()
{
  if (!_output)
  {
    const auto volumes = model.problem->cavity_volumes();
    for (std::size_t c = 0; c < volumes.size(); ++c)
      summary[model.setup.cavity_names[c] + "_volume_reference_mm3"] = volumes[c];
    for (std::size_t i = 0; i < probes.size(); ++i)
      summary["probe_reference_mm"][model.setup.probe_names[i]] = vec(probes[i]);
    _output.emplace(scene, folder, model, summary["steps"], probes, t0);
  }
  return *_output;
}

void RunState::quasi_static_step(const char* phase, double f, const solver::NewtonReport& report)
{
  output().step({{"phase", phase},
                 {"load_fraction", f},
                 {"surface_pressure_mmHg", surface_pressure / mmHg}},
                t0 + f, report, cavity_state());
}

double RunState::dynamic_step(nlohmann::json keys, double t, double dt,
                              const solver::NewtonReport& report,
                              const biomarkers::Columns& columns, const std::string& text)
{
  auto cavities = cavity_state();
  keys["dt_ms"] = dt;
  for (const auto& [name, value] : columns)
    keys[name] = value;
  const nlohmann::json& step = output().step(keys, t, report, cavities, text);
  add_frame(t, dt, report, columns);
  return probes.empty() ? 0.0
                        : step[model.setup.probe_names[0] + "_displacement_mm"][1].get<double>();
}

void RunState::add_frame(double t, double dt, const solver::NewtonReport& report,
                         const biomarkers::Columns& columns)
{
  if (!frames)
    return;
  auto state = cavity_state();
  state.insert(state.end(), columns.begin(), columns.end());
  state.push_back({"strain_energy_mJ", model.problem->strain_energy()});
  state.push_back({"kinetic_energy_mJ", model.problem->kinetic_energy()});
  frames->add(t, state,
              {{"dt_ms", dt},
               {"newton_iterations", double(report.iterations)},
               {"residual_N", report.residuals.back()}});
}

void RunState::start_dynamics()
{
  if (_dynamic)
    return;
  _dynamic = true;
  model.problem->start_dynamics(
      {scene.real("dynamics.dt"), scene.real("dynamics.rho_inf"), scene.real("dynamics.damping")});
  solid_newton().reset();
  output();
  open_frames();
}

void RunState::open_frames()
{
  // The frames of a puff on the eye; a prescribed apex pressure is known
  // at every instant, a computed one is a state column.
  const std::string load = scene.string("puff.load");
  if (!model.eye || load == "none")
    return;
  std::vector<std::pair<std::string, std::function<double(double)>>> known;
  if (prescribed)
    known.push_back({"apex_air_pressure_mmHg", [this](double t)
                     { return t < 0 ? 0.0 : (*prescribed)(0, t); }});
  std::vector<std::int32_t> anterior, posterior;
  auto& mesh = *model.setup.mesh.mesh;
  for (auto g : model.setup.boundaries.surface_load)
  {
    auto f = model.setup.mesh.facets->find(g);
    anterior.insert(anterior.end(), f.begin(), f.end());
  }
  // The posterior cornea: the cavities' wall facets that bound cornea cells.
  mesh.topology_mutable().create_connectivity(2, 3);
  const auto f2c = mesh.topology().connectivity(2, 3);
  std::set<std::int32_t> cornea;
  for (auto& [tag, part] : model.setup.parts)
    if (part == "cornea")
      for (auto c : model.setup.mesh.cells->find(tag))
        cornea.insert(c);
  for (const auto& walls : model.setup.boundaries.cavities)
    for (auto g : walls)
      for (auto f : model.setup.mesh.facets->find(g))
        if (cornea.count(f2c->links(f)[0]))
          posterior.push_back(f);
  // Whole-eye motion: the anterior surface's axial displacement at this
  // distance from the axis (design.md section 9) [mm].
  constexpr double whole_eye_x = 4.0;
  frames.emplace(biomarkers::Section(*model.problem, anterior, "anterior cornea"),
                 biomarkers::Section(*model.problem, posterior, "posterior cornea"),
                 scene.real("puff.frame_rate"), whole_eye_x, known);
}

namespace
{

/// The layout of a checkpoint's document; another cannot be read.
constexpr int checkpoint_format = 2;

} // namespace

void RunState::start_phase(Phase& p, std::size_t index)
{
  phase = &p;
  phase_index = index;
  phase_start = {timings(), stepper.newton_iterations, stepper.cuts, summary["steps"].size(),
                 t_output(), MPI_Wtime()};
}

nlohmann::json RunState::identity() const
{
  nlohmann::json petsc = nlohmann::json::array();
  for (const auto& [name, value] : _petsc)
    petsc.push_back({name, value});
  std::string forms = model.problem ? model.problem->forms_signature() : "";
  if (model.air)
    forms += model.air->forms_signature();
  return {{"format", checkpoint_format},
          {"scene", io::format("%016llx", (unsigned long long)[&] {
             const std::string toml = scene.to_toml({"checkpoint.minutes", "checkpoint.keep"});
             return io::fnv1a(toml.data(), toml.size());
           }())},
          {"petsc", petsc},
          {"forms", forms},
          {"mesh", _mesh_as_built}};
}

void RunState::checkpoint(const Stepper::MarchState& march)
{
  // Due on every rank or on none: rank 0's clock decides.
  const double minutes = scene.real("checkpoint.minutes");
  int due = MPI_Wtime() - _last_checkpoint >= 60 * minutes;
  MPI_Bcast(&due, 1, MPI_INT, 0, comm);
  if (!due)
    return;
  const double start = MPI_Wtime();
  nlohmann::json doc = identity();
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  nlohmann::json solvers;
  for (const auto& [name, t] : solver_timings())
    solvers[name] = t;
  doc.update({{"ranks", ranks},
              {"step", phase_start.steps + march.steps},
              {"phase", phase_index},
              {"phase_name", phase->name()},
              {"phase_state", phase->save()},
              {"phase_start",
               {phase_start.timings, phase_start.newton_iterations, phase_start.cuts,
                phase_start.steps, phase_start.output, MPI_Wtime() - phase_start.wall}},
              {"march", {march.steps, march.t, march.dt, march.successes}},
              {"summary", summary},
              {"frames", frames ? frames->state() : nlohmann::json()},
              {"newton_iterations", stepper.newton_iterations},
              {"cuts", stepper.cuts},
              {"solvers", solvers},
              {"t0", t0},
              {"open_pressures", open_pressures},
              {"surface_pressure", surface_pressure},
              {"probes", probes},
              {"dynamic", _dynamic},
              {"t_output", t_output()},
              {"xdmf", _output ? _output->fields_state() : nlohmann::json()},
              {"wall_s", MPI_Wtime() - wall_start}});
  if (closed)
    doc["closed"] = {{"pressures", closed->pressures()}, {"targets", closed->targets()}};
  io::CheckpointWriter writer(comm);
  if (model.problem)
    model.problem->save(writer);
  else
    doc["air"] = model.air->save(writer); // the air alone
  if (model.coupled && model.coupled->started())
    doc["coupled"] = model.coupled->save(writer);
  const std::size_t step = doc["step"];
  const auto bytes = writer.write(folder.dir() / "checkpoint", format("ckpt-%06zu.h5", step),
                                  doc, scene.integer("checkpoint.keep"));
  const double wall = MPI_Wtime() - start;
  _last_checkpoint = MPI_Wtime();
  auto& total = summary["checkpoints"];
  if (total.is_null())
    total = nlohmann::json::object();
  total["written"] = total.value("written", 0) + 1;
  total["wall_s"] = total.value("wall_s", 0.0) + wall;
  total["last_bytes"] = bytes;
  folder.log(format("checkpoint: step %zu, %s t = %.4f ms, %.2f MB in %.3f s", step,
                    phase->name(), march.t, bytes / 1e6, wall));
}

std::size_t RunState::resume(const io::CheckpointReader& checkpoint)
{
  const nlohmann::json& doc = checkpoint.document();
  const nlohmann::json now = identity();
  const char* what[] = {"format", "scene", "petsc", "forms", "mesh"};
  const char* why[] = {"another version of nct's checkpoint layout",
                       "another scene (or other --set values)",
                       "other --petsc or solver.petsc options",
                       "another build of the forms (FFCx signatures differ)",
                       "another mesh (the same scene meshed differently: another gmsh?)"};
  for (std::size_t i = 0; i < std::size(what); ++i)
    if (doc.value(what[i], nlohmann::json()) != now[what[i]])
      throw io::CheckpointError("the checkpoint " + checkpoint.file().string()
                                + " was written by " + why[i] + "; refusing to resume");
  folder.log(format("resume: %s, written on %d rank(s) at step %zu (%s t = %.4f ms)",
                    checkpoint.file().string().c_str(), doc.at("ranks").get<int>(),
                    doc.at("step").get<std::size_t>(),
                    doc.at("phase_name").get<std::string>().c_str(),
                    doc.at("march")[1].get<double>()));
  const int ranks = summary["ranks"];
  summary = doc.at("summary");
  summary["ranks"] = ranks;
  // The summary was saved before its own file was written: count that one.
  if (auto& total = summary["checkpoints"]; total.is_null())
    total = {{"written", 1}, {"wall_s", 0.0}};
  else
    total["written"] = total["written"].get<int>() + 1;
  summary["resumed"] = {{"file", checkpoint.file().string()},
                        {"ranks_before", doc.at("ranks")},
                        {"steps_before", doc.at("step")}};
  wall_start = MPI_Wtime() - doc.at("wall_s").get<double>();
  stepper.newton_iterations = doc.at("newton_iterations");
  stepper.cuts = doc.at("cuts");
  for (const auto& [name, t] : doc.at("solvers").items())
    _resumed_timings[name] = t.get<solver::Timings>();
  t0 = doc.at("t0");
  doc.at("open_pressures").get_to(open_pressures);
  surface_pressure = doc.at("surface_pressure");
  doc.at("probes").get_to(probes);
  x_imaged.clear();
  zero_pressure_inflated.clear();
  _dynamic = doc.at("dynamic");
  if (model.problem)
    resume_solid(checkpoint);
  else
    model.air->restore(checkpoint, doc.at("air"));
  const auto& m = doc.at("march");
  stepper.resume = Stepper::MarchState{m[0], m[1], m[2], m[3]};
  const auto& p = doc.at("phase_start");
  phase_start = {p[0].get<solver::Timings>(), p[1], p[2], p[3], p[4],
                 MPI_Wtime() - p[5].get<double>()};
  return doc.at("phase");
}

void RunState::resume_solid(const io::CheckpointReader& checkpoint)
{
  const nlohmann::json& doc = checkpoint.document();
  auto& problem = *model.problem;
  std::optional<solid::TimeStep> step;
  if (_dynamic)
    step = solid::TimeStep{scene.real("dynamics.dt"), scene.real("dynamics.rho_inf"),
                           scene.real("dynamics.damping")};
  problem.restore(checkpoint, step);
  if (doc.contains("coupled"))
    model.coupled->restore(checkpoint, doc["coupled"]);
  if (doc.contains("closed"))
    closed.emplace(problem, doc["closed"].at("pressures").get<std::vector<double>>(),
                   doc["closed"].at("targets").get<std::vector<double>>());
  else if (problem.cavities() > 0)
    problem.set_cavity_pressures(open_pressures);
  const auto& fields = doc.at("xdmf");
  _output.emplace(scene, folder, model, summary["steps"], probes, t0,
                  fields.is_null() ? nullptr : &fields);
  _output->t_output = doc.at("t_output");
  if (_dynamic)
  {
    open_frames();
    if (frames)
      frames->restore(doc.at("frames"));
  }
}

void RunState::write_tables() const
{
  if (!frames)
    return;
  folder.write_text("steps.csv", frames->steps_csv());
  folder.write_text("frames.csv", frames->frames_csv());
  folder.write_text("profiles.csv", frames->profiles_csv());
}

} // namespace nct
