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
  /// each iteration cuts the residual at least 4x; refactorise otherwise.
  bool reuse_jacobian = false;
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
};

/// PETSc options in force: defaults (MUMPS LU), overridden by `options`
/// in order, e.g. the scene's and then the command line's.
void set_petsc_options(const std::vector<std::pair<std::string, std::string>>& options);

/// Newton's method on R(x) = 0 for a state the caller owns.
class Newton
{
public:
  /// `A` holds the Jacobian's sparsity; the KSP reads the PETSc options.
  Newton(MPI_Comm comm, Mat A);
  ~Newton();
  Newton(const Newton&) = delete;
  Newton& operator=(const Newton&) = delete;

  /// Solve from the current x. `residual` assembles R at the current x
  /// into b; `jacobian` assembles dR/dx into A. x's ghosts are updated
  /// after every change. On failure x is left at the last iterate.
  NewtonReport solve(dolfinx::la::Vector<double>& x,
                     const std::function<void(dolfinx::la::Vector<double>&)>& residual,
                     const std::function<void(Mat)>& jacobian,
                     const NewtonSettings& settings);

  Timings timings;

private:
  KSP _ksp = nullptr;
  Mat _A;
  bool _factorised = false; ///< does the KSP hold a usable Jacobian?
};

} // namespace nct::solver
