// The solid (formulation forms/solid.py): the displacement u, quasi-static
// or in generalised-alpha dynamics.
#pragma once

#include <array>
#include <functional>
#include <memory>
#include <optional>
#include <set>
#include <string>
#include <vector>

#include <dolfinx/fem/Constant.h>
#include <dolfinx/fem/DirichletBC.h>
#include <dolfinx/fem/Expression.h>
#include <dolfinx/fem/Form.h>
#include <dolfinx/fem/Function.h>
#include <dolfinx/la/Vector.h>
#include <dolfinx/la/petsc.h>

#include "dynamics/time_step.h"
#include "io/checkpoint.h"
#include "meshio/model.h"
#include "section/section.h"
#include "solid/humor_inertia.h"
#include "solid/material.h"
#include "solid/viscoelasticity.h"

namespace nct::solid
{

/// The support of the fixed groups in the dynamics (forms/support.py):
/// springs and dashpots of the whole model's stiffness and damping, spread
/// evenly over the groups' area.
struct Support
{
  double stiffness = 0; ///< K [N/mm]
  double damping = 0;   ///< C [N ms/mm]
};

/// Facet groups (tags of mesh::Tagged::facets) by boundary condition.
struct Boundaries
{
  std::vector<std::int32_t> fixed;        ///< u = 0 (clamped), or the support's
  std::vector<std::int32_t> symmetry;     ///< u . n = 0 on axis-aligned planes
  std::vector<std::int32_t> axis;         ///< u_r = 0 (an axisymmetric section's r = 0)
  /// Walls of up to two cavities (each a list of groups): their pressures act here
  std::vector<std::vector<std::int32_t>> cavities;
  std::vector<std::int32_t> press; ///< the press (and a prescribed puff) acts here
  /// Per cavity: the area [mm^2, meshed part] of its lid, the opening it
  /// has on the fixed groups' plane (forms/support.py); 0 or none: no lid.
  std::vector<double> lids;
  /// Springs and dashpots on the fixed groups from the start of the
  /// dynamics; none: clamped throughout.
  std::optional<Support> support;
  /// The humors' density [g/mm^3] when their mass is modelled in the
  /// dynamics (forms/humor_inertia.py); none: massless.
  std::optional<double> humor_density;
};

/// The discretisation of the solid.
struct Element
{
  int degree = 2;                  ///< of the displacement: 1 or 2
  bool reduced_quadrature = true;  ///< cells at degree 2(degree-1), else 2 degree
  bool mixed = false;              ///< displacement-pressure P2/P0 (forms/solid.py)
  section::Dimension dimension = section::Dimension::three; ///< 3D or a section
};

/// Residual, Jacobian and derived quantities of the solid at the current u.
/// Quasi-static until start_dynamics(); then each residual is the
/// generalised-alpha balance of the step from (u_old, v_old, a_old) to u.
class Problem
{
public:
  /// `fibres` gives the fibre directions of a part at a reference point
  /// (3D; a section's are taken from it, solid/material.h);
  /// `volume_origin` is the point the cavity volume is taken about (on
  /// the axis of an axisymmetric section).
  Problem(const meshio::Tagged& mesh, const Element& element,
          const std::map<std::int32_t, std::string>& parts,
          const std::map<std::string, Material>& materials,
          const FibreRule& fibres, const Boundaries& boundaries,
          std::array<double, 3> volume_origin);

  /// Pressures [MPa] of the cavities, one per cavity.
  void set_cavity_pressures(const std::vector<double>& pressures);
  /// The press: its peak [MPa] on the pressed surface (the profile scales it).
  void set_press(double pressure) { _p_press->value = {pressure}; }
  /// Shape f(X) of the press, evaluated at the current
  /// reference coordinates (1 until set).
  void set_press_profile(const std::function<double(const std::array<double, 3>&)>& f);

  /// b = R(u), with b = u - g on Dirichlet dofs.
  void residual(dolfinx::la::Vector<double>& b);
  /// A = dR/du with identity rows on Dirichlet dofs.
  void jacobian(Mat A);
  /// Zero Jacobian with the sparsity of dR/du.
  /// Block size 3 (one block per node, 2 on a section) inserts a Jacobian 2x faster than
  /// "aij"; "sbaij" keeps only the upper triangle (the lower is ignored as
  /// it is assembled), for an LDL^T factorisation of the symmetric part.
  Mat create_matrix(const std::string& type = "baij") const;

  /// Whole-model cavity volumes (the meshed part times the symmetry factor).
  std::vector<double> cavity_volumes() const;
  /// Number of cavities.
  std::size_t cavities() const { return _volumes.size(); }
  /// b = dR/dp_c: the cavity's load at unit pressure, zero on Dirichlet dofs.
  void cavity_load(std::size_t c, dolfinx::la::Vector<double>& b);
  /// b = dV_c/du of the meshed part of cavity c (no symmetry factor).
  void volume_derivative(std::size_t c, dolfinx::la::Vector<double>& b);

  /// Switch to dynamics from rest at the current u (v = a = 0). With a
  /// support, its springs and dashpots replace the clamp, which leaves
  /// them its reaction as a dead load: the rest stays at rest.
  void start_dynamics(const dynamics::TimeStep& step);
  /// The state a checkpoint holds under "solid/": the reference geometry
  /// (zero pressure moves it), u, and in dynamics the last step's u, v, a
  /// and the support's state. Collective.
  void save(io::CheckpointWriter& checkpoint) const;
  /// Read that state back; in dynamics (`dynamic`) switch to them as
  /// start_dynamics() does, but with the checkpoint's motion (the time
  /// step is set before the next step, set_time_step).
  void restore(const io::CheckpointReader& checkpoint, bool dynamic);
  /// Change the time step (dynamics only).
  void set_time_step(const dynamics::TimeStep& step);
  /// After a converged step: a and v from the Newmark updates, then the
  /// new state becomes the old one.
  void advance();
  /// Dynamics, before advance(): the converged step's local error estimate
  /// in the displacement [mm], (beta - 1/6) dt^2 max|a_{n+1} - a_n| over the
  /// model (O. C. Zienkiewicz, Y. M. Xie, Earthq. Eng. Struct. Dyn. 20
  /// (1991) 871-887).
  double local_error() const;
  /// Dynamics: u = u_n + dt v_n + dt^2/2 a_n, the state whose Newmark
  /// acceleration is a_n (the constant-acceleration predictor).
  void predict();
  /// Time of the loads within the step, as a fraction from t_n to t_{n+1}
  /// (1 - alpha_f; 1 when quasi-static): loads are set at that time.
  double load_level() const;
  /// Dynamics: v_{n+1} = c[0] (u - u_n) + c[1] v_n + c[2] a_n, the
  /// velocity the Newmark updates give the current u.
  std::array<double, 3> velocity_coefficients() const;

  /// dR/du of the current phase (quasi-static or dynamic), without
  /// Dirichlet conditions, as the sum of these forms' matrices: for
  /// assembly into a coupled system.
  std::vector<const dolfinx::fem::Form<double>*> jacobian_forms() const;
  /// The work done on the matrix's viscous branches since the dynamics
  /// started [mJ], whole model (0 for an elastic model): over a load cycle
  /// that ends relaxed, the energy dissipated.
  double viscous_work() const;
  /// Whether a part's matrix is viscoelastic (forms/viscoelasticity.py).
  bool viscoelastic() const { return _viscoelasticity != nullptr; }
  /// The humors' inertia in force (forms/humor_inertia.py): in the
  /// dynamics, if modelled; else null. Its forces are set like the cavity
  /// pressures, before a residual or Jacobian.
  HumorInertia* humor_inertia() { return _dynamic ? _humor_inertia.get() : nullptr; }
  const HumorInertia* humor_inertia() const { return _dynamic ? _humor_inertia.get() : nullptr; }
  /// b = dR/df_j of the humors' inertial force j, zero on Dirichlet dofs
  /// (also dG_j/du: the border is symmetric).
  void humor_border(std::size_t j, dolfinx::la::Vector<double>& b);
  /// The time step's constant `name` of the forms (dt, alpha_m, alpha_f,
  /// beta, gamma, damping): for other forms of the same step.
  std::shared_ptr<const dolfinx::fem::Constant<double>> time_constant(const std::string& name) const
  {
    return _time.at(name);
  }
  /// The facets' load tags (forms/tags.py): the cavity walls, the press, the support.
  const dolfinx::mesh::MeshTags<std::int32_t>& load_tags() const { return *_load_tags; }
  /// Whether the step is dynamic (after start_dynamics()).
  bool dynamic() const { return _dynamic; }
  /// Per local scalar entry of u (owned and ghost): 1 on a Dirichlet dof
  /// (whose value is always zero).
  std::vector<std::int8_t> dirichlet_marker() const;
  /// The same for the dynamics, before they start: with a support, the
  /// symmetry planes' dofs only (the springs free the clamped ones).
  std::vector<std::int8_t> dynamic_dirichlet_marker() const;
  /// Stored energy at u and kinetic energy at v_old [N mm = mJ], whole model
  /// (times the whole-model factor).
  double strain_energy() const;
  double kinetic_energy() const;

  /// Displacement at the mesh's geometry nodes, laid out as geometry().x().
  std::vector<double> nodal_displacement() const;
  /// After the reference geometry moved: lay the fibres again and find
  /// the surface profile's points anew.
  void update_reference();
  /// Displacement at reference points (every rank gets every value); for
  /// repeated use at the same points, Probes finds their cells once.
  std::vector<std::array<double, 3>>
  displacement_at(const std::vector<std::array<double, 3>>& points) const;
  /// Vector P1 space: the mesh's coordinate element, for output.
  std::shared_ptr<const dolfinx::fem::FunctionSpace> coordinate_space() const
  {
    return _coordinate_space;
  }
  /// Von Mises stress per cell (for output).
  void update_von_mises();

  /// A value found somewhere in the mesh: where (the reference centroid of
  /// its cell, or its node) and in which part.
  struct Place
  {
    double value;
    std::array<double, 3> x; ///< [mm], reference coordinates
    std::string part;        ///< empty if unknown
  };
  /// The smallest det F over every cell's quadrature points and vertices
  /// (-inf if any is NaN), and where; collective, the same on every rank.
  Place smallest_jacobian() const;
  /// The largest |b_i| of a residual (inf if any is NaN or Inf), and at
  /// which node; collective.
  Place largest_residual(const dolfinx::la::Vector<double>& b) const;

  std::shared_ptr<dolfinx::fem::Function<double>> u;          ///< displacement [mm]
  std::shared_ptr<dolfinx::fem::Function<double>> von_mises;  ///< [MPa], DG0
  std::shared_ptr<dolfinx::fem::Function<double>> press_profile; ///< [-], P1
  /// The last converged state, in dynamics: u_n, v_n [mm/ms], a_n [mm/ms^2]
  std::shared_ptr<dolfinx::fem::Function<double>> u_old, v_old, a_old;
  CellFields fields;                                          ///< materials and fibres
  std::int64_t dofs() const;
  /// What the meshed part's integrals are multiplied by for the whole
  /// model: 2 per mirror plane, and 2 pi about the axis of an
  /// axisymmetric section (its integrals are per radian).
  double symmetry_factor() const { return _symmetry_factor; }
  section::Dimension dimension() const { return _dimension; }
  /// The FFCx signatures of the compiled residuals and Jacobians in use:
  /// another build of the forms has others.
  const std::string& forms_signature() const { return _forms_signature; }

private:
  /// The compiled kernels of forms/solid.py for one element and dimension.
  struct Kernels;
  static Kernels kernels(const Element& e);
  // The constructor's steps, in order.
  /// The displacement's and the materials' spaces, the state's functions.
  void make_spaces(const meshio::Tagged& m, const Kernels& k, const Kernels& p1);
  /// The integration tags: cells by law, facets by load (forms/solid.py).
  void tag_integrals(const meshio::Tagged& m, const Boundaries& boundaries);
  /// The constants the forms name: loads, the cut's origin and lids, the
  /// support's springs, the time step's parameters.
  void make_constants(std::array<double, 3> volume_origin, const Boundaries& boundaries);
  /// The clamp, the symmetry planes' and the axis' conditions, the
  /// whole-model factor; returns the axes of the mirror planes.
  std::set<int> make_boundary_conditions(const meshio::Tagged& m, const Boundaries& boundaries);
  /// Every form and expression, the viscoelasticity and the humors'
  /// inertia where the scene has them.
  void make_forms(const meshio::Tagged& m, const Kernels& k, const Element& element,
                  const Boundaries& boundaries, const std::set<int>& mirrors);
  /// The support's springs and dashpots in place of the clamp (dynamics).
  void release_support();
  /// Scalar forms summed over the ranks, times the whole-model factor.
  std::vector<double>
  whole_model(const std::vector<std::shared_ptr<dolfinx::fem::Form<double>>>& forms) const;

  std::shared_ptr<dolfinx::fem::Form<double>> _R, _J, _R_dynamic, _J_dynamic,
      _strain_energy, _kinetic_energy;
  /// The matrix's viscoelasticity in the dynamics; null when elastic.
  std::unique_ptr<Viscoelasticity> _viscoelasticity;
  /// The humors' inertia in the dynamics; null when massless.
  std::unique_ptr<HumorInertia> _humor_inertia;
  bool _dynamic = false;
  /// dt, alpha_m, alpha_f, beta, gamma, damping
  std::map<std::string, std::shared_ptr<dolfinx::fem::Constant<double>>> _time;
  std::shared_ptr<const dolfinx::fem::FunctionSpace> _coordinate_space; ///< vector P1
  /// Per cavity: volume, unit-pressure load, volume derivative.
  std::vector<std::shared_ptr<dolfinx::fem::Form<double>>> _volumes, _cavity_loads,
      _dvolumes, _cavity_loads_dynamic;
  std::shared_ptr<dolfinx::fem::Expression<double>> _von_mises, _det_F;
  /// `value` at a local cell: its reference centroid and part.
  Place at_cell(std::int32_t cell, double value) const;
  /// Of every rank's place, the one with the smallest value, on every rank.
  Place gather(const Place& local) const;
  std::vector<std::shared_ptr<dolfinx::fem::Constant<double>>> _p_cavities;
  std::shared_ptr<dolfinx::fem::Constant<double>> _p_press, _x0, _support_stiffness,
      _support_damping;
  std::array<std::shared_ptr<dolfinx::fem::Constant<double>>, 2> _lids;
  /// The Dirichlet conditions in force: the clamp's and the symmetry
  /// planes'; the symmetry planes' alone once a support holds the model.
  std::vector<std::shared_ptr<const dolfinx::fem::DirichletBC<double>>> _bcs, _symmetry_bcs;
  std::optional<Support> _support;
  std::shared_ptr<dolfinx::fem::Function<double>> _u_support;
  /// The clamp's reaction, taken over by the support (owned entries).
  std::optional<dolfinx::la::Vector<double>> _preload;
  std::shared_ptr<dolfinx::fem::Form<double>> _support_area;
  std::shared_ptr<dolfinx::mesh::MeshTags<std::int32_t>> _law_tags, _load_tags;
  double _symmetry_factor = 1;
  section::Dimension _dimension = section::Dimension::three;
  std::string _forms_signature;
  std::vector<double> _profile_points; ///< reference points of press_profile's dofs
  // What lays the fibres: kept for update_reference().
  std::shared_ptr<const dolfinx::mesh::MeshTags<std::int32_t>> _cells;
  std::map<std::int32_t, std::string> _parts;
  std::map<std::string, Material> _materials;
  FibreRule _fibres;
};

/// The displacement at fixed reference points, their cells found once:
/// the reference geometry must not move while the object is in use.
class Probes
{
public:
  Probes(const Problem& problem, std::vector<std::array<double, 3>> points)
      : _problem(problem), _probes(*problem.u->function_space()->mesh(), std::move(points))
  {
  }
  /// The current displacement at each point; collective, every rank gets
  /// every value.
  std::vector<std::array<double, 3>> displacement() const { return _probes.values(*_problem.u); }

private:
  const Problem& _problem;
  meshio::Probes _probes;
};

} // namespace nct::solid
