// The mass of the closed cavities' humors as the inertia of their
// translation (forms/humor_inertia.py): the moments M of the humors, their
// inertial forces as bordering unknowns, and their part of the solid's
// dynamic residual and Jacobian.
#pragma once

#include <map>
#include <memory>
#include <span>
#include <string>
#include <vector>

#include <dolfinx/fem/Constant.h>
#include <dolfinx/fem/Form.h>
#include <dolfinx/fem/Function.h>
#include <dolfinx/la/Vector.h>
#include <dolfinx/mesh/MeshTags.h>

namespace nct::io
{
class CheckpointWriter;
class CheckpointReader;
} // namespace nct::io

namespace nct::solid
{

struct Element;

/// The humors' inertial forces f_j, one per cavity and kept component
/// (j = c * components + i), each the multiplier of
/// G_j = (M_j(u) - M*_j) / V_c - f_j / (rho V_c c) = 0, so that
/// f_j = rho (d2M_j/dt2) at the generalised-alpha level n+1-alpha_m; the
/// residual gains sum_j (f_j / V_c) dM_j/du. Every quantity is the meshed
/// part's. Acts in the dynamics only, from start().
class HumorInertia
{
public:
  /// `constants` must hold x0, lid_1, lid_2 (shared with the solid's forms)
  /// and dt, alpha_m, beta, gamma (its time step); `facets` the solid's load
  /// tags; `components` the axes kept (those of no mirror plane; the
  /// axis of an axisymmetric section); `density` [g/mm^3].
  HumorInertia(
      const Element& element, std::shared_ptr<const dolfinx::fem::Function<double>> u,
      const std::map<std::string, std::shared_ptr<const dolfinx::fem::Constant<double>>>&
          constants,
      const dolfinx::mesh::MeshTags<std::int32_t>& facets, std::size_t cavities,
      std::vector<int> components, double density);

  /// Number of unknowns (cavities times components).
  std::size_t size() const { return _volumes.size() * _components.size(); }
  /// The component (axis) of unknown j.
  int component(std::size_t j) const { return _components[j % _components.size()]; }
  /// The cavity of unknown j.
  std::size_t cavity(std::size_t j) const { return j / _components.size(); }

  /// At rest at the current u: the moments now, their rates zero;
  /// `volumes` the cavities' held volumes [mm^3, meshed part].
  void start(const std::vector<double>& volumes);
  /// The inertial forces now [N, meshed part].
  void set_forces(std::span<const double> f);
  std::span<const double> forces() const { return _forces; }
  /// Add sum_j (f_j / V_c) dM_j/du at the current u to `b` (owned and
  /// ghost entries; the caller scatters and sets the Dirichlet rows).
  void add_residual(std::span<double> b) const;
  /// Its Jacobian, sum_j (f_j / V_c) d2M_j/du2.
  const dolfinx::fem::Form<double>& jacobian_form() const;
  /// g[j] = G_j at the current u and forces. Collective.
  void constraints(std::span<double> g) const;
  /// b = dM_j/du / V_c, the border's column and row of unknown j.
  void border(std::size_t j, dolfinx::la::Vector<double>& b) const;
  /// dG_j/df_j = -1 / (rho V_c c).
  double compliance(std::size_t j) const;
  /// The humor's mean pressure less the cavity's multiplier [MPa]:
  /// -(f / V) . M / V of cavity c.
  double mean_pressure_shift(std::size_t c) const;
  /// The humors' kinetic energy as translating, sum_j rho (dM_j/dt)^2 / (2 V_c),
  /// at the last converged step [mJ, meshed part].
  double kinetic_energy() const;
  /// After a converged step: the Newmark updates of M's rates. Collective.
  void advance();

  /// The moments' state under "solid/humor_inertia". Collective.
  void save(io::CheckpointWriter& checkpoint) const;
  void restore(const io::CheckpointReader& checkpoint);

private:
  /// M_j at the current u, every j [mm^4]. Collective.
  std::vector<double> moments() const;
  /// The weights g_c of the forms: f_c / V_c.
  void weigh_by_forces() const;
  /// The time step's dt, alpha_m, beta, gamma and c = (1 - alpha_m) / (beta dt^2).
  struct Step
  {
    double dt, alpha_m, beta, gamma, c;
  };
  Step step() const;

  std::map<std::string, std::shared_ptr<const dolfinx::fem::Constant<double>>> _time;
  std::vector<std::shared_ptr<dolfinx::fem::Constant<double>>> _g; ///< per cavity
  std::shared_ptr<dolfinx::fem::Form<double>> _moment, _load, _tangent;
  std::vector<int> _components;
  double _density;
  std::vector<double> _volumes;                  ///< per cavity [mm^3]
  std::vector<double> _forces;                   ///< [N]
  std::vector<double> _m_old, _m_rate, _m_accel; ///< M_n and its rates, per unknown
};

} // namespace nct::solid
