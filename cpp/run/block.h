// A physics block of a model, and the meshes the blocks are built on.
#pragma once

#include <array>
#include <map>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "air/domain.h"
#include "eye/geometry.h"
#include "io/checkpoint.h"
#include "io/output.h"
#include "humor/humor.h"
#include "meshio/model.h"
#include "solid/problem.h"

namespace nct
{

/// Everything the solid's mesh brings: the distributed mesh, its parts and
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
  /// The humors' mesh (cavity.humor_inertia = "flow") and its groups.
  std::optional<meshio::Tagged> humor;
  humor::Boundaries humor_boundaries;
};

/// The air's mesh: the air domain meshed with the idealised eye (or in
/// its place) in one gmsh model, so that the eye's anterior surface is
/// the air's wall node for node; or a file mesh's fluid groups.
struct AirMesh
{
  meshio::Tagged mesh;
  air::Domain domain;
  eye::Derived eye;  ///< the eye's shape (apex_y), also without the eye
  std::int64_t eye_cells = 0, air_cells = 0; ///< tetrahedra of the whole model
};

/// A physics block of a model: its unknowns and forms on its mesh, and
/// what a run needs of each block alike.
class Block
{
public:
  virtual ~Block() = default;
  /// Its name in checkpoints ("solid", "air", "mesh_motion", "coupling").
  virtual const char* name() const = 0;
  /// What it is (mesh, degree, unknowns) into the summary and the log.
  virtual void describe(nlohmann::json& summary, io::RunFolder& folder) const = 0;
  /// Its forms' and mesh's identity: a checkpoint must match it.
  virtual std::string identity() const { return ""; }
  /// Its state at a checkpoint (fields into `writer`, the rest returned);
  /// restore() takes it back, its files continued in `folder`. Collective.
  virtual nlohmann::json save(io::CheckpointWriter& writer) const = 0;
  virtual void restore(const io::CheckpointReader& checkpoint, const nlohmann::json& state,
                       io::RunFolder& folder)
      = 0;
  /// Its tables so far, whole (also when a run fails).
  virtual void write_tables() const {}
  /// Its final state into the summary, once the run is through.
  virtual void summarise(nlohmann::json&) const {}
  /// Wall time spent writing its fields [s].
  virtual double t_output() const { return 0; }
};

} // namespace nct
