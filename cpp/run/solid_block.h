// The solid block: the solid on its mesh and what acts on it (its
// cavities, the press and the prescribed puff, its support) and what it
// records (the steps, probes and fields, the puff's frames).
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "biomarkers/record.h"
#include "cavity/cavity.h"
#include "humor/humor.h"
#include "io/moving_fields.h"
#include "io/output.h"
#include "run/block.h"
#include "run/stepper.h"
#include "settings/settings.h"
#include "solid/problem.h"
#include "solver/newton.h"

namespace nct
{

/// What the solid block takes of the scene: its keys ([fem], [cavity],
/// [press], ...) and its parts' materials, the time step, the puff that
/// loads it and its frames' clock, whether fields are written.
struct SolidBlockSettings
{
  SolidSettings solid;
  std::map<std::string, solid::Material> materials; ///< by part
  /// The meshed Navier-Stokes humor's stabilisation time: the nominal
  /// time step [dynamics] dt [ms].
  double humor_stabilisation_time;
  PuffSettings::Load puff;                           ///< none: no frames
  std::shared_ptr<const puff::Load> prescribed;      ///< the prescribed p(r, t) [mmHg], or null
  double frame_rate;                                 ///< the frames' [1/s]
  bool fields;                                       ///< output.fields
};

/// The solid block.
class SolidBlock : public Block
{
public:
  /// The solid on `mesh`; `eye`: the idealised eye (its frames).
  SolidBlock(MeshSetup mesh, SolidBlockSettings settings, bool eye);

  const MeshSetup mesh;
  const SolidBlockSettings settings;
  solid::Problem problem;
  const bool eye;

  // Block
  const char* name() const override { return "solid"; }
  void describe(nlohmann::json& summary, io::RunFolder& folder) const override;
  std::string identity() const override;
  nlohmann::json save(io::CheckpointWriter& writer) const override;
  void restore(const io::CheckpointReader& checkpoint, const nlohmann::json& state,
               io::RunFolder& folder) override;
  void write_tables() const override;
  /// The apex, the probes' last displacements, each cavity's final and
  /// largest pressure and its volume.
  void summarise(nlohmann::json& summary) const override;
  double t_output() const override { return _output ? _output->t_output : 0.0; }

  // The cavities: open at pressures the inflation sets, then closed.
  /// The open cavities' pressures at `f` of the IOP (inflate.iop).
  void inflate(double f);
  /// Each cavity keeps its volume now; its pressure becomes an unknown.
  void close();
  const cavity::Closed* closed() const { return _closed ? &*_closed : nullptr; }
  cavity::Closed* closed() { return _closed ? &*_closed : nullptr; }
  /// The humor in the cavities (cavity.humor_inertia).
  std::unique_ptr<humor::Humor> humor;
  /// The name of the Newton system now if it is the humor's own (in the
  /// dynamics), else null: the solid's.
  const char* humor_system() const { return _dynamic ? humor->system_name() : nullptr; }
  /// The Newton system now: the closed cavities bordered, or open; in the
  /// dynamics with the humor.
  solver::System system();
  /// Each cavity's pressure [mmHg] and volume [mm^3] now.
  biomarkers::Columns cavity_state() const;
  /// Each cavity's pressure now [MPa].
  std::vector<double> cavity_pressures() const
  {
    return _closed ? _closed->pressures() : _open_pressures;
  }

  // The follower pressure on the pressed surface: the press and the prescribed puff.
  /// The press's shape (press.profile) on the pressed surface, before a ramp.
  void start_press();
  /// The press at `f` of its peak (press.pressure).
  void press(double f);
  /// The press now [MPa].
  double press_now() const { return _press; }
  /// The press held and the prescribed puff's pressure at time t [ms].
  void set_load(double t);
  /// The prescribed puff's apex pressure [mmHg] at t (0 without one).
  double apex_load(double t) const;

  /// Zero pressure's results: the mesh as imaged, and its last
  /// pressurised state, from which the inflation starts (empty once used).
  std::vector<double> x_imaged, inflated;
  /// The probes' reference points (zero pressure carries them).
  std::vector<std::array<double, 3>> probes;

  // Dynamics.
  /// Switch to dynamics at the current state (once), integrating over
  /// `step` until the stepper sets another; with a puff on the eye, open
  /// the frames.
  void start_dynamics(const dynamics::TimeStep& step);
  bool dynamic() const { return _dynamic; }
  /// The time integration, for the Stepper.
  Stepper::Dynamics dynamics();

  // The record.
  /// Start the record at pseudo-time t (once; the geometry is final by
  /// then): the reference volumes and probes into the summary, the first fields.
  void open_output(io::RunFolder& folder, nlohmann::json& summary, double t);
  /// This block's keys of a converged step (its cavities, its probes'
  /// displacements) into `step` (which holds its "phase"), its text for the
  /// log; the probes' row into probes.csv, the fields written. Returns the
  /// cavities' state (cavity_state()).
  biomarkers::Columns record(nlohmann::json& step, std::string& text, double time);

  /// The probes' displacements now (every rank gets them).
  std::vector<std::array<double, 3>> probe_displacement() const;
  /// The state at t into the frames (if any): the cavities (cavity_state()
  /// now), `columns`, the energies; the solver's figures go to the step
  /// table only.
  void add_frame(double t, double dt, const solver::NewtonReport& report,
                 const biomarkers::Columns& columns, const biomarkers::Columns& cavities);
  std::optional<biomarkers::Record> frames;

private:
  /// The frames of a puff on the eye.
  void open_frames();
  /// Displacement and von Mises stress at `time` (output.fields).
  void write_fields(double time);

  struct Output
  {
    Output(io::RunFolder& folder, const MeshSetup& mesh, solid::Problem& problem,
           const std::vector<std::array<double, 3>>& points)
        : folder(folder), probes(problem, points),
          fields(folder, mesh.mesh.mesh, problem.coordinate_space()),
          humor(mesh.humor ? std::make_unique<io::MovingFields>(folder, mesh.humor->mesh) : nullptr)
    {
    }
    io::RunFolder& folder;
    solid::Probes probes;
    io::Fields fields;
    /// The humor's pressure on its moving mesh (with its flow).
    std::unique_ptr<io::MovingFields> humor;
    double t_output = 0; ///< wall time spent writing fields [s]
  };
  std::optional<Output> _output;
  std::string _probes_csv; ///< probes.csv so far (rows after the header)
  std::vector<double> _open_pressures; ///< [MPa], while the cavities are open
  std::optional<cavity::Open> _open;
  std::optional<cavity::Closed> _closed;
  double _press_peak;                      ///< [MPa]
  double _press = 0;                       ///< the press now [MPa]
  std::function<double(const std::array<double, 3>&)> _press_profile;
  bool _dynamic = false;
};

} // namespace nct
