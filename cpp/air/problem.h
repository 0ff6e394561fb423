// The air: incompressible Navier-Stokes in ALE form (forms/air.py) on a
// tagged mesh, with its boundary conditions and BDF time stepping.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <memory>
#include <utility>
#include <vector>

#include <dolfinx/fem/Constant.h>
#include <dolfinx/fem/DirichletBC.h>
#include <dolfinx/fem/Form.h>
#include <dolfinx/fem/Function.h>
#include <dolfinx/la/Vector.h>
#include <petscmat.h>

#include "meshio/model.h"

namespace nct::air
{

/// Properties of the air [g/mm^3, MPa ms] and of its outlet condition.
struct Fluid
{
  double density = 1.25e-6;
  double viscosity = 1.8e-8;
  double backflow = 1.0; ///< beta of the outlet's backflow traction (>= 1/2: energy stable)
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
};

/// The mixed velocity-pressure problem of forms/air.py. The mesh velocity
/// w is a coefficient (zero: a rigid mesh); a moving mesh changes the
/// geometry's coordinates and w together.
class Problem
{
public:
  /// Velocity and pressure are continuous piecewise linear (equal order,
  /// stable by PSPG): the cheapest pair per unknown, and the mesh's own
  /// element, which the mesh motion and the solid's P1 geometry share.
  /// `velocity_scale` [mm/ms]: a typical speed, which makes the continuity
  /// rows forces like the momentum rows (continuity_scale = rho U).
  Problem(const meshio::Tagged& m, const Fluid& fluid, const Boundaries& boundaries,
          double velocity_scale);

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
  /// The converged step becomes the old state.
  void advance();

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

  /// The unknowns (u, p) now, at t_n and at t_{n-1}; the mesh velocity.
  std::shared_ptr<dolfinx::fem::Function<double>> up, up_n, up_nm1, w;
  /// Dofs of (u, p) (local, owned and ghost) of the velocity and the pressure.
  const std::vector<std::int32_t>& velocity_dofs() const { return _velocity_dofs; }
  const std::vector<std::int32_t>& pressure_dofs() const { return _pressure_dofs; }
  std::int64_t dofs() const;

private:
  std::shared_ptr<dolfinx::fem::Form<double>> _R, _J;
  std::map<std::string, std::shared_ptr<dolfinx::fem::Constant<double>>> _constants;
  std::shared_ptr<dolfinx::fem::Function<double>> _inlet_shape, _inlet; ///< collapsed velocity space
  std::vector<std::shared_ptr<const dolfinx::fem::DirichletBC<double>>> _bcs;
  std::vector<std::int32_t> _velocity_dofs, _pressure_dofs;
  double _bc_diagonal = 1;
  double _last_dt = 0; ///< the last advanced step's length (0 before any)
  double _dt = 0;
};

} // namespace nct::air
