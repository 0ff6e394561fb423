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
                         double t0)
    : _scene(scene), _folder(folder), _model(model), _steps(steps),
      _probes(*model.problem, probes),
      _fields(folder, model.setup.mesh.mesh, model.problem->coordinate_space()),
      _t_step(MPI_Wtime())
{
  if (scene.boolean("output.fields"))
  {
    _fields.write(*model.problem->fields.at("fibre_1"), t0);
    _fields.write(*model.problem->fields.at("fibre_2"), t0);
  }
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

RunState::RunState(MPI_Comm comm, const scene::Scene& s, io::RunFolder& folder, Model& model)
    : comm(comm), scene(s), folder(folder), model(model),
      settings(newton_settings(s)),
      stepper(make_stepper(s, settings, folder)), wall_start(MPI_Wtime())
{
  summary["scene"] = s.file().string();
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  summary["ranks"] = ranks;
  summary["steps"] = nlohmann::json::array();
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
  for (auto& [name, s] : _solvers)
    t += s.newton->timings;
  return t;
}

std::map<std::string, solver::Timings> RunState::solver_timings() const
{
  std::map<std::string, solver::Timings> t;
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

void RunState::write_tables() const
{
  if (!frames)
    return;
  folder.write_text("steps.csv", frames->steps_csv());
  folder.write_text("frames.csv", frames->frames_csv());
  folder.write_text("profiles.csv", frames->profiles_csv());
}

} // namespace nct
