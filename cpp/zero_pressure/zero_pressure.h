// The zero-pressure (stress-free) geometry behind an imaged, pressurised one.
#pragma once

#include <array>
#include <functional>
#include <string>
#include <vector>

#include "solid/problem.h"

namespace nct::zero_pressure
{

/// Stopping and acceleration of the fixed point.
struct Settings
{
  double tolerance = 1e-4; ///< max nodal distance to the imaged geometry [mm]
  int max_iterations = 30;
  bool aitken = true;      ///< Aitken (Irons-Tuck) relaxation of each update
};

/// One fixed-point iteration: the geometric residual r = X + u(X) - x_imaged
/// at the geometry nodes, before the update by omega r.
struct Iteration
{
  double max = 0;   ///< max_nodes |r| [mm]
  double rms = 0;   ///< sqrt(mean_nodes |r|^2) [mm]
  double omega = 0; ///< relaxation of the update that followed (0: none)
  double wall = 0;  ///< [s]
};

struct Report
{
  bool converged = false;
  std::vector<Iteration> iterations;
};

/// Find the stress-free reference geometry X whose pressurised shape is
/// the mesh's current geometry x_imaged (docs/physics.md section 7), by the
/// backward-displacement fixed point
///
///     X_0 = x_imaged,  X_{k+1} = X_k - omega_k (x(X_k) - x_imaged),
///
/// with x(X) = X + u(X) the pressurised shape computed by `pressurise`
/// (it solves problem.u on the current geometry), omega_k = 1 or the
/// Aitken factor omega_k = -omega_{k-1} r_{k-1} . (r_k - r_{k-1}) / |r_k - r_{k-1}|^2
/// (U. Kuttler, W. A. Wall, Comput. Mech. 43 (2008) 61-72, eq. 44).
/// Fibres are laid again on every new geometry. On return the mesh holds
/// the last X and problem.u its pressurised state; `progress` sees each
/// iteration.
Report solve(solid::Problem& problem, const Settings& settings,
             const std::function<void()>& pressurise,
             const std::function<void(int, const Iteration&)>& progress);

/// The mesh's node coordinates replaced by `x` (laid out as the
/// geometry's x) for the lifetime of the object, then restored.
class SwappedGeometry
{
public:
  SwappedGeometry(const dolfinx::mesh::Mesh& mesh, const std::vector<double>& x);
  ~SwappedGeometry();
  SwappedGeometry(const SwappedGeometry&) = delete;
  SwappedGeometry& operator=(const SwappedGeometry&) = delete;

private:
  std::span<double> _x;
  std::vector<double> _saved;
};

/// Max and rms distance [mm] between the geometry nodes pressurised by
/// problem.u, X + u(X), and `x_imaged` (laid out as the geometry's x).
std::array<double, 2> mismatch(const solid::Problem& problem,
                               const std::vector<double>& x_imaged);

/// Points of the geometry `x_from` (laid out as the mesh geometry's x)
/// carried to the mesh's current geometry: same cell, same barycentric
/// coordinates. Every rank gets every point; throws for a point outside.
std::vector<std::array<double, 3>> points_on_current(const dolfinx::mesh::Mesh& mesh,
                                         const std::vector<double>& x_from,
                                         const std::vector<std::array<double, 3>>& points);

} // namespace nct::zero_pressure
