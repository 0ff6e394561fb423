// The humors in the closed cavities in the dynamics (cavity.humor_inertia):
// what a humor contributes to the solid's Newton system, whichever model
// it is: massless, translating with the eye (forms/humor_inertia.py),
// flowing (forms/humor_flow.py) or Navier-Stokes (forms/air_ale.py).
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include <nlohmann/json.hpp>
#include <petscmat.h>

#include "biomarkers/record.h"
#include "cavity/cavity.h"
#include "dynamics/time_step.h"
#include "fsi/coupled.h"
#include "io/checkpoint.h"
#include "io/moving_fields.h"
#include "io/output.h"
#include "meshio/model.h"
#include "settings/settings.h"
#include "solid/problem.h"
#include "solver/newton.h"

namespace nct::humor
{

/// The humor mesh's groups: per cavity, its volume groups and the facet
/// groups it shares with the solid's wall of that cavity; the axis of an
/// axisymmetric section and the symmetry planes, on which the humor mesh
/// slides; openings at the cavity's pressure (p~ = 0, the mesh held); the
/// lid on the solid's cut, which moves with the cut face's mean normal
/// displacement (forms/support.py). Every other boundary facet is a rigid
/// wall (dp/dn = 0, the mesh held).
struct Boundaries
{
  std::vector<std::vector<std::int32_t>> volumes, walls; ///< per cavity
  std::vector<std::int32_t> axis, symmetry, open, lid;
};

/// A humor: its unknowns, residual and Jacobian blocks in the dynamics
/// (beside the solid's and its cavities'), its time integration, its
/// record and its checkpoint. The defaults are the massless humor's: the
/// solid's own system with its cavities, the solid's integrator, nothing
/// recorded. Acts in the dynamics only; before them the cavities alone
/// hold the humor.
class Humor
{
public:
  explicit Humor(solid::Problem& solid) : _solid(solid) {}
  virtual ~Humor() = default;
  Humor(const Humor&) = delete;
  Humor& operator=(const Humor&) = delete;

  /// Its cavity.humor_inertia value.
  virtual const char* name() const = 0;
  /// Its mesh and unknowns into the summary and the log (a meshed humor's).
  virtual void describe(nlohmann::json&, io::RunFolder&) const {}

  /// At the start of the dynamics, on the solid's current state.
  virtual void start() {}
  /// The Newton system of the dynamics: the solid with its cavities,
  /// `closed` (their pressures unknowns) or else `open`, and the humor.
  virtual solver::System system(cavity::Closed* closed, cavity::Open& open)
  {
    return closed ? closed->system() : open.system();
  }
  /// The name of its own Newton system and a matrix with its pattern; a
  /// null name: the solid's system (its matrix, its factorisation).
  virtual const char* system_name() const { return nullptr; }
  virtual Mat create_matrix() { return nullptr; }
  /// The next step: its length and the solid's integrator.
  virtual void set_time_step(const dynamics::TimeStep& step) { _solid.set_time_step(step); }
  /// After a converged step: the new state becomes the old one.
  virtual void advance() { _solid.advance(); }
  /// Whether predict() gives the next step's first iterate, and that.
  virtual bool predicts() const { return true; }
  virtual void predict() { _solid.predict(); }

  /// What it adds to cavity c's pressure multiplier to give the humor's
  /// mean pressure [MPa].
  virtual double pressure_shift(std::size_t) const { return 0; }
  /// Its columns of the steps' state (`cavities`: the cavities' names).
  virtual void state(const std::vector<std::string>&, biomarkers::Columns&) const {}
  /// Its columns of the frames' energies.
  virtual void energies(biomarkers::Columns&) const {}
  /// Its kinetic energy at the last converged step [mJ, meshed part].
  virtual double kinetic_energy() const { return 0; }
  /// Its fields at `time` into `files` (output.fields), on its mesh. Collective.
  virtual void write(io::MovingFields&, double) {}
  /// Its extremes over the dynamics into the summary.
  virtual void summarise(nlohmann::json&) const {}
  /// Its state at a checkpoint (fields into `writer`), and back, in the dynamics.
  virtual nlohmann::json save(io::CheckpointWriter&) const { return nullptr; }
  virtual void restore(const io::CheckpointReader&, const nlohmann::json&) { start(); }

  /// The field it joins the coupled air's system with (puff.load =
  /// "fsi"), or null: its mass is then the solid's forms' (or none).
  virtual fsi::Joined* joined() { return nullptr; }

protected:
  solid::Problem& _solid;
};

/// The humor's mesh, its groups and the solid's wall it flows along.
struct Mesh
{
  const meshio::Tagged& solid;          ///< the solid's mesh
  std::vector<std::int32_t> walls;      ///< the solid's cavity wall groups, all cavities
  const std::optional<meshio::Tagged>& humor; ///< its own mesh (flow, navier_stokes)
  const Boundaries& boundaries;
};

/// The humor cavity.humor_inertia names, on `solid` (whose forms hold the
/// translating humor's mass). `dt` [ms]: the nominal time step (the Navier-Stokes
/// humor's stabilisation).
std::unique_ptr<Humor> make(solid::Problem& solid, const Mesh& mesh, const CavitySettings& cavity,
                            double dt);

/// A meshed humor's description: its cells and unknowns into the summary
/// (humor_cells, humor_dofs), a line into the log.
void describe_mesh(nlohmann::json& summary, io::RunFolder& folder, const dolfinx::mesh::Mesh& mesh,
                   std::int64_t dofs, const char* unknowns, std::size_t wall_nodes,
                   const char* name);

} // namespace nct::humor
