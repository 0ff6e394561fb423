// The coupling block: the solid and the air in one Newton system, and
// what it watches over the puff.
#pragma once

#include <petscksp.h>

#include "biomarkers/record.h"
#include "dynamics/time_step.h"
#include "fsi/coupled.h"
#include "run/air_block.h"
#include "run/block.h"
#include "run/mesh_motion_block.h"
#include "run/stepper.h"
#include "settings/settings.h"

namespace nct
{

class SolidBlock;

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
  dynamics::TimeStep _step; ///< the step now
  fsi::Power _power;
  double _jacobian = 1, _force = 0;
  /// The air mesh's smallest Jacobian, the largest interface power
  /// mismatch and power over the steps so far [W].
  double _worst_jacobian = 1, _worst_power = 0, _largest_power = 0;
};

} // namespace nct
