// Newton's method with an energy line search, on a PETSc linear solver.
#pragma once

#include <functional>
#include <string>
#include <utility>
#include <vector>

#include <dolfinx/la/Vector.h>
#include <petscksp.h>

namespace nct::solver
{

/// Stopping and globalisation of one Newton solve.
struct NewtonSettings
{
  int max_iterations = 25;
  double rtol = 1e-9;       ///< relative to the first residual norm
  double atol = 1e-11;      ///< absolute residual norm
  bool line_search = true;  ///< energy line search (else full steps)
  /// Keep the factorised Jacobian (across iterations and solves) while
  /// each iteration after a solve's first cuts the residual at least 4x;
  /// refactorise otherwise.
  bool reuse_jacobian = false;
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

/// Wall time spent in assembly and in linear solves [s].
struct Timings
{
  double assemble = 0;
  double solve = 0;
  int linear_solves = 0;
  int jacobians = 0; ///< Jacobian assemblies (factorisations with a direct solver)
  double border = 0; ///< of assemble and solve: the bordered system's extra work
};

/// PETSc options in force: defaults (MUMPS LU), overridden by `options`
/// in order, e.g. the scene's and then the command line's.
void set_petsc_options(const std::vector<std::pair<std::string, std::string>>& options);

/// The nonlinear system R(x, y) = 0, G(x, y) = 0 of a distributed field x
/// bordered by a few global unknowns y (every rank holds all of y), e.g.
/// the pressures of closed cavities. Without y it is R(x) = 0.
///
/// Newton's linear system is the bordered matrix
///
///     [ K  B ] [dx]   [R]        K = dR/dx, B_i = dR/dy_i,
///     [ C  0 ] [dy] = [G],       C_i = dG_i/dx (G does not depend on y),
///
/// solved by block elimination with K's factorisation: z = K^-1 R,
/// Z_i = K^-1 B_i, S = C Z, dy = S^-1 (C z - G), dx = z - Z dy.
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
  /// B[i] = dR/dy_i (zero on Dirichlet dofs), C[i] = dG_i/dx; only with y.
  std::function<void(std::vector<dolfinx::la::Vector<double>>& B,
                     std::vector<dolfinx::la::Vector<double>>& C)>
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

  /// Forget the factorised Jacobian (e.g. after the mesh moved).
  void reset() { _factorised = false; }
  /// The linear solver, e.g. to give a fieldsplit preconditioner its blocks.
  KSP ksp() const { return _ksp; }

  Timings timings;

private:
  KSP _ksp = nullptr;
  Mat _A;
  bool _factorised = false; ///< does the KSP hold a usable Jacobian?
};

} // namespace nct::solver
