// The air: incompressible Navier-Stokes in ALE form (forms/air.py) on a
// tagged mesh, with its boundary conditions and BDF time stepping.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <string>
#include <utility>
#include <vector>

#include <dolfinx/fem/Constant.h>
#include <dolfinx/fem/DirichletBC.h>
#include <dolfinx/fem/Expression.h>
#include <dolfinx/fem/Form.h>
#include <dolfinx/fem/Function.h>
#include <dolfinx/la/Vector.h>
#include <petscmat.h>

#include <nlohmann/json.hpp>

#include "io/checkpoint.h"
#include "meshio/model.h"
#include "section/section.h"

namespace nct::air
{

/// Properties of the air [g/mm^3, MPa ms] and of its outlet condition
/// (keys and defaults: [air], cpp/settings/air.cpp).
struct Fluid
{
  double density;
  double viscosity;
  double backflow; ///< beta of the outlet's backflow traction (>= 1/2: energy stable)
  /// Time scale T of the stabilisation parameter tau [ms] (forms/navier_stokes.py);
  /// infinity leaves its time term out.
  double stabilisation_time;
};

/// Velocity conditions by facet group. Groups in none of these lists are
/// left free: the outlet's natural condition sigma n = 0.
struct Boundaries
{
  /// Groups where some velocity components vanish: walls (0, 1, 2),
  /// symmetry planes (the normal component).
  std::vector<std::pair<std::int32_t, std::vector<int>>> zero;
  std::vector<std::int32_t> inlet;  ///< velocity = set_inlet's field
  std::vector<std::int32_t> outlet; ///< backflow stabilised
  /// The fluid-solid interface of a moving mesh: its velocity is the
  /// solid's (a coupling's constraint, not a condition here); the air's
  /// force on it is measured there.
  std::vector<std::int32_t> interface;
};

/// The mixed velocity-pressure problem of the air, in one of two
/// formulations: on its mesh's own coordinates with a given mesh velocity
/// w (forms/air.py; zero: a rigid mesh; a moving mesh changes the
/// geometry's coordinates and w together), or on a fixed reference mesh
/// that a mesh displacement d maps onto the current air (forms/air_ale.py:
/// the residual depends on d, with an exact derivative, for a monolithic
/// coupled solve; the mesh velocity is the BDF derivative of d).
class Problem
{
public:
  /// Velocity and pressure are continuous piecewise linear (equal order,
  /// stable by PSPG): the cheapest pair per unknown, and the mesh's own
  /// element, which the mesh motion and the solid's P1 geometry share.
  /// `velocity_scale` [mm/ms]: a typical speed, which makes the continuity
  /// rows forces like the momentum rows (continuity_scale = rho U).
  /// `d`: the mesh displacement (P1 vector on the mesh) of the moving
  /// formulation, or null for the fixed one. `dimension`: 3D, or the
  /// section (forms/section.py) a 2D mesh stands for.
  Problem(const meshio::Tagged& m, const Fluid& fluid, const Boundaries& boundaries,
          double velocity_scale, std::shared_ptr<dolfinx::fem::Function<double>> d = nullptr,
          section::Dimension dimension = section::Dimension::three);

  /// The inlet velocity: `shape(x)` per inlet point, times `scale` (set
  /// per step by set_inlet_scale).
  void set_inlet(const std::function<std::array<double, 3>(const std::array<double, 3>&)>& shape);
  /// Scale the inlet's velocity and put every Dirichlet value into up, so
  /// that Newton's residual starts from the balance equations alone.
  void set_inlet_scale(double scale);

  /// The next step's length [ms] and BDF order (1 or 2, variable-step
  /// BDF2 from the last advanced step's length; BDF1 before any): call
  /// before every step. dt = infinity: steady flow.
  void set_time_step(double dt, int order);
  /// The converged step becomes the old state (and, moving, the mesh
  /// velocity of the step is kept for the next step's tau).
  void advance();

  /// The state a checkpoint holds under "air/": the mesh's nodes, (u, p)
  /// now and before, and (moving) the mesh displacements and velocity;
  /// returns the scalars it needs besides (the last step's length).
  nlohmann::json save(io::CheckpointWriter& checkpoint) const;
  /// Read that state back (`scalars`: what save() returned).
  void restore(const io::CheckpointReader& checkpoint, const nlohmann::json& scalars);
  /// The FFCx signatures of the compiled residual and Jacobian.
  const std::string& forms_signature() const { return _forms_signature; }

  /// b = R(u, p), with b = d (u - g) on Dirichlet dofs: d = rho U (1 mm)^2
  /// [N per mm/ms] keeps those rows of the size of the balance's.
  void residual(dolfinx::la::Vector<double>& b);
  /// A = dR/d(u, p) with rows d e_i on Dirichlet dofs.
  void jacobian(Mat A);
  Mat create_matrix() const;

  /// Velocity [mm/ms] and pressure [MPa] of the current state, on their
  /// own (collapsed) spaces: for output and probes.
  void update_fields();
  std::shared_ptr<dolfinx::fem::Function<double>> velocity, pressure;

  /// The unknowns (u, p) now, at t_n and at t_{n-1}; the mesh velocity
  /// (fixed: given; moving: the last step's, for tau).
  std::shared_ptr<dolfinx::fem::Function<double>> up, up_n, up_nm1, w;
  /// Moving: the mesh displacement [mm] now, at t_n and at t_{n-1}.
  std::shared_ptr<dolfinx::fem::Function<double>> d, d_n, d_nm1;
  bool moving() const { return d != nullptr; }
  /// Dofs of (u, p) (local, owned and ghost) of the velocity and the pressure.
  const std::vector<std::int32_t>& velocity_dofs() const { return _velocity_dofs; }
  const std::vector<std::int32_t>& pressure_dofs() const { return _pressure_dofs; }
  std::int64_t dofs() const;

  /// dR/d(u, p) and (moving) dR/dd, the shape derivative.
  const dolfinx::fem::Form<double>& jacobian_form() const { return *_J; }
  const dolfinx::fem::Form<double>& jacobian_mesh_form() const { return *_J_mesh; }
  /// Per local entry of (u, p): 1 on a Dirichlet dof.
  std::vector<std::int8_t> dirichlet_marker() const;
  /// Diagonal of a Dirichlet row [g/ms].
  double bc_diagonal() const { return _bc_diagonal; }
  /// Moving: the air's force on the interface, -integral sigma n da [N]
  /// (the meshed part; every rank gets it).
  std::array<double, 3> interface_force() const;
  /// Moving: the power the air's stress delivers to the solid on the
  /// interface, -integral sigma n . u da [W] (the meshed part; every rank).
  double traction_power() const;
  /// Moving: the pressure's mean over the current domain [MPa] (the
  /// meshed part; every rank gets it).
  double mean_pressure() const;
  /// The owned velocity dofs (local index in (u, p), component) on the
  /// facets of these groups, each node once: where force_on sums.
  std::vector<std::array<std::int32_t, 2>> wall_dofs(const std::vector<std::int32_t>& groups) const;
  /// The air's force on the walls whose wall_dofs these are [N]: minus its
  /// consistent reaction, the residual's velocity rows there before any
  /// condition replaces them (every rank gets it). At a converged state;
  /// for a body's drag and lift.
  std::array<double, 3> force_on(const std::vector<std::array<std::int32_t, 2>>& dofs) const;
  /// Moving: the smallest det F of the mesh map over the cells, and the
  /// reference centroid of its cell (every rank gets it); -inf if NaN.
  std::pair<double, std::array<double, 3>> smallest_mesh_jacobian() const;

private:
  int _gdim = 3; ///< the mesh's dimension
  std::shared_ptr<dolfinx::fem::Form<double>> _R, _J, _J_mesh;
  std::array<std::shared_ptr<dolfinx::fem::Form<double>>, 3> _force;
  std::shared_ptr<dolfinx::fem::Form<double>> _traction_power, _volume, _pressure_volume;
  std::shared_ptr<dolfinx::fem::Expression<double>> _mesh_jacobian;
  std::map<std::string, std::shared_ptr<dolfinx::fem::Constant<double>>> _constants;
  std::shared_ptr<dolfinx::fem::Function<double>> _inlet_shape, _inlet; ///< collapsed velocity space
  std::vector<std::shared_ptr<const dolfinx::fem::DirichletBC<double>>> _bcs;
  std::vector<std::int32_t> _velocity_dofs, _pressure_dofs;
  std::shared_ptr<const dolfinx::mesh::MeshTags<std::int32_t>> _facets;
  double _bc_diagonal = 1;
  double _last_dt = 0; ///< the last advanced step's length (0 before any)
  std::string _forms_signature;
  double _dt = 0;
};

} // namespace nct::air
