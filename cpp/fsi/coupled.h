// Two-way fluid-structure interaction: the solid (with its closed
// cavities), the air and the air mesh's motion in one Newton system.
#pragma once

#include <array>
#include <cstdint>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <petscmat.h>
#include <span>

#include "air/problem.h"
#include "cavity/cavity.h"
#include "mesh_motion/problem.h"
#include "meshio/model.h"
#include "solid/problem.h"
#include "solver/monolithic.h"
#include "solver/newton.h"

namespace nct::fsi
{

/// The fluid-solid interface: facet groups of the solid's mesh and of the
/// air's mesh that are the same surface, node for node.
struct Interface
{
  std::vector<std::int32_t> solid, air;
};

/// A field that joins the coupled system beside the solid's displacement
/// (the humor's flow, cpp/humor): its unknowns, its rows and its
/// couplings to the solid.
class Joined
{
public:
  virtual ~Joined() = default;
  /// Its field of the stacked unknowns.
  virtual solver::Monolithic::Field field() const = 0;
  /// Its place in U, whose field `solid` is the solid's u and `own` its own.
  virtual void place(const solver::Monolithic& U, std::size_t solid, std::size_t own) = 0;
  /// With U unpacked: its loads added to the solid's rows `b_solid` (laid
  /// out as u's entries, owned first), its own rows into `b_own`.
  virtual void add_residual(std::span<double> b_solid, std::span<double> b_own) = 0;
  /// Its blocks and its couplings to the solid into A, where place() put them.
  virtual void add_jacobian(Mat A) = 0;
  /// Why the current state is not admissible for it, or empty. Collective.
  virtual std::string inadmissible() = 0;
  /// After a converged step.
  virtual void advance() = 0;
};

/// The interface's power at the solid's balance level t_{n+1-alpha_f}
/// [W = N mm/ms]: what leaves the air (its force on the interface times the air's
/// velocity there) and what enters the solid (the load it receives times
/// its Newmark velocity).
struct Power
{
  double air = 0, solid = 0;
};

/// The coupled system. Unknowns, stacked in one vector: the solid's
/// displacement (all of it), the air's velocity and pressure, the mesh
/// displacement in the moving region; the closed cavities' pressures
/// border it (as for the solid alone).
///
/// At each interface node and component where neither side is held by a
/// Dirichlet condition:
/// - kinematics: the air's velocity equals the solid's velocity that the
///   generalised-alpha (Newmark) updates give its displacement,
///   u_f = c0 (u - u_n) + c1 v_n + c2 a_n; the mesh displacement equals
///   the solid's displacement since the coupling started, d = u - u_0;
///   these constraint rows replace the air's momentum rows and the mesh
///   motion's rows there;
/// - dynamics: the replaced momentum rows, the air's consistent reaction
///   lambda (the force on the air from the wall, at t_{n+1}), are added
///   to the solid's rows at the same node, at the solid's balance level:
///   (1 - alpha_f) lambda_{n+1} + alpha_f lambda_n. The solid's P2 edge
///   nodes carry no air load: the air's force is lumped at the vertices
///   (the transfer is the transpose of the kinematic constraint, so the
///   power leaving the air equals the power entering the solid).
/// Where the solid is held (clamped, or the normal component on a
/// symmetry plane), the air and mesh there are held at zero.
///
/// The Jacobian holds every block: the solid's, the air's with its shape
/// derivative dR/dd (unless left out), the mesh motion's, the constraints'
/// and the reaction's rows moved onto the solid.
class Coupled
{
public:
  /// Pairs the interface nodes by place: call before the solid's
  /// reference geometry moves (zero pressure), on the meshes as built.
  /// `shape_derivative` false leaves the air's dR/dd block out of the
  /// Jacobian (a quasi-Newton method).
  /// `joined`: a fourth field (the humors' flow), or null.
  /// `fluid`: the fluid's field name (in Newton's diagnostics).
  Coupled(solid::Problem& solid, air::Problem& air, mesh_motion::Problem& motion,
          const meshio::Tagged& solid_mesh, const meshio::Tagged& air_mesh,
          const Interface& interface, bool shape_derivative,
          Joined* joined = nullptr, const std::string& fluid = "air");

  /// Start coupling from the solid's current state: the air mesh is
  /// moved (its reference with it) so that its interface lies on the
  /// solid's current surface, by the mesh motion's extension; the air is
  /// at rest, d = 0, and u_0 is the current u.
  void start();
  /// Has the coupling started (or been restored)?
  bool started() const { return _started; }
  /// The coupling's state a checkpoint holds, with the air's (the solid's
  /// is the solid's own): per interface node (in the order of their places
  /// as built, whatever the partition) u_0 and the last step's reaction.
  nlohmann::json save(io::CheckpointWriter& checkpoint) const;
  /// Continue from a checkpoint instead of start(): the air mesh, the air
  /// and the coupling as saved (the solid restored before).
  void restore(const io::CheckpointReader& checkpoint, const nlohmann::json& state);
  /// The coupled Newton system; `closed`: the solid's closed cavities
  /// (their pressures are y), or null.
  solver::System system(cavity::Closed* closed);
  /// A matrix with the coupled Jacobian's pattern (assembled once).
  Mat create_matrix();
  /// The next step (its length and the solid's integrator) and the air's
  /// BDF order.
  void set_time_step(const dynamics::TimeStep& step, int bdf_order);
  /// After a converged step: the new state becomes the old one.
  void advance();
  /// The interface power of the converged step (before advance()).
  /// Collective; assembles the coupled and the solid's residuals.
  Power power();

  /// The stacked unknowns (fields: solid, air, mesh_motion; the joined
  /// field's fourth).
  solver::Monolithic& unknowns() { return *_unknowns; }
  const solver::Monolithic& unknowns() const { return *_unknowns; }
  /// Interface nodes paired (each with up to 3 coupled components).
  std::size_t interface_nodes() const { return _nodes.size(); }
  /// Why the current state is not admissible (an inverted solid element
  /// or air cell, and where), or empty. Collective.
  std::string inadmissible() const;

  /// Wall time [s] spent in each part of the residuals and Jacobians:
  /// "solid", "air", "mesh_motion", "humor_flow" (their own forms and the
  /// humor's coupling to the wall), "air_shape" (the
  /// shape derivative), "interface" (the constraints and the moved
  /// reaction, with their communication), "matrix_communication" (the
  /// Jacobian's entries sent to the ranks that own their rows).
  const std::map<std::string, double>& timings() const { return _timings; }

private:
  /// Per interface node: global indices (in the stacked system) of the
  /// solid's, the air's and the mesh's dofs of each component (-1: held),
  /// and this rank's local indices where it owns them (-1 otherwise).
  struct Node
  {
    std::array<std::int64_t, 3> solid, air, mesh;
    std::int32_t solid_block = -1;        ///< local block of u
    std::array<std::int32_t, 3> air_dof{-1, -1, -1}; ///< local dofs of (u, p)
    std::int32_t mesh_block = -1;         ///< local block of d
    std::array<double, 3> air_place;      ///< reference place in the air mesh
  };
  void pair(const meshio::Tagged& solid_mesh, const meshio::Tagged& air_mesh,
            const Interface& interface);
  /// Every entry of the coupled Jacobian into A (MatSetValues, ADD).
  void add_jacobian(Mat A);
  /// The coupled residual (x must be unpacked) into b; keeps lambda.
  void residual(dolfinx::la::Vector<double>& b);
  /// Per node and component, the solid's displacement and Newmark
  /// velocity (every rank gets them).
  void solid_state(std::vector<double>& u, std::vector<double>& v) const;

  solid::Problem& _solid;
  air::Problem& _air;
  mesh_motion::Problem& _motion;
  Joined* _joined;
  std::shared_ptr<dolfinx::mesh::Mesh> _air_mesh; ///< moved by start()
  bool _shape_derivative;
  std::unique_ptr<solver::Monolithic> _unknowns;
  int _gdim = 3; ///< the meshes' dimension: a section's nodes have 2 components
  std::vector<Node> _nodes;
  std::vector<std::size_t> _order; ///< the nodes by their places as built
  std::vector<double> _u0;                     ///< u at the start, per node and component
  std::vector<double> _lambda, _lambda_n;      ///< the air's reaction at t_{n+1}, t_n
  std::vector<double> _air_velocity_n;         ///< u_f at t_n, per node and component
  solver::BlockIndices _solid_block, _air_block, _air_mesh_block, _mesh_block;
  std::vector<std::size_t> _moved_rows; ///< air rows added to the solid's
  std::vector<std::int8_t> _solid_held, _air_held;
  std::unique_ptr<dolfinx::la::Vector<double>> _b_solid, _b_air, _b_mesh; ///< block residuals
  std::map<std::string, double> _timings;
  double _alpha_f = 0;
  bool _started = false;
};

} // namespace nct::fsi
