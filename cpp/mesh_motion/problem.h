// The mesh motion (forms/mesh_motion.py): the air mesh's displacement,
// extended from the fluid-solid interface into the air.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <limits>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <dolfinx/fem/Constant.h>
#include <dolfinx/fem/Form.h>
#include <dolfinx/fem/Function.h>
#include <dolfinx/la/Vector.h>

#include "meshio/model.h"

namespace nct::mesh_motion
{

/// The extension operator (forms/mesh_motion.py).
struct Settings
{
  std::string model = "harmonic"; ///< "harmonic" or "elastic"
  double stiffening = 1.0;        ///< chi of the Jacobian-based stiffening (0: none)
  double poisson_ratio = 0.3;     ///< nu of the elastic extension
  /// Only the nodes within this distance of the interface move [mm]; the
  /// rest of the mesh is fixed and carries no unknowns.
  double distance = std::numeric_limits<double>::infinity();
  double scale = 1.0; ///< stiffness scale [MPa]: rows in N
};

/// Conditions by facet group: components held at zero (walls, inlet,
/// outlet: all; symmetry planes: the normal one), and the interface,
/// whose displacement the solid gives.
struct Boundaries
{
  std::vector<std::pair<std::int32_t, std::vector<int>>> fixed;
  std::vector<std::int32_t> interface;
};

/// The mesh displacement d (continuous P1, the mesh's own element) on the
/// reference air mesh and its extension operator, restricted to the
/// moving region (the nodes within Settings::distance of the interface).
class Problem
{
public:
  Problem(const meshio::Tagged& mesh, const Settings& settings, const Boundaries& boundaries);

  /// The mesh displacement [mm] (zero outside the moving region).
  std::shared_ptr<dolfinx::fem::Function<double>> d;

  /// Owned nodes (block indices of d's map) that are unknowns, sorted.
  const std::vector<std::int32_t>& active() const { return _active; }
  /// Per local scalar entry of d (owned and ghost): 1 where a boundary
  /// holds it at zero (active nodes only), else 0.
  const std::vector<std::int8_t>& fixed() const { return _fixed; }
  /// Per local scalar entry of d: 1 on the interface, else 0.
  const std::vector<std::int8_t>& interface() const { return _interface; }
  /// Diagonal of a held row [N/mm]: scale times 1 mm.
  double diagonal() const { return _diagonal; }

  /// b = R(d) over the moving cells, summed over the ranks (owned rows);
  /// held rows b = diagonal (d - 0).
  void residual(dolfinx::la::Vector<double>& b);
  /// dR/dd (linear: the reference mesh never moves).
  const dolfinx::fem::Form<double>& jacobian_form() const { return *_J; }

  /// Set d to the extension of a displacement of the interface, zero on
  /// the held boundaries: one linear solve (MUMPS, factorised at the first
  /// call and kept: the operator is the reference mesh's). `g` gives the
  /// displacement of owned interface nodes (block indices of d's map; 3
  /// values each; held components are ignored). The mesh must be at its
  /// reference geometry. For the start of a coupled run, the humor's mesh
  /// (cpp/humor) and tests.
  void extend(const std::vector<std::pair<std::int32_t, std::array<double, 3>>>& g);

  /// Number of unknowns (active scalar entries) over all ranks.
  std::int64_t dofs() const;

private:
  /// extend()'s linear system, factorised once.
  struct Extension;
  std::shared_ptr<Extension> _extension;
  std::shared_ptr<dolfinx::fem::Form<double>> _R, _J;
  std::shared_ptr<const dolfinx::mesh::MeshTags<std::int32_t>> _moving;
  std::map<std::string, std::shared_ptr<dolfinx::fem::Constant<double>>> _constants;
  std::vector<std::int32_t> _active;
  std::vector<std::int8_t> _fixed, _interface;
  double _diagonal = 1;
};

} // namespace nct::mesh_motion
