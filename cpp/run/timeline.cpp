#include "run/timeline.h"

#include <algorithm>

#include "io/format.h"
#include "run/solid_block.h"

namespace nct
{
namespace
{

using io::format;

/// The layout of a checkpoint's document; another cannot be read.
constexpr int checkpoint_format = 3;

} // namespace

Stepper make_stepper(const SolverSettings& s, io::RunFolder& folder)
{
  return Stepper(s.newton, s.max_step_cuts,
                 s.extrapolate ? Stepper::Predictor::extrapolate : Stepper::Predictor::previous,
                 folder);
}

RunState::RunState(MPI_Comm comm, const Input& in, io::RunFolder& folder, Model& model,
                   std::vector<std::pair<std::string, std::string>> petsc)
    : comm(comm), input(in), settings(in.settings), folder(folder), model(model),
      stepper(make_stepper(in.settings.solver, folder)), wall_start(MPI_Wtime()),
      _petsc(std::move(petsc)), _last_checkpoint(wall_start), _t_step(wall_start)
{
  summary["scene"] = in.scene.file().string();
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  summary["ranks"] = ranks;
  summary["steps"] = nlohmann::json::array();
  stepper.control = settings.step_control;
  if (const int every = settings.checkpoint.steps; every > 0)
  {
    for (const Block* b : model.blocks())
      if (const std::string id = b->identity(); !id.empty())
        _blocks_as_built += std::string(b->name()) + ": " + id + "; ";
    stepper.boundaries = {every, [this](const Stepper::MarchState& m) { checkpoint(m); }};
  }
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
  // A meshed humor's dynamics: the solid's and the humor's unknowns
  // stacked (the humor's pressure; or velocity, pressure and mesh), one AIJ
  // matrix, LU.
  if (const char* name = model.solid->humor_system())
    return newton(name, [&] { return model.solid->humor->create_matrix(); });
  // LDL^T (solver.factorisation): the upper triangle and MUMPS' LDL^T of
  // the symmetric matrix it stands for (the follower pressures' skew part
  // is left to the Newton iteration). A preconditioner named on the command
  // line other than a factorisation (--petsc "-pc_type gamg") wins over
  // it: the AIJ matrix PETSc's multigrids take, with the rigid-body modes.
  char pc_type[64] = "lu";
  PetscOptionsGetString(nullptr, nullptr, "-pc_type", pc_type, sizeof(pc_type), nullptr);
  const bool factorised = std::string(pc_type) == "lu" || std::string(pc_type) == "cholesky";
  const bool ldlt = factorised && settings.solver.ldlt;
  const bool fresh = _solvers.find("solid") == _solvers.end();
  auto& problem = model.solid->problem;
  auto& n = newton("solid", [&]
                   { return problem.create_matrix(!factorised ? "aij" : ldlt ? "sbaij" : "baij"); });
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

double RunState::t_output() const
{
  double t = 0;
  for (const Block* b : model.blocks())
    t += b->t_output();
  return t;
}

void RunState::record_step(nlohmann::json step, double time, const solver::NewtonReport& report,
                           const std::string& text)
{
  step["time"] = time;
  step["newton_iterations"] = report.iterations;
  step["residual_N"] = report.residuals.back();
  step["newton_residuals"] = report.residuals;
  auto& steps = summary["steps"];
  steps.push_back(step);
  // The puff's share done, and the time left at the pace since its march began.
  std::string share;
  if (step["phase"] == "puff" && settings.puff.duration > 0)
  {
    const double f = std::clamp(time / settings.puff.duration, 0.0, 1.0);
    if (_share_start < 0)
      _share_start = std::max(0.0, f - step.value("dt_ms", 0.0) / settings.puff.duration);
    const double spent = MPI_Wtime() - phase_start.wall;
    share = format("  puff %3.0f %%", 100 * f);
    if (f > _share_start && f < 1)
      share += format(", about %.0f s left", spent * (1 - f) / (f - _share_start));
  }
  folder.log(format("step %3zu  %-7s t %+8.4f  newton %2d  |R| %.2e%s  wall %.2f s%s",
                    steps.size(), step["phase"].get<std::string>().c_str(), time,
                    report.iterations, report.residuals.back(), text.c_str(),
                    MPI_Wtime() - _t_step, share.c_str()));
  _t_step = MPI_Wtime();
}

void RunState::write_tables() const
{
  for (const Block* b : model.blocks())
    b->write_tables();
}

void RunState::start_phase(Phase& p, std::size_t index)
{
  phase = &p;
  phase_index = index;
  _share_start = -1;
  phase_start = {timings(), stepper.newton_iterations, stepper.cuts, summary["steps"].size(),
                 t_output(), MPI_Wtime()};
}

nlohmann::json RunState::identity() const
{
  nlohmann::json petsc = nlohmann::json::array();
  for (const auto& [name, value] : _petsc)
    petsc.push_back({name, value});
  return {{"format", checkpoint_format},
          {"scene", io::format("%016llx", (unsigned long long)[&] {
             const std::string toml
                 = input.scene.to_toml({"checkpoint.minutes", "checkpoint.keep"});
             return io::fnv1a(toml.data(), toml.size());
           }())},
          {"petsc", petsc},
          {"blocks", _blocks_as_built}};
}

void RunState::checkpoint(const Stepper::MarchState& march)
{
  // Due on every rank or on none: rank 0's clock decides.
  int due = MPI_Wtime() - _last_checkpoint >= 60 * settings.checkpoint.minutes;
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
              {"newton_iterations", stepper.newton_iterations},
              {"cuts", stepper.cuts},
              {"rejections", stepper.rejections},
              {"solvers", solvers},
              {"wall_s", MPI_Wtime() - wall_start}});
  io::CheckpointWriter writer(comm);
  for (const Block* b : model.blocks())
    doc["block_state"][b->name()] = b->save(writer);
  const std::size_t step = doc["step"];
  const auto bytes = writer.write(folder.dir() / "checkpoint", format("ckpt-%06zu.h5", step),
                                  doc, settings.checkpoint.keep);
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
  const char* what[] = {"format", "scene", "petsc", "blocks"};
  const char* why[] = {"another version of nct's checkpoint layout",
                       "another scene (or other --set values)",
                       "other --petsc or solver.petsc options",
                       "another build of the forms (FFCx signatures differ) or another mesh "
                       "(the same scene meshed differently: another gmsh?)"};
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
  stepper.rejections = doc.value("rejections", 0);
  for (const auto& [name, t] : doc.at("solvers").items())
    _resumed_timings[name] = t.get<solver::Timings>();
  for (Block* b : model.blocks())
    b->restore(checkpoint, doc.at("block_state").at(b->name()), folder);
  const auto& m = doc.at("march");
  stepper.resume = Stepper::MarchState{m[0], m[1], m[2], m[3]};
  const auto& p = doc.at("phase_start");
  phase_start = {p[0].get<solver::Timings>(), p[1], p[2], p[3], p[4],
                 MPI_Wtime() - p[5].get<double>()};
  return doc.at("phase");
}

} // namespace nct
