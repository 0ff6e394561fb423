// Finite-strain viscoelasticity of the matrix (forms/viscoelasticity.py):
// the Prony terms' history at the cell quadrature points, and its part of
// the solid's dynamic residual and Jacobian.
#pragma once

#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <dolfinx/fem/Constant.h>
#include <dolfinx/fem/Expression.h>
#include <dolfinx/fem/Form.h>
#include <dolfinx/fem/Function.h>
#include <dolfinx/mesh/MeshTags.h>

#include "section/section.h"

namespace nct::io
{
class CheckpointWriter;
class CheckpointReader;
} // namespace nct::io

namespace nct::solid
{

struct Element;

/// The history of the Prony terms (S_iso,n and each Q_k,n at every cell
/// quadrature point) and the forms that add the viscous stress to the
/// dynamic balance. The quasi-static phases are the long-time response:
/// this module acts in the dynamics only, from start().
class Viscoelasticity
{
public:
  /// `coefficients` must hold u, u_old, c10 and the Prony fields
  /// modulus_k and relaxation_time_k; `constants` dt and alpha_f, shared
  /// with the solid's dynamic forms; `cells` the solid's law tags.
  Viscoelasticity(
      const Element& element,
      const std::map<std::string, std::shared_ptr<const dolfinx::fem::Function<double>>>&
          coefficients,
      const std::map<std::string, std::shared_ptr<const dolfinx::fem::Constant<double>>>&
          constants,
      const dolfinx::mesh::MeshTags<std::int32_t>& cells);

  /// The history of a state at rest: S_iso,n at the current u, Q_k,n = 0.
  void start();
  /// Add the viscous part of the residual at the current u to `b`
  /// (owned and ghost entries; the caller scatters).
  void add_residual(std::span<double> b) const;
  /// Its Jacobian dR_visc/du.
  const dolfinx::fem::Form<double>& jacobian_form() const { return *_J; }
  /// After a converged step, before u_old moves on: the work done on the
  /// viscous branches over the step is summed, then the history becomes
  /// the step's end state. Collective.
  void advance();
  /// The work done on the viscous branches since start() [mJ], meshed
  /// part; over a load cycle that ends relaxed, the energy dissipated.
  double work() const { return _work; }

  /// The history under "solid/viscoelasticity/", keyed by cell. Collective.
  void save(io::CheckpointWriter& checkpoint) const;
  void restore(const io::CheckpointReader& checkpoint);

private:
  /// The values of `e` at each local cell's quadrature points into the
  /// history fields, six entries each.
  void evaluate(const dolfinx::fem::Expression<double>& e,
                const std::vector<std::shared_ptr<dolfinx::fem::Function<double>>>& fields) const;
  /// A history field's values, one block per owned cell (points x 6).
  std::vector<double> cell_blocks(const dolfinx::fem::Function<double>& f) const;

  std::vector<std::int32_t> _cells; ///< the owned cells, where the history is evaluated
  std::shared_ptr<dolfinx::fem::Function<double>> _stress_old;
  std::vector<std::shared_ptr<dolfinx::fem::Function<double>>> _overstress_old;
  std::shared_ptr<dolfinx::fem::Expression<double>> _stress_new, _overstress_new;
  std::shared_ptr<dolfinx::fem::Form<double>> _R, _J, _work_form;
  double _work = 0;
};

} // namespace nct::solid
