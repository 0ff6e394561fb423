#include "solver/newton.h"

#include <cmath>
#include <map>
#include <sstream>

#include <dolfinx/la/petsc.h>

namespace nct::solver
{
namespace
{

double norm(const dolfinx::la::Vector<double>& b)
{
  const std::int32_t n = b.map()->size_local() * b.bs();
  double s = 0;
  for (std::int32_t i = 0; i < n; ++i)
    s += b.array()[i] * b.array()[i];
  MPI_Allreduce(MPI_IN_PLACE, &s, 1, MPI_DOUBLE, MPI_SUM, b.map()->comm());
  return std::sqrt(s);
}

} // namespace

void set_petsc_options(const std::vector<std::pair<std::string, std::string>>& options)
{
  // MUMPS with the PORD ordering: the fastest of AMD, AMF, QAMD, PORD and
  // MUMPS' automatic choice on the eye's shell meshes (scripts/benchmark.sh).
  std::map<std::string, std::string> all = {{"ksp_type", "preonly"},
                                            {"pc_type", "lu"},
                                            {"pc_factor_mat_solver_type", "mumps"},
                                            {"mat_mumps_icntl_7", "4"}};
  for (auto& [k, v] : options)
    all[k.rfind("-", 0) == 0 ? k.substr(1) : k] = v;
  for (auto& [k, v] : all)
    PetscOptionsSetValue(nullptr, ("-" + k).c_str(), v.empty() ? nullptr : v.c_str());
}

Newton::Newton(MPI_Comm comm, Mat A) : _A(A)
{
  KSPCreate(comm, &_ksp);
  KSPSetFromOptions(_ksp);
}

Newton::~Newton()
{
  if (_ksp)
    KSPDestroy(&_ksp);
}

NewtonReport Newton::solve(dolfinx::la::Vector<double>& x,
                           const std::function<void(dolfinx::la::Vector<double>&)>& residual,
                           const std::function<void(Mat)>& jacobian,
                           const NewtonSettings& settings)
{
  NewtonReport report;
  dolfinx::la::Vector<double> b(x.map(), x.bs()), dx(x.map(), x.bs()),
      x_old(x.map(), x.bs());
  Vec b_petsc = dolfinx::la::petsc::create_vector_wrap(b);
  Vec dx_petsc = dolfinx::la::petsc::create_vector_wrap(dx);

  auto assemble_residual = [&]
  {
    double t = MPI_Wtime();
    residual(b);
    timings.assemble += MPI_Wtime() - t;
    return norm(b);
  };

  double r = assemble_residual();
  report.residuals.push_back(r);
  const double r0 = r;
  if (!std::isfinite(r))
    report.reason = "the residual is not finite at the start of the step";
  while (report.reason.empty())
  {
    if (r <= std::max(settings.atol, settings.rtol * r0))
    {
      report.converged = true;
      break;
    }
    if (report.iterations == settings.max_iterations)
    {
      report.reason = "no convergence in " + std::to_string(settings.max_iterations)
                      + " iterations";
      break;
    }

    double t = MPI_Wtime();
    jacobian(_A);
    timings.assemble += MPI_Wtime() - t;
    t = MPI_Wtime();
    KSPSetOperators(_ksp, _A, _A);
    KSPSolve(_ksp, b_petsc, dx_petsc);
    timings.solve += MPI_Wtime() - t;
    ++timings.linear_solves;
    KSPConvergedReason ksp_reason;
    KSPGetConvergedReason(_ksp, &ksp_reason);
    if (ksp_reason < 0)
    {
      report.reason = std::string("the linear solver failed (")
                      + KSPConvergedReasons[ksp_reason] + ")";
      break;
    }
    dx.scatter_fwd();

    // Backtracking: halve the step until the residual norm decreases
    // (Armijo); fall back to the best finite decrease seen.
    std::copy(x.array().begin(), x.array().end(), x_old.mutable_array().begin());
    auto take = [&](double alpha)
    {
      for (std::size_t i = 0; i < x.array().size(); ++i)
        x.mutable_array()[i] = x_old.array()[i] - alpha * dx.array()[i];
      return assemble_residual();
    };
    double alpha = 1.0, r_new = take(alpha);
    if (settings.line_search)
    {
      double best_alpha = std::isfinite(r_new) ? alpha : 0.0;
      double best_r = std::isfinite(r_new) ? r_new : r;
      while (!(std::isfinite(r_new) && r_new <= (1 - 1e-4 * alpha) * r)
             && alpha > 1.0 / 64)
      {
        alpha /= 2;
        r_new = take(alpha);
        if (std::isfinite(r_new) && r_new < best_r)
          best_alpha = alpha, best_r = r_new;
      }
      if (!(std::isfinite(r_new) && r_new <= (1 - 1e-4 * alpha) * r))
      {
        if (best_alpha == 0.0 || best_r >= r)
        {
          take(0.0);
          report.reason = "the line search found no decrease of the residual";
          ++report.iterations;
          break;
        }
        r_new = take(best_alpha);
      }
    }
    ++report.iterations;
    r = r_new;
    report.residuals.push_back(r);
    if (!std::isfinite(r))
      report.reason = "the residual became NaN or Inf";
  }
  VecDestroy(&b_petsc);
  VecDestroy(&dx_petsc);
  return report;
}

} // namespace nct::solver
