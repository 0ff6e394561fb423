// Newton's method with an energy line search, on a PETSc linear solver.
#pragma once

#include <functional>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include <dolfinx/la/Vector.h>
#include <nlohmann/json.hpp>
#include <petscksp.h>

#include "solver/anderson.h"

namespace nct::solver
{

/// How a Newton iteration gets its linear solve.
enum class Jacobian
{
  /// Assemble and factorise the Jacobian at every iteration: Newton's
  /// quadratic convergence at a factorisation per iteration.
  every_iteration,
  /// Keep the factorised Jacobian (across iterations and solves) while
  /// each iteration after a solve's first cuts the residual norm by at
  /// least `reuse_contraction`; refactorise otherwise (modified Newton),
  /// and after `reuse_iterations` iterations on it within a solve. With
  /// `anderson` > 0 the iteration is Anderson-accelerated.
  reuse,
  /// Assemble the Jacobian at every iteration and solve with the KSP
  /// (GMRES) preconditioned by the last factorisation, kept across
  /// iterations and solves; refactorise when a solve needs more than
  /// `krylov_refactorise` iterations or fails (Newton-Krylov).
  krylov,
};

/// Stopping and globalisation of one Newton solve.
struct NewtonSettings
{
  int max_iterations = 25;
  double rtol = 1e-9;       ///< relative to the first residual norm
  double atol = 1e-11;      ///< absolute residual norm
  /// Converged also when the error estimate from the last two steps,
  /// |dx_k| q / (1 - q) with q = |dx_k| / |dx_{k-1}| < 1 (max norms, in
  /// the unknowns' units: mm for displacements), is below this; 0: off.
  double increment_tol = 0;
  bool line_search = true;  ///< energy line search (else full steps)
  Jacobian jacobian = Jacobian::every_iteration;
  double reuse_contraction = 0.25; ///< Jacobian::reuse only
  int reuse_iterations = 1000;     ///< Jacobian::reuse only
  /// Jacobian::reuse: depth of the Anderson acceleration of the iteration
  /// on a kept factorisation (solver/anderson.h); 0: plain modified Newton.
  int anderson = 0;
  int krylov_refactorise = 10;     ///< Jacobian::krylov only
  /// The solve counts as diverging once the residual norm exceeds this
  /// multiple of its smallest value so far.
  double max_growth = 1e4;
};

/// What happened in one Newton solve.
struct NewtonReport
{
  bool converged = false;
  int iterations = 0;
  std::vector<double> residuals; ///< l2 norm before each iteration, and the last
  std::string reason;            ///< why it stopped without converging
};

/// Where a Newton solver's wall time went [s], with counts.
struct Timings
{
  double residual = 0;        ///< residual assemblies
  int residuals = 0;          ///< of which the line search's:
  int line_search_residuals = 0;
  double jacobian = 0;        ///< Jacobian assemblies
  int jacobians = 0;
  double border_assemble = 0; ///< the bordered system's B and C
  double factorise = 0;       ///< the preconditioner's set-up (LU: the factorisation)
  int factorisations = 0;
  double solve = 0;           ///< linear solves (LU: back-solves), the border's included
  int linear_solves = 0;
  int krylov_iterations = 0;  ///< summed over the linear solves (preonly: 1 each)
  double border = 0;          ///< of the above: the bordered system's extra work

  double assemble() const { return residual + jacobian + border_assemble; }
  double linear() const { return factorise + solve; }
  Timings& operator+=(const Timings& o);
  Timings operator-(const Timings& o) const;
};

/// Timings as JSON, by name (the summary's profile, a checkpoint), and back.
void to_json(nlohmann::json& j, const Timings& t);
void from_json(const nlohmann::json& j, Timings& t);

/// PETSc options in force: defaults (MUMPS LU; with Jacobian::krylov
/// right-preconditioned GMRES on it), overridden by `options` in order,
/// e.g. the scene's and then the command line's.
void set_petsc_options(const std::vector<std::pair<std::string, std::string>>& options,
                       Jacobian jacobian = Jacobian::every_iteration);

/// The nonlinear system R(x, y) = 0, G(x, y) = 0 of a distributed field x
/// bordered by a few global unknowns y (every rank holds all of y), e.g.
/// the pressures of closed cavities. Without y it is R(x) = 0.
///
/// Newton's linear system is the bordered matrix
///
///     [ K  B ] [dx]   [R]        K = dR/dx, B_i = dR/dy_i,
///     [ C  D ] [dy] = [G],       C_i = dG_i/dx, D = dG/dy (dense, small),
///
/// solved by block elimination with K's factorisation: z = K^-1 R,
/// Z_i = K^-1 B_i, S = C Z - D, dy = S^-1 (C z - G), dx = z - Z dy.
/// If R and G are the derivatives of one Lagrangian, dx . R + dy . G is
/// its directional derivative, which the line search drives to zero.
struct System
{
  dolfinx::la::Vector<double>* x;
  std::vector<double>* y; ///< may be empty
  /// b = R and g = G at the current (x, y); b = x - x_D on Dirichlet dofs.
  std::function<void(dolfinx::la::Vector<double>& b, std::vector<double>& g)> residual;
  /// A = K, with identity rows on Dirichlet dofs.
  std::function<void(Mat A)> jacobian;
  /// B[i] = dR/dy_i (zero on Dirichlet dofs), C[i] = dG_i/dx and
  /// D[i * ny + j] = dG_i/dy_j (given zero); only with y.
  std::function<void(std::vector<dolfinx::la::Vector<double>>& B,
                     std::vector<dolfinx::la::Vector<double>>& C, std::vector<double>& D)>
      border;
  /// Why the current (x, y) is not admissible (e.g. an inverted element,
  /// and where), empty if it is; collective. Null: every state is. A step
  /// into an inadmissible state is halved like one to a non-finite residual.
  std::function<std::string()> inadmissible;
  /// Where the residual b is largest, for the failure report; collective.
  std::function<std::string(const dolfinx::la::Vector<double>& b)> locate;
};

/// Newton's method on a System the caller owns.
class Newton
{
public:
  /// `A` holds the Jacobian's sparsity; the KSP reads the PETSc options
  /// (those under `prefix` if given).
  Newton(MPI_Comm comm, Mat A, const std::string& prefix = "");
  ~Newton();
  Newton(const Newton&) = delete;
  Newton& operator=(const Newton&) = delete;

  /// Solve from the current (x, y). x's ghosts are updated after every
  /// change. The residual norm is sqrt(|R|^2 + |G|^2). On failure (x, y)
  /// are left at the last iterate.
  NewtonReport solve(const System& system, const NewtonSettings& settings);

  /// Forget the factorised Jacobian (e.g. after the mesh moved). Under
  /// Jacobian::krylov a changed Jacobian needs no reset: only a new pattern.
  void reset() { _factorised = _border_current = false; }
  /// The linear solver, e.g. to give a fieldsplit preconditioner its blocks.
  KSP ksp() const { return _ksp; }

  Timings timings;

private:
  /// One solve's vectors (the residual, the step, the state before it).
  struct Work;

  /// A factorisation of the current A.
  void factorise();
  /// After a failed factorisation: if MUMPS ran short of workspace (or
  /// `forced`, a test's), double its workspace allowance (ICNTL(14)) and
  /// drop the factor, so that the next factorise() starts anew. True when
  /// it did.
  bool enlarge_workspace(bool forced);
  /// sol = A^-1 rhs, counted and timed; under Jacobian::krylov a failed
  /// solve on an old factorisation refactorises and retries.
  KSPConvergedReason linear_solve(Vec rhs, Vec sol, const NewtonSettings& settings);
  /// The Newton step (dx, dy) of the bordered system at the current
  /// state, with a new Jacobian if `assemble`; why it failed, or empty.
  std::string newton_step(Work& w, bool assemble, const NewtonSettings& settings);
  /// Take the step (x, y) -= alpha (dx, dy): alpha halved while the state
  /// is inadmissible, then the energy line search. Returns the new
  /// residual norm and sets alpha; why no usable step exists, or empty.
  std::string take_step(Work& w, const NewtonSettings& settings, double& alpha, double& r);

  KSP _ksp = nullptr;
  Mat _A;
  bool _factorised = false; ///< does the KSP hold a usable factorisation?
  bool _fresh = false;      ///< is it the current Jacobian's?
  bool _refactorise = false; ///< Jacobian::krylov: a solve was slow
  int _uses = 0;             ///< iterations on the factorisation in this solve
  /// A bordered system's C_i and Z_i = K^-1 B_i, of the factorised K, and D.
  std::vector<dolfinx::la::Vector<double>> _C, _Z;
  std::vector<double> _D;
  bool _border_current = false;
  std::optional<Anderson> _anderson;
};

} // namespace nct::solver
