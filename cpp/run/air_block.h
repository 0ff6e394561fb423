// The air block (its inlet and its record), the mesh motion and the
// coupling of the solid and the air.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>

#include <petscksp.h>

#include "air/problem.h"
#include "biomarkers/record.h"
#include "fsi/coupled.h"
#include "mesh_motion/problem.h"
#include "run/air_output.h"
#include "run/block.h"
#include "run/stepper.h"
#include "settings/settings.h"

namespace nct
{

class SolidBlock;

/// The air block: the air on its mesh (fixed, or moving with a mesh
/// motion), its inlet in time, its record (the apex pressure, the
/// corneal pressure table, the centreline or a file mesh's forces, the
/// fields).
class AirBlock : public Block
{
public:
  /// The air on `mesh`; `motion`: its mesh displacement when the mesh
  /// moves (coupled), else null. `with_eye`: the eye is in the air (a
  /// rigid or coupled wall).
  AirBlock(AirMesh mesh, AirBlockSettings settings, const air::Fluid& fluid,
           const air::Boundaries& boundaries, double velocity_scale,
           std::shared_ptr<dolfinx::fem::Function<double>> motion, bool eye, bool with_eye);

  const AirMesh mesh;
  const AirBlockSettings settings;
  air::Problem problem;
  const bool eye;      ///< the idealised eye's air (else a file mesh's fluid)
  const bool with_eye; ///< the eye is a wall in it (rigid or coupled)

  // Block
  const char* name() const override { return "air"; }
  void describe(nlohmann::json& summary, io::RunFolder& folder) const override;
  std::string identity() const override;
  nlohmann::json save(io::CheckpointWriter& writer) const override;
  void restore(const io::CheckpointReader& checkpoint, const nlohmann::json& state,
               io::RunFolder& folder) override;
  void write_tables() const override;
  double t_output() const override { return _record ? _record->t_output() : 0.0; }

  /// The inlet's speed [mm/ms] at time t [ms].
  double inlet(double t) const { return _inlet(t); }
  /// The inlet at time t into the air's conditions.
  void set_inlet(double t) { problem.set_inlet_scale(_inlet(t)); }
  /// The air's time integration alone (a fixed mesh), for the Stepper.
  Stepper::Dynamics dynamics();
  /// The air alone's Newton system.
  solver::System system();
  /// Velocity and pressure blocks for a fieldsplit preconditioner.
  void set_fieldsplit(KSP ksp) const;

  /// Start the record on the air mesh as it is now (once; a resumed run
  /// continues the one it saved). `motion`: the moving mesh's, or null.
  void open_record(io::RunFolder& folder, const mesh_motion::Problem* motion);
  AirRecord& record() { return *_record; }
  /// The air alone's step: its keys into `step`, its text for the log,
  /// its row into steps.csv. Collective.
  void record_step(nlohmann::json& step, std::string& text, double time, double dt,
                   const solver::NewtonReport& report);
  /// The record's peaks into the summary (the air alone: its top level;
  /// else under "air"), and into the log.
  void summarise_record(nlohmann::json& summary, io::RunFolder& folder) const;

private:
  std::function<double(double)> _inlet;
  std::optional<AirRecord> _record;
  nlohmann::json _resumed; ///< a checkpoint's record, until the record opens
  std::string _steps_csv;  ///< the air alone's steps.csv
  double _t_step = 0;      ///< wall time at the last step
  std::vector<double> _no_border;
  io::RunFolder* _folder = nullptr;
};

/// The mesh motion: the air mesh's displacement, extended from the
/// interface (forms/mesh_motion.py).
class MeshMotionBlock : public Block
{
public:
  MeshMotionBlock(const meshio::Tagged& mesh, const mesh_motion::Settings& settings,
                  const mesh_motion::Boundaries& boundaries)
      : problem(mesh, settings, boundaries)
  {
  }
  mesh_motion::Problem problem;
  const char* name() const override { return "mesh_motion"; }
  void describe(nlohmann::json& summary, io::RunFolder&) const override
  {
    summary["mesh_motion_dofs"] = problem.dofs();
  }
  /// Saved and restored with the air by the coupling.
  nlohmann::json save(io::CheckpointWriter&) const override { return nullptr; }
  void restore(const io::CheckpointReader&, const nlohmann::json&, io::RunFolder&) override {}
};

/// The coupling of the solid and the air (cpp/fsi) in one Newton system,
/// and what it watches over the puff: the air mesh's smallest Jacobian,
/// the interface's power balance.
class CouplingBlock : public Block
{
public:
  CouplingBlock(SolidBlock& solid, AirBlock& air, MeshMotionBlock& motion,
                const fsi::Interface& interface, const FsiSettings& settings);
  const FsiSettings settings;
  fsi::Coupled coupled;

  // Block
  const char* name() const override { return "coupling"; }
  void describe(nlohmann::json& summary, io::RunFolder& folder) const override;
  nlohmann::json save(io::CheckpointWriter& writer) const override;
  void restore(const io::CheckpointReader& checkpoint, const nlohmann::json& state,
               io::RunFolder& folder) override;

  /// The coupled system's linear solver options (fsi.linear_solver).
  void set_solver_options() const;
  /// Its fieldsplit blocks, if the preconditioner is one.
  void set_fieldsplit(KSP ksp);
  /// The coupled time integration, for the Stepper: at each converged
  /// step the power, the mesh's Jacobian and the air's force are taken
  /// before the step advances.
  Stepper::Dynamics dynamics();
  /// The state at time t (the air's record sampled, the coupling's
  /// figures): its columns, their text onto `text`; the extremes kept.
  /// Collective.
  biomarkers::Columns sample(double t, std::string& text);
  /// The puff's extremes and its energy balance into the summary.
  void summarise(nlohmann::json& summary) const override;
  /// The columns' values at rest (before the puff).
  static biomarkers::Columns at_rest();

  /// The energy account starts at the current state (the coupling's start).
  void start_energy();

private:
  /// The solid's energy balance over the puff [mJ, whole model]: its
  /// change of kinetic and strain energy, its mass damping's dissipation
  /// (2 c KE) and the cavities' work (p dV) against the work the air does
  /// on it, taken two ways: from the air's own stress on the interface
  /// (air::Problem::traction_power), independent of the coupling, and from
  /// the reaction the coupling moves onto the solid (Power::solid); each
  /// trapezoidal in time.
  struct Energy
  {
    /// The solid at a step: KE, KE + SE, each cavity's volume and pressure.
    struct State
    {
      double kinetic = 0, total = 0;
      std::vector<double> volumes, pressures;
    };
    double traction = 0, reaction = 0, change = 0, damping = 0, cavities = 0;
    double start = 0;                   ///< KE + SE when the coupling started
    double power = 0, reaction_power = 0; ///< the last step's
    State last;                         ///< the last step's
  };
  Energy::State energy_state() const;
  double symmetry() const;
  /// The energy account at a converged, advanced step of length dt.
  void account(double dt, double traction_power);

  SolidBlock& _solid;
  AirBlock& _air;
  Energy _energy;
  double _step = 0; ///< the step's length [ms]
  fsi::Power _power;
  double _jacobian = 1, _force = 0;
  /// The air mesh's smallest Jacobian, the largest interface power
  /// mismatch and power over the steps so far [W].
  double _worst_jacobian = 1, _worst_power = 0, _largest_power = 0;
};

} // namespace nct
