// XDMF time series on a moving mesh: each step holds its own geometry.
#pragma once

#include <map>
#include <memory>
#include <string>

#include <dolfinx/fem/Function.h>
#include <dolfinx/mesh/Mesh.h>

#include "io/output.h"

namespace nct::io
{

/// One XDMF file per function on a mesh that moves: each time step holds
/// its own geometry (the reference coordinates plus a displacement), so
/// ParaView shows the mesh moving. Files are valid after every write.
///
/// The topology is written once per file, in the first step's Grid; later
/// steps include it by reference. Values are written per geometry node, as
/// dolfinx's XDMFFile does. The mesh is never modified.
class MovingFields
{
public:
  MovingFields(const RunFolder& folder, std::shared_ptr<const dolfinx::mesh::Mesh> mesh);
  ~MovingFields();
  MovingFields(const MovingFields&) = delete;
  MovingFields& operator=(const MovingFields&) = delete;

  /// Append `f` (continuous P1, scalar or vector, on `mesh`) at `time` to <f.name>.xdmf, on
  /// the mesh displaced by `displacement` (continuous P1 vector on `mesh`). The ghost
  /// values of both must be up to date. Collective on the mesh's communicator.
  void write(const dolfinx::fem::Function<double>& f,
             const dolfinx::fem::Function<double>& displacement, double time);

private:
  struct File; ///< an open HDF5 file and its XML document
  const RunFolder& _folder;
  std::shared_ptr<const dolfinx::mesh::Mesh> _mesh;
  std::map<std::string, std::unique_ptr<File>> _files;
};

} // namespace nct::io
