// A scene's model: the mesh with its parts and boundaries, and the solid on it.
#pragma once

#include <array>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include <mpi.h>

#include "air/domain.h"
#include "air/problem.h"
#include "eye/geometry.h"
#include "fsi/coupled.h"
#include "mesh_motion/problem.h"
#include "meshio/model.h"
#include "puff/load.h"
#include "scene/scene.h"
#include "solid/problem.h"

namespace nct
{

/// Everything a scene's mesh brings: the distributed mesh, its parts and
/// boundaries, how fibres are laid, where volumes and probes are taken.
struct MeshSetup
{
  meshio::Tagged mesh;
  std::map<std::int32_t, std::string> parts;
  solid::Boundaries boundaries;
  solid::FibreRule fibres;
  std::array<double, 3> volume_origin;
  std::vector<std::array<double, 3>> probes;
  std::vector<std::string> probe_names;
  std::vector<std::string> cavity_names; ///< one per entry of boundaries.cavities
};

/// The air's mesh: the air domain meshed with the idealised eye (or in
/// its place) in one gmsh model, so that the eye's anterior surface is
/// the air's wall node for node.
struct AirMesh
{
  meshio::Tagged mesh;
  air::Domain domain;
  eye::Derived eye;  ///< the eye's shape (apex_y), also without the eye
  std::int64_t eye_cells = 0, air_cells = 0; ///< tetrahedra of the whole model
  double t_mesh = 0; ///< wall time of meshing and distribution [s]
};

/// A scene's model: the physics blocks it switches on, on their meshes.
/// - the solid (every scene but the air alone): its mesh, built or read;
/// - the air (puff.load = "air": alone, on a fixed mesh about a rigid eye
///   or none; "fsi": on a moving mesh about the eye, meshed with it);
/// - the mesh motion and the coupling of the solid and the air ("fsi").
struct Model
{
  MeshSetup setup;
  std::unique_ptr<solid::Problem> problem; ///< the solid, or null
  bool eye = false;   ///< the parametric eye (else an external mesh)
  double t_mesh = 0;  ///< wall time of meshing and distribution [s]
  double t_setup = 0; ///< wall time of the problem's setup [s]
  std::optional<AirMesh> air_mesh;
  std::unique_ptr<air::Problem> air;
  std::unique_ptr<mesh_motion::Problem> motion;
  std::unique_ptr<fsi::Coupled> coupled;
};

/// Build the scene's model. Throws scene::Error on bad input.
Model make_model(MPI_Comm comm, const scene::Scene& scene);

/// The puff's air pressure p(r, t) [mmHg] (puff.load), or null for none.
/// Throws scene::Error for a table that cannot be read.
std::unique_ptr<puff::Load> puff_load(const scene::Scene& scene);
/// The measured pulse's shape in time from puff.peak, rise_rate,
/// fall_rate and pulse_duration; throws scene::Error naming the keys.
puff::PulseShape pulse_shape(const scene::Scene& scene);

/// The checks of a scene that need more than its keys: the eye's geometry,
/// an external mesh's groups against the scene's materials and boundaries.
/// Nothing is meshed; throws scene::Error.
void check(MPI_Comm comm, const scene::Scene& scene);

} // namespace nct
