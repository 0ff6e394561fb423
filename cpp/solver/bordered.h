// A monolithic system bordered, or not, by a few unknowns of its first
// field's (a closed cavity's pressures): the one way the coupled systems
// (the solid with its humor, with the air) take their cavities.
#pragma once

#include <functional>
#include <map>
#include <string>
#include <vector>

#include <dolfinx/la/Vector.h>
#include <petscmat.h>

#include "solver/monolithic.h"
#include "solver/newton.h"

namespace nct::solver
{

/// Unknowns that border the first field of a system (cavity::Closed).
class Border
{
public:
  virtual ~Border() = default;
  /// The first field's problem takes the unknowns' values.
  virtual void apply() = 0;
  /// g = the unknowns' own residual.
  virtual void constraints(std::vector<double>& g) const = 0;
  /// B[i] = dR/dy_i, C[i] = dG_i/du, laid out as the first field, and D = dG/dy.
  virtual void border(std::vector<dolfinx::la::Vector<double>>& B,
                      std::vector<dolfinx::la::Vector<double>>& C, std::vector<double>& D) const
      = 0;
  /// The unknowns, for a System's y.
  virtual std::vector<double>* unknowns() = 0;
};

/// The Newton system on `U`'s stacked unknowns, bordered by `border` (null:
/// none). `residual(b)` and `jacobian(A)` (entries added, not assembled)
/// see the unknowns unpacked and the border applied; `first` is laid out
/// as U's first field (a scratch vector); the Jacobian's final assembly
/// (its entries sent to the ranks that own their rows) is timed into
/// `*matrix_time` if given. The caller sets `inadmissible` and `locate`.
System bordered(Monolithic& U, Border* border, const dolfinx::la::Vector<double>& first,
                std::function<void(dolfinx::la::Vector<double>&)> residual,
                std::function<void(Mat)> jacobian, double* matrix_time = nullptr);

} // namespace nct::solver
