// A run is a timeline of phases acting on a model's blocks: the run's
// bookkeeping (RunState), the phases, and the timeline a scene asks for.
#pragma once

#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <dolfinx/la/petsc.h>
#include <mpi.h>
#include <nlohmann/json.hpp>

#include "io/checkpoint.h"
#include "io/output.h"
#include "run/model.h"
#include "run/stepper.h"
#include "settings/settings.h"
#include "solver/newton.h"

namespace nct
{

/// A stepper with the scene's Newton settings, step cutting and predictor.
Stepper make_stepper(const SolverSettings& s, io::RunFolder& folder);

class Phase;

/// The run's bookkeeping: the summary and its record of steps, the step
/// controller's counts, the Newton solvers (one per Jacobian), the phase
/// running and where it started, the checkpoints. The physics state is
/// the blocks'.
class RunState
{
public:
  /// `petsc`: the PETSc options in force (a checkpoint must match them).
  RunState(MPI_Comm comm, const Input& input, io::RunFolder& folder, Model& model,
           std::vector<std::pair<std::string, std::string>> petsc = {});

  MPI_Comm comm;
  const Input& input;
  const Settings& settings;
  io::RunFolder& folder;
  Model& model;
  nlohmann::json summary;
  Stepper stepper;
  double wall_start; ///< MPI_Wtime() at the start; resumed: less the time before

  /// The Newton solver of a named Jacobian, its matrix made by `create`
  /// on first use; `prefix`: its PETSc options prefix.
  solver::Newton& newton(const std::string& name, const std::function<Mat()>& create,
                         const std::string& prefix = "");
  /// The solid's (LU or LDL^T, solver.factorisation).
  solver::Newton& solid_newton();
  /// The solvers' timings, summed, and each solver's by name.
  solver::Timings timings() const;
  std::map<std::string, solver::Timings> solver_timings() const;
  /// Wall time spent writing fields, all blocks [s].
  double t_output() const;

  /// A converged step into the summary's steps and the log: `step` holds
  /// the phase's and the blocks' keys, `text` their part of the log line.
  void record_step(nlohmann::json step, double time, const solver::NewtonReport& report,
                   const std::string& text);
  /// Every block's tables so far, whole.
  void write_tables() const;

  // The timeline's progress, and checkpoints (checkpoint.*).
  /// The phase running and its place in the timeline.
  Phase* phase = nullptr;
  std::size_t phase_index = 0;
  /// Where the running phase started: the counts and timings its profile
  /// is taken against.
  struct PhaseStart
  {
    solver::Timings timings;
    int newton_iterations = 0, cuts = 0;
    std::size_t steps = 0;
    double output = 0, wall = 0;
  } phase_start;
  /// The phase starts now.
  void start_phase(Phase& p, std::size_t index);
  /// At a march's checkpoint boundary: the whole run's state into
  /// <out>/checkpoint/ckpt-<step>.h5 if a write is due (checkpoint.minutes).
  void checkpoint(const Stepper::MarchState& march);
  /// Continue from a checkpoint (checked against this scene, build and
  /// mesh): its state restored, the stepper set to resume its march.
  /// Returns the index of the phase to continue.
  std::size_t resume(const io::CheckpointReader& checkpoint);

private:
  /// What a checkpoint must match: the format, the scene (but where and
  /// how often checkpoints are written), the PETSc options, the blocks'
  /// forms and meshes as built.
  nlohmann::json identity() const;
  std::vector<std::pair<std::string, std::string>> _petsc;
  std::string _blocks_as_built;
  /// A resumed run's solvers' timings before, until each solver is made.
  std::map<std::string, solver::Timings> _resumed_timings;
  double _last_checkpoint = 0; ///< MPI_Wtime() of the last write
  double _t_step;              ///< MPI_Wtime() at the last recorded step
  /// The puff's share done when the running phase started its march (-1:
  /// no puff step yet), for the time left.
  double _share_start = -1;
  struct Solver
  {
    std::unique_ptr<dolfinx::la::petsc::Matrix> A;
    std::unique_ptr<solver::Newton> newton;
  };
  std::map<std::string, Solver> _solvers;
};

/// A phase of a run, acting on the blocks it was made with.
class Phase
{
public:
  virtual ~Phase() = default;
  virtual void run(RunState& state) = 0;
  /// Its name in the log and the profile.
  virtual const char* name() const = 0;
  /// Its own state at a checkpoint boundary of its march; restore() takes
  /// it back before a resumed run().
  virtual nlohmann::json save() const { return nullptr; }
  virtual void restore(const nlohmann::json&) {}
};

/// The phases a scene asks for, in order, on the model's blocks: zero
/// pressure, inflate, close, press, rest, puff (prescribed, the air alone,
/// or coupled). Each quasi-static phase spans one unit of pseudo-time
/// before the rest, which spans [-rest.duration, 0]; the puff starts at 0.
std::vector<std::unique_ptr<Phase>> timeline(const Settings& settings, Model& model);

} // namespace nct
