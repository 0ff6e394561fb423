// The fluid cavities (humors) as seen by the Newton solve: prescribed
// pressures (open) or closed cavities whose pressures are unknowns.
#pragma once

#include <vector>

#include "solid/problem.h"
#include "solver/bordered.h"
#include "solver/newton.h"

namespace nct::cavity
{

/// The solid with prescribed cavity pressures (open cavities, or none):
/// R(u) = 0 and no bordering unknowns.
class Open
{
public:
  explicit Open(solid::Problem& problem) : _problem(problem) {}
  solver::System system();

private:
  solid::Problem& _problem;
  std::vector<double> _none;
};

/// Closed cavities (docs/physics.md section 6): each pressure p_c is the Lagrange
/// multiplier of V_c(u) = V_c,target, so the humor is incompressible.
/// The constraint rows are G_c = (V_c,target - V_c(u)) / s in the meshed
/// part's volume (s the symmetry factor): with R = dPi/du + sum p_c dR/dp_c
/// and dR/dp_c = -dV_c/du, (R, G) is the gradient of the Lagrangian
/// Pi(u) + sum p_c G_c(u), so the bordered matrix is symmetric. In the
/// dynamics, with the humors' mass (solid::HumorInertia), their inertial
/// forces follow the pressures among the unknowns, with their own rows.
class Closed : public solver::Border
{
public:
  /// Close the cavities at the problem's current state: the targets are
  /// the current volumes, the pressures start at `pressures` [MPa].
  Closed(solid::Problem& problem, std::vector<double> pressures);
  /// Closed at volumes held before, `targets` [mm^3], with the humors'
  /// inertial forces `forces` [N] (a checkpoint's).
  Closed(solid::Problem& problem, std::vector<double> pressures, std::vector<double> targets,
         std::vector<double> forces);
  /// The solid with its closed cavities: x = u, y = the unknowns().
  solver::System system();

  /// The pieces a larger system composes, at the problem's current u:
  /// set the problem's cavity pressures (and the humors' forces) from the unknowns,
  void apply() override;
  /// g = the constraints (the unknowns' residual),
  void constraints(std::vector<double>& g) const override;
  /// B[i] = dR/dy_i, C[i] = dG_i/du, laid out as u, and D = dG/dy (row-major).
  void border(std::vector<dolfinx::la::Vector<double>>& B,
              std::vector<dolfinx::la::Vector<double>>& C, std::vector<double>& D) const override;
  /// The unknowns, for a System's y: the pressures [MPa], then in the
  /// dynamics the humors' inertial forces [N, meshed part] if modelled.
  std::vector<double>* unknowns() override;

  /// Cavity pressures [MPa] (the multipliers).
  std::vector<double> pressures() const
  {
    return {_unknowns.begin(), _unknowns.begin() + _targets.size()};
  }
  /// The humors' inertial forces [N, meshed part]; empty when massless or quasi-static.
  std::vector<double> forces() const
  {
    return {_unknowns.begin() + _targets.size(), _unknowns.end()};
  }
  /// Whole-model volumes held [mm^3].
  const std::vector<double>& targets() const { return _targets; }

private:
  solid::Problem& _problem;
  std::vector<double> _unknowns, _targets;
};

} // namespace nct::cavity
