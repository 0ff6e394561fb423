// The mesh motion block: the air mesh's displacement, extended from the
// interface.
#pragma once

#include "mesh_motion/problem.h"
#include "run/block.h"

namespace nct
{

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

} // namespace nct
