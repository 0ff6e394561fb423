// The air block: the air on its mesh, its inlet in time, its record, and
// the settings it takes of the scene.
#pragma once

#include <functional>
#include <memory>
#include <optional>
#include <string>

#include <petscksp.h>

#include "air/problem.h"
#include "biomarkers/record.h"
#include "mesh_motion/problem.h"
#include "run/air_output.h"
#include "run/block.h"
#include "run/stepper.h"
#include "settings/settings.h"

namespace nct
{

/// What the air block takes of the scene: [air] and [inlet] (with
/// output.force_on), the puff's time course that the inlet follows and the
/// measured pulse's shape the check built, a file mesh's inlet table, the
/// model's dimension, whether fields are written.
struct AirBlockSettings
{
  AirSettings air;
  double peak_time, width_t;             ///< the inlet's Gaussian in time [ms]
  std::optional<puff::PulseShape> pulse; ///< its measured pulse (inlet.history = "pulse")
  std::vector<std::array<double, 4>> inlet_table; ///< a file mesh's: x, y, z [mm], u [m/s]
  section::Dimension dimension;
  bool fields; ///< output.fields
};

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

} // namespace nct
