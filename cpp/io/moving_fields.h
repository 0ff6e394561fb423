// XDMF time series on a moving mesh: each step holds its own geometry.
#pragma once

#include <map>
#include <memory>
#include <string>

#include <dolfinx/fem/Function.h>
#include <dolfinx/mesh/Mesh.h>
#include <nlohmann/json.hpp>

#include "io/output.h"
#include "io/xdmf_series.h"

namespace nct::io
{

/// One XDMF file per function on a mesh that moves: each time step holds
/// its own geometry (the reference coordinates plus a displacement), so
/// ParaView shows the mesh moving. Files are valid after every write.
///
/// The topology is written once per file, in the first step's Grid; later
/// steps include it by reference (a resumed run on a partition that lays
/// the mesh out otherwise writes it again). Values are written per
/// geometry node, as dolfinx's XDMFFile does. The mesh is never modified.
class MovingFields
{
public:
  MovingFields(const RunFolder& folder, std::shared_ptr<const dolfinx::mesh::Mesh> mesh);
  MovingFields(const MovingFields&) = delete;
  MovingFields& operator=(const MovingFields&) = delete;

  /// Append `f` (continuous P1, scalar or vector, on `mesh`) at `time` to <f.name>.xdmf, on
  /// the mesh displaced by `displacement` (continuous P1 vector on `mesh`). The ghost
  /// values of both must be up to date. Collective on the mesh's communicator.
  void write(const dolfinx::fem::Function<double>& f,
             const dolfinx::fem::Function<double>& displacement, double time);
  /// What a checkpoint keeps: each file's steps and the mesh's layout.
  /// Collective.
  nlohmann::json state() const;
  /// Continue the files as `state` left them: the steps after it deleted.
  /// Collective.
  void resume(const nlohmann::json& state);

private:
  std::shared_ptr<const dolfinx::mesh::Mesh> _mesh;
  XdmfFiles _files;
};

} // namespace nct::io
