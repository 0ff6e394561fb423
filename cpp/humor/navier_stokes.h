// The humors as viscous incompressible Navier-Stokes in ALE form (the
// air's forms, forms/air_ale.py) on the humor's mesh, two-way coupled to
// the solid's walls (cpp/fsi): the full equations the hydroelastic
// pressure (humor::Flow) linearises, for checking it.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include <petscmat.h>

#include <nlohmann/json.hpp>

#include "air/problem.h"
#include "dynamics/time_step.h"
#include "fsi/coupled.h"
#include "humor/humor.h"
#include "io/checkpoint.h"
#include "mesh_motion/problem.h"
#include "meshio/model.h"
#include "solid/problem.h"
#include "solver/monolithic.h"
#include "solver/newton.h"

namespace nct::humor
{

/// The humor as a Navier-Stokes fluid (velocity and pressure, P1/P1 with
/// PSPG/SUPG/LSIC, forms/navier_stokes.py) on its mesh, which follows the
/// walls by the mesh motion's harmonic extension; stuck to the walls
/// (no slip) and coupled to them as the air is (fsi::Coupled: the fluid's
/// velocity is the wall's Newmark velocity, its reaction the wall's load).
///
/// Its volume is held by its incompressibility: the constant pressure is
/// the multiplier of the walls' zero net flux (so no cavity::Closed
/// borders the system). The solid's own cavity pressure stays at what it
/// was when the dynamics started (the IOP): p is the humor's pressure
/// above it. The axis and symmetry planes are slip walls, as is the lid
/// across an eye's cut, which must be at rest (the cut clamped).
class NavierStokes final : public Humor
{
public:
  /// Pairs the humor's walls with the solid's `walls` groups by place:
  /// call on the meshes as built, before the solid's reference geometry
  /// moves. `density` [g/mm^3], `viscosity` [MPa ms], `speed` a typical
  /// speed [mm/ms] (the continuity rows' scale), `stabilisation_time` the
  /// time scale T that bounds the stabilisation's tau where the humor is
  /// still [ms] (as the air's, air::Fluid).
  NavierStokes(solid::Problem& solid, const meshio::Tagged& solid_mesh,
               const std::vector<std::int32_t>& walls, const meshio::Tagged& humor,
               const Boundaries& boundaries, double density, double viscosity, double speed,
               double stabilisation_time);

  // Humor
  const char* name() const override { return "navier_stokes"; }
  void describe(nlohmann::json& summary, io::RunFolder& folder) const override;
  /// The humor's mesh onto the solid's current walls, at rest (u = 0, p = 0).
  void start() override;
  /// The coupled Newton system of the solid and the humor: the humor
  /// holds its volume, the wall keeps the cavity's pressure as closed.
  solver::System system(cavity::Closed*, cavity::Open&) override
  {
    return _coupled->system(nullptr);
  }
  const char* system_name() const override { return "solid_humor_navier_stokes"; }
  Mat create_matrix() override { return _coupled->create_matrix(); }
  /// The next step: its length and the solid's integrator (the fluid's
  /// BDF2 after the first step).
  void set_time_step(const dynamics::TimeStep& step) override;
  /// After a converged step: its extremes kept, then the new state becomes
  /// the old one (the solid's too).
  void advance() override;
  bool predicts() const override { return false; }
  /// Its mean pressure once started: p is the humor's above the cavity's.
  double pressure_shift(std::size_t) const override
  {
    return _coupled->started() ? mean_pressure() : 0.0;
  }
  /// Its velocity and pressure on its moving mesh.
  void write(io::MovingFields& files, double time) override;
  /// Its largest pressure range and speed.
  void summarise(nlohmann::json& summary) const override;
  solver::Monolithic& unknowns() { return _coupled->unknowns(); }
  /// Why the state is not admissible (a folded solid element or humor cell), or empty.
  std::string inadmissible() const { return _coupled->inadmissible(); }

  /// Unknowns of the fluid (velocity and pressure).
  std::int64_t dofs() const { return _fluid->dofs(); }
  /// The humor's mean pressure above the solid's cavity pressure [MPa].
  double mean_pressure() const { return _fluid->mean_pressure(); }
  /// The largest range of the pressure over the humor, and its largest
  /// speed, over the steps so far [MPa, mm/ms].
  double pressure_range_max() const { return _range_max; }
  double speed_max() const { return _speed_max; }
  /// The smallest Jacobian of the humor mesh's map over the steps so far.
  double mesh_jacobian_min() const { return _jacobian_min; }
  /// Wall nodes coupled.
  std::size_t wall_nodes() const { return _coupled->interface_nodes(); }
  /// The fluid's velocity and pressure (update_fields() first), on the mesh.
  air::Problem& fluid() { return *_fluid; }
  const std::map<std::string, double>& timings() const { return _coupled->timings(); }

  /// The state a checkpoint holds (the fluid's, the coupling's, the extremes).
  nlohmann::json save(io::CheckpointWriter& checkpoint) const override;
  void restore(const io::CheckpointReader& checkpoint, const nlohmann::json& state) override;

private:
  std::unique_ptr<mesh_motion::Problem> _motion;
  std::unique_ptr<air::Problem> _fluid;
  std::unique_ptr<fsi::Coupled> _coupled;
  double _range_max = 0, _speed_max = 0, _jacobian_min = 1;
};

} // namespace nct::humor
