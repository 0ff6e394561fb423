// A run is a timeline of phases acting on a model: what the phases share
// (RunState), the phases, and the timeline a scene asks for.
#pragma once

#include <array>
#include <functional>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <dolfinx/la/petsc.h>
#include <mpi.h>
#include <nlohmann/json.hpp>

#include "biomarkers/record.h"
#include "cavity/cavity.h"
#include "io/checkpoint.h"
#include "io/output.h"
#include "puff/load.h"
#include "run/model.h"
#include "run/stepper.h"
#include "scene/scene.h"
#include "solver/newton.h"

namespace nct
{

/// The scene's Newton settings (solver.*).
solver::NewtonSettings newton_settings(const scene::Scene& s);

/// A stepper with the scene's step cutting and predictor (solver.*).
Stepper make_stepper(const scene::Scene& s, const solver::NewtonSettings& settings,
                     io::RunFolder& folder);

/// The solid's record of a run: a line per converged step in the log and
/// the summary's steps, its fields, the probes. Made once the reference
/// geometry is final (after the zero-pressure phase).
class SolidOutput
{
public:
  /// `fields`: a resumed run's fields (Fields::state()), continued
  /// instead of started.
  SolidOutput(const scene::Scene& scene, io::RunFolder& folder, Model& model,
              nlohmann::json& steps, const std::vector<std::array<double, 3>>& probes,
              double t0, const nlohmann::json* fields = nullptr);

  /// A converged step into the summary's steps (returned), the log and
  /// the fields; `step` holds the phase's own keys.
  const nlohmann::json& step(nlohmann::json step, double time, const solver::NewtonReport& report,
                             const biomarkers::Columns& cavities, const std::string& extra = "");
  /// Displacement and von Mises stress at `time` (output.fields).
  void write_fields(double time);
  /// Its fields' files, for a checkpoint. Collective.
  nlohmann::json fields_state() const { return _fields.state(); }
  /// The probes' displacements now (every rank gets them).
  std::vector<std::array<double, 3>> probe_displacement() const { return _probes.displacement(); }
  double t_output = 0; ///< wall time spent writing fields [s]

private:
  const scene::Scene& _scene;
  io::RunFolder& _folder;
  Model& _model;
  nlohmann::json& _steps;
  solid::Probes _probes;
  io::Fields _fields;
  double _t_step;
};

/// What the phases of a run share: the scene, the model, the Newton
/// solvers (one per Jacobian), the solid's loads and cavities, the run
/// folder, the summary and what has been recorded.
class Phase;

class RunState
{
public:
  /// `petsc`: the PETSc options in force (a checkpoint must match them).
  RunState(MPI_Comm comm, const scene::Scene& scene, io::RunFolder& folder, Model& model,
           std::vector<std::pair<std::string, std::string>> petsc = {});

  MPI_Comm comm;
  const scene::Scene& scene;
  io::RunFolder& folder;
  Model& model;
  nlohmann::json summary;
  const solver::NewtonSettings settings;
  Stepper stepper;
  double wall_start; ///< MPI_Wtime() at the start; resumed: less the time before

  /// The Newton solver of a named Jacobian, its matrix made by `create`
  /// on first use; `prefix`: its PETSc options prefix.
  solver::Newton& newton(const std::string& name, const std::function<Mat()>& create,
                         const std::string& prefix = "");
  solver::Newton& solid_newton();
  /// The solvers' timings, summed, and each solver's by name.
  solver::Timings timings() const;
  std::map<std::string, solver::Timings> solver_timings() const;

  // The solid's loads and cavities.
  double t0 = 0; ///< pseudo-time at the start of the current quasi-static phase
  std::vector<double> open_pressures; ///< [MPa], while the cavities are open
  std::optional<cavity::Open> open;
  std::optional<cavity::Closed> closed;
  /// The solid's Newton system now: its closed cavities bordered, or open.
  solver::System solid_system();
  double press_peak = 0;       ///< [MPa]
  double surface_pressure = 0; ///< the press now [MPa]
  std::function<double(const std::array<double, 3>&)> press_profile;
  /// The prescribed air pressure p(r, t) [mmHg] (puff.load gaussian or table), or null.
  std::unique_ptr<puff::Load> prescribed;
  /// The surface load at time t: the press (held) and the prescribed air.
  void set_surface_load(double t);
  /// Each cavity's pressure [mmHg] and volume [mm^3] now.
  biomarkers::Columns cavity_state() const;

  // The reference geometry and what is recorded on it.
  std::vector<double> x_imaged; ///< the mesh as imaged (zero pressure on)
  /// Zero pressure's last pressurised state (the solid's local u), for
  /// the inflate phase to start from; empty once used.
  std::vector<double> zero_pressure_inflated;
  std::vector<std::array<double, 3>> probes;
  /// The solid's output, made on first use (the geometry is final by then).
  /// Resumed, the summary holds what it recorded before.
  SolidOutput& output();
  /// A quasi-static step's record.
  void quasi_static_step(const char* phase, double f, const solver::NewtonReport& report);
  /// A dynamic step's record: `keys` (with its "phase") into the step,
  /// `columns` into the step and the frames, `text` onto its log line;
  /// returns the first probe's axial displacement (0 without probes).
  double dynamic_step(nlohmann::json keys, double t, double dt,
                      const solver::NewtonReport& report, const biomarkers::Columns& columns = {},
                      const std::string& text = "");
  /// The current state into the frames (if any): the cavities, `columns`,
  /// the energies; the solver's figures go to the step table only.
  void add_frame(double t, double dt, const solver::NewtonReport& report,
                 const biomarkers::Columns& columns);
  /// Switch the solid to dynamics at the current state (once) and, with a
  /// puff on the eye, open the frames.
  void start_dynamics();
  bool dynamic() const { return _dynamic; }
  std::optional<biomarkers::Record> frames;
  /// The frames' tables (steps.csv, frames.csv, profiles.csv), whole.
  void write_tables() const;
  double t_output() const { return _output ? _output->t_output : 0.0; }

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
  /// The frames of a puff on the eye (from start_dynamics).
  void open_frames();
  /// The solid's part of resume(): its fields, cavities, output, frames.
  void resume_solid(const io::CheckpointReader& checkpoint);
  /// What a checkpoint must match: the format, the scene (but where and
  /// how often checkpoints are written), the PETSc options, the forms, the
  /// mesh as built.
  nlohmann::json identity() const;
  std::vector<std::pair<std::string, std::string>> _petsc;
  std::string _mesh_as_built;
  /// A resumed run's solvers' timings before, until each solver is made.
  std::map<std::string, solver::Timings> _resumed_timings;
  double _last_checkpoint = 0; ///< MPI_Wtime() of the last write
  struct Solver
  {
    std::unique_ptr<dolfinx::la::petsc::Matrix> A;
    std::unique_ptr<solver::Newton> newton;
  };
  std::map<std::string, Solver> _solvers;
  std::optional<SolidOutput> _output;
  bool _dynamic = false;
};

/// A phase of a run.
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

/// The phases a scene asks for, in order: zero pressure, inflate, close,
/// press, rest, puff (prescribed, the air alone, or coupled).
std::vector<std::unique_ptr<Phase>> timeline(const scene::Scene& scene, const Model& model);

} // namespace nct
