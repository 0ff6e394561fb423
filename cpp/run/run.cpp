#include "run/run.h"

#include <cstdlib>
#include <dlfcn.h>

#include <sys/resource.h>

#include <dolfinx/common/log.h>

#include "io/checkpoint.h"
#include "io/format.h"
#include "run/model.h"
#include "run/timeline.h"

namespace nct
{
namespace
{

using io::format;

/// What the model is, into the log and the summary.
void describe(RunState& s)
{
  for (const Block* b : s.model.blocks())
    b->describe(s.summary, s.folder);
  s.folder.log(format("meshing %.2f s, setup %.2f s", s.model.t_mesh, s.model.t_setup));
}

/// Run the phase s.phase (started by s.start_phase, or resumed) and add its
/// profile (wall time, where it went) to the summary's.
void run_phase(RunState& s)
{
  Phase& phase = *s.phase;
  phase.run(s);
  const auto& start = s.phase_start;
  nlohmann::json p = s.timings() - start.timings;
  p["phase"] = phase.name();
  p["wall_s"] = MPI_Wtime() - start.wall;
  p["output_s"] = s.t_output() - start.output;
  p["newton_iterations"] = s.stepper.newton_iterations - start.newton_iterations;
  p["step_cuts"] = s.stepper.cuts - start.cuts;
  p["steps"] = s.summary["steps"].size() - start.steps;
  s.summary["profile"].push_back(p);
}

/// The run's counts and timings into the summary, written to summary.json.
void finish(RunState& s, const std::string& status)
{
  const solver::Timings t = s.timings();
  s.summary["status"] = status;
  s.summary["newton_iterations"] = s.stepper.newton_iterations;
  s.summary["linear_solves"] = t.linear_solves;
  s.summary["jacobians"] = t.jacobians;
  s.summary["factorisations"] = t.factorisations;
  s.summary["krylov_iterations"] = t.krylov_iterations;
  s.summary["step_cuts"] = s.stepper.cuts;
  s.summary["step_rejections"] = s.stepper.rejections;
  s.summary["wall_s"] = MPI_Wtime() - s.wall_start;
  // Peak resident memory (the factorisations' included): the largest rank's
  // and all ranks' together [MB].
  rusage usage;
  getrusage(RUSAGE_SELF, &usage);
  double peak[2] = {usage.ru_maxrss / 1024.0, usage.ru_maxrss / 1024.0};
  MPI_Allreduce(MPI_IN_PLACE, &peak[0], 1, MPI_DOUBLE, MPI_MAX, s.comm);
  MPI_Allreduce(MPI_IN_PLACE, &peak[1], 1, MPI_DOUBLE, MPI_SUM, s.comm);
  s.summary["memory_peak_rank_mb"] = peak[0];
  s.summary["memory_peak_total_mb"] = peak[1];
  s.summary["timings_s"] = {{"mesh", s.model.t_mesh},
                            {"setup", s.model.t_setup},
                            {"assemble", t.assemble()},
                            {"linear_solve", t.linear()},
                            {"border", t.border},
                            {"output", s.t_output()}};
  // Each Newton system's own (the solid's, the air's, the coupled one's).
  for (const auto& [name, u] : s.solver_timings())
  {
    s.summary["timings_s"]["solvers"][name] = u;
    s.summary["timings_s"]["solvers"][name]["assemble"] = u.assemble();
    s.summary["timings_s"]["solvers"][name]["linear_solve"] = u.linear();
  }
  s.folder.write_text("summary.json", s.summary.dump(2) + "\n");
}

/// Open MPI started without a launcher (a singleton, the usual `nct`):
/// no helper daemon (ess_singleton_isolated) and the shared-memory
/// transport rather than probing the network's (pml ob1). Together they
/// take MPI's start from 0.44 s to 0.08 s here; one rank sends nothing.
/// A launcher's ranks (mpirun, srun) and a user's own settings are left
/// alone.
void quiet_singleton()
{
  for (const char* launched : {"OMPI_COMM_WORLD_SIZE", "PMIX_RANK", "PMI_RANK"})
    if (std::getenv(launched))
      return;
  setenv("OMPI_MCA_ess_singleton_isolated", "1", 0);
  setenv("OMPI_MCA_pml", "ob1", 0);
}

} // namespace

Runtime::Runtime(const char* program)
{
  quiet_singleton();
  int argc = 1;
  char* argv[] = {const_cast<char*>(program), nullptr};
  char** pargv = argv;
  PetscInitialize(&argc, &pargv, nullptr, nullptr);
  dolfinx::init_logging(argc, pargv);
  // One BLAS thread per rank unless the environment says otherwise: the
  // ranks fill the cores, and OpenBLAS' threads on top oversubscribe them.
  if (!std::getenv("OPENBLAS_NUM_THREADS") && !std::getenv("OMP_NUM_THREADS"))
    if (auto set = reinterpret_cast<void (*)(int)>(dlsym(RTLD_DEFAULT, "openblas_set_num_threads")))
      set(1);
}

Runtime::~Runtime() { PetscFinalize(); }

std::string blas_library()
{
  Dl_info info;
  void* dgemm = dlsym(RTLD_DEFAULT, "dgemm_");
  if (!dgemm || !dladdr(dgemm, &info) || !info.dli_fname)
    return "none";
  std::error_code error;
  const auto path = std::filesystem::canonical(info.dli_fname, error);
  return error ? info.dli_fname : path.string();
}

nlohmann::json run(MPI_Comm comm, const Input& in, const RunOptions& options)
{
  const Settings& s = in.settings;
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  // A resumed run's checkpoint is read (and checked) before anything else.
  std::optional<io::CheckpointReader> checkpoint;
  if (options.resume)
  {
    if (s.checkpoint.steps == 0)
      throw io::CheckpointError(in.scene.file().string() + ": --resume needs the scene the run "
                                "was started with, whose checkpoint.steps is > 0 (it is 0)");
    checkpoint.emplace(options.out / "checkpoint");
  }
  io::RunFolder folder(comm, options.out, options.resume);
  folder.write_text("scene.toml", in.scene.to_toml());
  folder.log("nct: " + in.scene.file().string() + " on " + std::to_string(ranks)
             + " rank(s) -> " + options.out.string());
  folder.log("blas: " + blas_library());

  // Linear solver options: defaults, then the scene's, then the command line's.
  auto petsc = s.solver.petsc;
  petsc.insert(petsc.end(), options.petsc.begin(), options.petsc.end());
  solver::set_petsc_options(petsc, s.solver.newton.jacobian);

  Model model = make_model(comm, in);
  RunState state(comm, in, folder, model, petsc);
  state.summary["blas"] = blas_library();
  describe(state);
  const auto phases = timeline(s, model);
  if (phases.empty())
    throw std::runtime_error("the scene loads nothing: no cavity to inflate, no "
                             "press.pressure and no puff");
  state.summary["profile"] = nlohmann::json::array();
  std::size_t first = 0;
  if (checkpoint)
  {
    first = state.resume(*checkpoint);
    if (first >= phases.size())
      throw io::CheckpointError("the checkpoint " + checkpoint->file().string()
                                + " names a phase this scene does not have");
    phases[first]->restore(checkpoint->document().at("phase_state"));
    state.phase = phases[first].get();
    state.phase_index = first;
    state.summary["blas"] = blas_library(); // this process's, not the one before
  }
  try
  {
    for (std::size_t i = first; i < phases.size(); ++i)
    {
      if (i > first || !checkpoint)
        state.start_phase(*phases[i], i);
      run_phase(state);
    }
  }
  catch (const std::exception& e) // Diverged, or a biomarker that cannot be taken
  {
    state.summary["error"] = e.what();
    try
    {
      state.write_tables();
    }
    catch (const std::exception& w)
    {
      state.summary["error"] = std::string(e.what()) + "; writing the tables failed too: " + w.what();
    }
    finish(state, "failed");
    throw;
  }
  for (const Block* b : model.blocks())
    b->summarise(state.summary);
  state.write_tables();
  finish(state, "converged");
  const solver::Timings t = state.timings();
  folder.log(format("done: %d Newton iterations, %d step cuts; assemble %.2f s, linear solve "
                    "%.2f s (%d factorisations %.2f s; border %.2f s), output %.2f s, total "
                    "%.2f s",
                    state.stepper.newton_iterations, state.stepper.cuts, t.assemble(),
                    t.linear(), t.factorisations, t.factorise, t.border, state.t_output(),
                    state.summary["wall_s"].get<double>()));
  return state.summary;
}

} // namespace nct
