// The dimension of a model (forms/section.py): a 3D mesh, or a 2D section.
#pragma once

#include <string>

namespace nct::section
{

/// A 3D model, an axisymmetric section (r = x[0], z = x[1]: every
/// integral per radian) or a plane-strain one (per unit thickness).
enum class Dimension
{
  three,
  axisymmetric,
  plane
};

/// The scene's name of a dimension (mesh.dimension).
inline std::string name(Dimension d)
{
  return d == Dimension::three ? "3d" : d == Dimension::axisymmetric ? "axisymmetric" : "plane";
}

/// The mesh's geometric and topological dimension: 3, or 2 for a section.
inline int mesh_dimension(Dimension d) { return d == Dimension::three ? 3 : 2; }

} // namespace nct::section
