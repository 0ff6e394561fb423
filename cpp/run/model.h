// A scene's model: the physics blocks it switches on, on their meshes.
#pragma once

#include <memory>
#include <vector>

#include <mpi.h>
#include <nlohmann/json.hpp>

#include "run/block.h"
#include "settings/settings.h"

namespace nct
{

class SolidBlock;
class AirBlock;
class MeshMotionBlock;
class CouplingBlock;

/// A scene's model: the blocks it switches on.
/// - the solid (every scene but the air alone): its mesh, built or read;
/// - the air (puff.load = "air": alone, on a fixed mesh about a rigid eye
///   or none; "fsi": on a moving mesh about the eye, meshed with it);
/// - the mesh motion and the coupling of the solid and the air ("fsi").
class Model
{
public:
  Model(Model&&) noexcept;
  ~Model();
  bool eye = false;   ///< the parametric eye (else an external mesh)
  double t_mesh = 0;  ///< wall time of meshing and distribution [s]
  double t_setup = 0; ///< wall time of the blocks' setup [s]
  std::unique_ptr<SolidBlock> solid;
  std::unique_ptr<AirBlock> air;
  std::unique_ptr<MeshMotionBlock> mesh_motion;
  std::unique_ptr<CouplingBlock> coupling;
  /// The blocks there are, in the order above.
  std::vector<Block*> blocks() const;

private:
  Model() = default;
  friend Model make_model(MPI_Comm comm, const Input& input);
};

/// Mesh the scene and build its blocks. Collective.
Model make_model(MPI_Comm comm, const Input& input);

} // namespace nct
