// The flow a moving wall drives in the closed cavities' humors
// (forms/humor_flow.py): the hydroelastic pressure on the humor's own
// mesh, one Newton system with the solid and its closed cavities.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <span>
#include <string>
#include <utility>
#include <vector>

#include <dolfinx/fem/Form.h>
#include <dolfinx/fem/Function.h>
#include <dolfinx/la/Vector.h>
#include <petscmat.h>

#include "cavity/cavity.h"
#include "humor/humor.h"
#include "io/moving_fields.h"
#include "mesh_motion/problem.h"
#include "meshio/model.h"
#include "solid/problem.h"
#include "solver/monolithic.h"
#include "solver/newton.h"

namespace nct::humor
{

/// The humors' pressure p = P_c + p~ (P_c the closed cavity's multiplier)
/// and the coupled system of the solid, its closed cavities and p~.
///
/// Unknowns, stacked: the solid's displacement, then p~ (P1 on the humor
/// mesh) but where p~ = 0: on the openings, or at one node of a closed
/// humor; the closed cavities' pressures border the system
/// (cavity::Closed), an open cavity's is prescribed. The humor mesh follows the wall by
/// the mesh motion's extension (mesh_motion::Problem) at the start of
/// every step, from the last converged wall: its geometry lags the wall by
/// a step within the step's Newton iterations (the Laplacian's dependence
/// on the wall's shape is not differentiated). Acts in the dynamics only.
class Flow final : public Humor
{
public:
  /// Pairs the humor's wall nodes with the solid's by place: call on the
  /// meshes as built, before the solid's reference geometry moves (zero
  /// pressure). `density` [g/mm^3].
  Flow(solid::Problem& solid, const meshio::Tagged& humor, const Boundaries& boundaries,
       double density);

  /// Where the humor sits in a monolithic system: the rows and columns of
  /// its blocks.
  struct Placement
  {
    const solver::Monolithic* U;
    std::size_t solid, humor; ///< the fields of u and p~
    /// The solid's block (its held rows and columns left out), the humor's.
    solver::BlockIndices solid_block, humor_block;
    /// Per cavity: the solid's rows by the wall's p~, the wall's p~ rows by u.
    std::array<solver::BlockIndices, 2> load_p, flux_u;
  };
  /// The humor's field of a monolithic system: p~ but where it is held.
  solver::Monolithic::Field field() const;
  /// The humor in U, whose field `solid` is the solid's u and `humor` field().
  Placement place(const solver::Monolithic& U, std::size_t solid, std::size_t humor) const;
  /// With the system's functions set (unpacked): the wall's and the lid's
  /// loads added to the solid's free rows (`b_solid`, laid out as u's
  /// entries, owned first), and the humor's rows into `b_humor` (p~'s
  /// owned entries).
  void add_residual(std::span<double> b_solid, std::span<double> b_humor);
  /// The humor's blocks and the wall's and lid's couplings into A (not the
  /// solid's own), at the places `at` gives.
  void add_jacobian(const Placement& at, Mat A);

  /// At the start of the dynamics: the humor mesh onto the solid's current
  /// wall, p~ = 0.
  void start() override;
  /// After a converged step of a system it joined: the humor mesh follows
  /// the wall. Throws std::runtime_error, naming the place, if a humor
  /// cell folded.
  void follow();
  /// Why the current wall is not admissible for the humor, empty if it is:
  /// the humor's mesh would fold following it (its place and how far).
  /// Collective; the humor's mesh stays where it is.
  std::string inadmissible();

  // Humor
  const char* name() const override { return "flow"; }
  void describe(nlohmann::json& summary, io::RunFolder& folder) const override;
  /// The solid with its closed cavities (null: open, at their pressures)
  /// and the humor, alone (no air): a Newton system of its own, on
  /// unknowns(), and a matrix with its pattern (AIJ, assembled once).
  solver::System system(cavity::Closed* closed, cavity::Open& open) override;
  const char* system_name() const override { return "solid_humor_flow"; }
  Mat create_matrix() override;
  /// The solid's step, then the humor mesh follows the wall.
  void advance() override;
  /// The solid's predictor (u and p~ stacked).
  void predict() override;
  /// Its largest pressure range and Bernoulli term.
  void summarise(nlohmann::json& summary) const override;
  /// The coupled air's fourth field: p~, its wall and its lid.
  fsi::Joined* joined() override { return &_in_air; }
  /// The stacked unknowns of system() (fields: solid, humor_flow).
  solver::Monolithic& unknowns() { return *_own_unknowns; }

  /// p~ [MPa] on the humor mesh: the pressure less the cavity's.
  std::shared_ptr<dolfinx::fem::Function<double>> p;
  /// p~ at `time` into `files` (its file humor_pressure.xdmf), on the
  /// humor's mesh where it is now. Collective.
  void write(io::MovingFields& files, double time) override;
  /// Unknowns of p~ (all ranks).
  std::int64_t dofs() const;
  /// Wall nodes paired with the solid's.
  std::size_t wall_nodes() const { return _pairs.size(); }
  /// What the linearisation leaves out, measured over the converged steps
  /// since start() [MPa]: the largest range of p~ over the humor (its
  /// flow's own pressure differences), and the largest Bernoulli term
  /// rho |w|^2 / 2, w the humor's velocity from Euler's equation,
  /// w_{n+1} = w_n - dt grad p~ / rho (per cell, the step's gradient).
  double pressure_range_max() const { return _range_max; }
  double bernoulli_max() const { return _bernoulli_max; }
  /// The humor's kinetic energy rho/2 integral |w|^2 dV at the last
  /// converged step, w as above [mJ, meshed part]. Collective.
  double kinetic_energy() const override;
  /// The humor's smallest cell volume now over as built (negative: folded),
  /// and where (current coordinates). Collective.
  std::pair<double, std::array<double, 3>> smallest_cell_ratio() const;
  /// Wall time [s] by part: "solid" (its forms, in system()), "humor" (its
  /// forms), "wall" (the wall's and the lid's blocks and transfers),
  /// "mesh_motion" (the extension).
  const std::map<std::string, double>& timings() const { return _timings; }

private:
  /// The flow as the coupled air's fourth field, at the place it was given.
  struct InAir final : fsi::Joined
  {
    explicit InAir(Flow& flow) : flow(flow) {}
    Flow& flow;
    Placement at;
    solver::Monolithic::Field field() const override { return flow.field(); }
    void place(const solver::Monolithic& U, std::size_t solid, std::size_t own) override
    {
      at = flow.place(U, solid, own);
    }
    void add_residual(std::span<double> b_solid, std::span<double> b_own) override
    {
      flow.add_residual(b_solid, b_own);
    }
    void add_jacobian(Mat A) override { flow.add_jacobian(at, A); }
    std::string inadmissible() override { return flow.inadmissible(); }
    void advance() override { flow.follow(); }
  };
  InAir _in_air{*this};
  /// A humor wall node: its cavity and place as built.
  struct Pair
  {
    int cavity;
    std::array<double, 3> place;
  };
  void pair(const meshio::Tagged& humor, const Boundaries& boundaries);
  void choose_held_nodes(const meshio::Tagged& humor, const Boundaries& boundaries);
  void make_forms();
  /// p~ on the wall into the solid mesh's p_1, p_2 (p~ set).
  void set_wall_pressures();
  /// system()'s residual into b and Jacobian into A (x unpacked).
  void residual(dolfinx::la::Vector<double>& b);
  void own_jacobian(Mat A);
  /// The humor mesh onto the solid's current wall: the extension of the
  /// wall's displacement (the mesh at its geometry as built), the mesh
  /// moved by it, the lid measured.
  void follow_wall();
  void extend_to_wall();
  void move_humor_mesh();
  /// 1 / (rho c) of the solid's time step [mm^2/MPa].
  void set_compliance();
  /// What the forms read of the state: the compliance and p~ on the wall.
  void set_loads()
  {
    set_compliance();
    set_wall_pressures();
  }
  /// The lid's constants on the solid's reference geometry: the cut's
  /// area, mean normal and n(v) = integral_cut N . v dA.
  void measure_cut();
  /// L(q) = integral_lid q dA on the humor's current geometry.
  void measure_lid();
  /// A scalar form summed over the ranks.
  double total(const dolfinx::fem::Form<double>& form) const;
  /// The converged step's Euler update of the humor's velocity, and the
  /// largest range of p~ and Bernoulli term so far.
  void measure_linearisation();

  std::shared_ptr<dolfinx::mesh::Mesh> _humor_mesh;
  std::vector<double> _x_built; ///< the humor mesh's geometry as built
  std::vector<double> _cell_volume_built; ///< per local cell, signed
  double _density;
  std::unique_ptr<mesh_motion::Problem> _motion;
  /// The solid mesh's P1 wall pressure per cavity (forms' p_1, p_2).
  std::array<std::shared_ptr<dolfinx::fem::Function<double>>, 2> _p_wall;
  std::shared_ptr<dolfinx::fem::Constant<double>> _compliance;
  std::shared_ptr<dolfinx::fem::Form<double>> _load, _load_u, _laplace, _laplace_p;
  std::array<std::shared_ptr<dolfinx::fem::Form<double>>, 2> _load_p, _flux, _flux_u;
  std::vector<Pair> _pairs; ///< every wall node, the same on every rank
  /// Local dofs and their pair: the solid's P1 wall dofs (owned and
  /// ghost) per cavity, with the solid mesh's geometry node; the humor's
  /// wall dofs (owned and ghost); the humor mesh displacement's owned wall
  /// nodes (block dofs).
  struct Solid_dof
  {
    std::int32_t dof, node;
    std::size_t k;
  };
  std::array<std::vector<Solid_dof>, 2> _solid_dofs;
  std::vector<std::pair<std::int32_t, std::size_t>> _humor_dofs, _mesh_dofs;
  std::vector<std::int32_t> _held;   ///< the humor dofs where p~ = 0 (local, owned, sorted)
  std::vector<std::int32_t> _active; ///< the others
  std::int32_t _solid_owned = 0, _scalar_owned = 0, _humor_owned = 0;
  std::vector<std::int8_t> _solid_held;
  /// Scratch: the solid's residual and the wall's load on it (laid out as
  /// u), the humor's rows, a P1 vector of the solid's mesh.
  std::unique_ptr<dolfinx::la::Vector<double>> _b_solid, _b_wall, _b_humor, _b_scalar;
  std::map<std::string, double> _timings;
  /// system()'s unknowns and their places.
  std::unique_ptr<solver::Monolithic> _own_unknowns;
  Placement _own;

  /// The lid (forms/humor_flow.py); without one, the forms are null.
  std::shared_ptr<dolfinx::fem::Form<double>> _cut_normal, _cut_area, _cut_flux, _cut_motion,
      _lid_area;
  std::shared_ptr<dolfinx::mesh::MeshTags<std::int32_t>> _lid_tags;
  double _cut_area_value = 0;
  std::array<double, 3> _cut_normal_mean{0, 0, 0};
  std::vector<double> _n_block, _L_block; ///< n, L laid out as u's and p~'s owned entries
  std::vector<std::int32_t> _lid_mesh_dofs; ///< the humor mesh displacement's owned lid nodes
  /// The humor's velocity per local cell (3 components) [mm/ms], and the
  /// largest p~ range and Bernoulli term so far [MPa].
  std::vector<double> _w;
  double _range_max = 0, _bernoulli_max = 0;
};

} // namespace nct::humor
