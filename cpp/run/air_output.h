// The air's record of a puff: the jet's centreline, the apex pressure,
// the pressure on the anterior cornea, the velocity and pressure fields.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "air/problem.h"
#include "io/moving_fields.h"
#include "io/output.h"
#include "mesh_motion/problem.h"
#include "meshio/model.h"
#include "run/block.h"
#include "settings/settings.h"

namespace nct
{

struct AirBlockSettings; // run/air_block.h

/// The air's velocity and pressure fields (output.fields) every
/// air.output_interval: on a fixed mesh as XDMF, on a moving one each
/// write on its current mesh, with the mesh displacement.
class AirFields
{
public:
  /// `motion`: the mesh motion, or null for a fixed mesh.
  AirFields(const AirBlockSettings& settings, io::RunFolder& folder, const meshio::Tagged& mesh,
            air::Problem& air, const mesh_motion::Problem* motion);
  /// Write the fields at `time` if they are due (update_fields done).
  void sample(double time);
  double t_output = 0; ///< wall time spent writing fields [s]
  /// When the next fields are due and the files so far, for a checkpoint
  /// (collective); restore() continues them.
  nlohmann::json state() const;
  void restore(const nlohmann::json& state);

private:
  bool _write;      ///< output.fields
  double _interval; ///< air.output_interval [ms]
  air::Problem& _air;
  const mesh_motion::Problem* _motion;
  io::Fields _fields;                        ///< on a fixed mesh
  std::unique_ptr<io::MovingFields> _moving; ///< on a moving one
  double _next_output = 0;
};

/// Distances from the nozzle's exit along the axis where the centreline
/// velocity is recorded [mm].
constexpr double centreline_distances[] = {2, 4, 6, 8, 10};

/// What the air's record writes: centreline.csv (the axial speed 2-10 mm
/// from the nozzle's exit), with the eye corneal_pressure.csv (the air
/// pressure on the anterior cornea's nodes on z = 0, t_ms,r_mm,p_mmHg,
/// the table puff.load = "table" reads; on a moving mesh r is the node's
/// current distance from the axis) and the XDMF velocity and pressure
/// every air.output_interval (on a moving mesh, each step on its current
/// mesh, with the mesh displacement). Points are the air mesh's reference
/// ones (on a moving mesh they move with it: the apex stays on the cornea).
class AirOutput
{
public:
  /// Find the probes on the air mesh as it is now (the reference of a
  /// moving one). `motion`: the mesh motion, or null for a fixed mesh.
  AirOutput(const AirBlockSettings& settings, io::RunFolder& folder, const AirMesh& mesh,
            air::Problem& air, bool with_eye, const mesh_motion::Problem* motion);

  struct Sample
  {
    double apex_pressure = 0; ///< [mmHg]
    double max_speed = 0;     ///< [m/s]
  };
  /// The state at `time` into the tables and, when due, the fields; every
  /// value is computed (collectively) before any row is added.
  Sample sample(double time);
  /// centreline.csv and (with the eye) corneal_pressure.csv, whole.
  void write_tables() const;
  /// The centreline's peaks, the largest speed and the apex pressure's
  /// maximum into the summary.
  void summarise(nlohmann::json& summary) const;
  /// The apex pressure's largest value [mmHg] and when [ms].
  double apex_max() const { return _apex_max; }
  double apex_max_time() const { return _apex_max_time; }
  double t_output() const { return _fields.t_output; }
  /// What has been recorded (the tables, the peaks), for a checkpoint;
  /// restore() takes it back.
  nlohmann::json state() const;
  void restore(const nlohmann::json& state);

private:
  io::RunFolder& _folder;
  air::Problem& _air;
  const mesh_motion::Problem* _motion;
  bool _with_eye;
  meshio::Probes _centreline, _cornea, _apex;
  AirFields _fields;
  std::string _centreline_csv, _table_csv;
  std::vector<double> _centreline_peak;
  double _apex_max, _apex_max_time = 0, _speed_max = 0;
};

/// The air's record of a run on a file mesh: its force on the groups of
/// output.force_on, summed (minus the consistent reaction, each node
/// once), per step into forces.csv (t_ms,fx_N,fy_N,fz_N), the largest
/// speed, and the fields (on the moving mesh of a coupled run).
class FlowOutput
{
public:
  /// `motion`: the mesh motion, or null for a fixed mesh.
  FlowOutput(const AirBlockSettings& settings, io::RunFolder& folder, const meshio::Tagged& mesh,
             air::Problem& air, const mesh_motion::Problem* motion);

  struct Sample
  {
    std::array<double, 3> force{0, 0, 0}; ///< [N]
    double max_speed = 0;                 ///< [m/s]
  };
  /// The force at the converged state, before the step is advanced (the
  /// reaction needs the step's time derivatives). Collective.
  void measure();
  /// The state at `time` (the force as last measured) into the table and,
  /// when due, the fields. Collective.
  Sample sample(double time);
  /// forces.csv, whole.
  void write_tables() const;
  double t_output() const { return _fields.t_output; }
  /// The last force and the largest speed into the summary.
  void summarise(nlohmann::json& summary) const;
  /// What has been recorded (the tables, the peaks), for a checkpoint;
  /// restore() takes it back.
  nlohmann::json state() const;
  void restore(const nlohmann::json& state);

private:
  io::RunFolder& _folder;
  air::Problem& _air;
  std::vector<std::array<std::int32_t, 2>> _wall_dofs; ///< of output.force_on
  bool _axisymmetric = false; ///< forces of the body of revolution: axial only
  bool _forces = false;
  AirFields _fields;
  std::string _forces_csv;
  Sample _last;
  std::array<double, 3> _force{0, 0, 0};
  double _speed_max = 0;
};

/// The air's record of a run, whichever the mesh: the eye's (AirOutput:
/// the apex, the corneal pressure, the centreline) or a file mesh's
/// (FlowOutput: the force on output.force_on).
class AirRecord
{
public:
  /// `eye`: the idealised eye's air (else a file mesh's fluid); `with_eye`:
  /// the eye is in the air (a rigid or coupled wall); `motion`: the mesh
  /// motion, or null for a fixed mesh.
  AirRecord(const AirBlockSettings& settings, io::RunFolder& folder, const AirMesh& mesh,
            air::Problem& air, bool eye, bool with_eye, const mesh_motion::Problem* motion);

  struct Sample
  {
    double apex_pressure = 0;             ///< [mmHg] (the eye)
    double max_speed = 0;                 ///< [m/s]
    std::array<double, 3> force{0, 0, 0}; ///< [N] (a file mesh)
  };
  /// What needs the converged step before it is advanced (the force).
  void measure();
  /// The state at `time` into the tables and, when due, the fields.
  Sample sample(double time);
  void write_tables() const;
  void summarise(nlohmann::json& summary) const;
  /// Wall time spent writing fields [s].
  double t_output() const { return _eye ? _eye->t_output() : _flow->t_output(); }
  /// The eye's record, or null on a file mesh.
  const AirOutput* eye() const { return _eye ? &*_eye : nullptr; }
  /// What has been recorded (the tables, the peaks), for a checkpoint;
  /// restore() takes it back.
  nlohmann::json state() const;
  void restore(const nlohmann::json& state);

private:
  std::optional<AirOutput> _eye;
  std::optional<FlowOutput> _flow;
};

} // namespace nct
