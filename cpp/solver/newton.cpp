#include "solver/newton.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include <dolfinx/la/petsc.h>

namespace nct::solver
{
namespace
{

/// Global dot product of two vectors (owned entries).
double dot(const dolfinx::la::Vector<double>& a, const dolfinx::la::Vector<double>& b)
{
  const std::int32_t n = a.map()->size_local() * a.bs();
  double s = 0;
  for (std::int32_t i = 0; i < n; ++i)
    s += a.array()[i] * b.array()[i];
  MPI_Allreduce(MPI_IN_PLACE, &s, 1, MPI_DOUBLE, MPI_SUM, a.map()->comm());
  return s;
}

double norm(const dolfinx::la::Vector<double>& b) { return std::sqrt(dot(b, b)); }

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
      x_old(x.map(), x.bs()), b_start(x.map(), x.bs());
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

    const std::size_t n = report.residuals.size();
    const bool slow = n >= 2 && report.residuals[n - 1] > 0.25 * report.residuals[n - 2];
    double t = MPI_Wtime();
    if (!settings.reuse_jacobian || !_factorised || slow)
    {
      jacobian(_A);
      ++timings.jacobians;
      timings.assemble += MPI_Wtime() - t;
      t = MPI_Wtime();
      KSPSetOperators(_ksp, _A, _A);
      _factorised = true;
    }
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
    std::copy(b.array().begin(), b.array().end(), b_start.mutable_array().begin());

    // Step length. x(alpha) = x_old - alpha dx. "energy": find alpha where
    // the residual is orthogonal to the step, g(alpha) = dx . R(x(alpha))
    // = 0 (the energy's directional derivative), by secant steps from
    // alpha = 1; a non-finite residual halves alpha. Full steps otherwise.
    std::copy(x.array().begin(), x.array().end(), x_old.mutable_array().begin());
    auto take = [&](double alpha)
    {
      for (std::size_t i = 0; i < x.array().size(); ++i)
        x.mutable_array()[i] = x_old.array()[i] - alpha * dx.array()[i];
      return assemble_residual();
    };
    double alpha = 1.0, r_new = take(alpha);
    while (!std::isfinite(r_new) && alpha > 1.0 / 64)
      r_new = take(alpha /= 2);
    if (settings.line_search && std::isfinite(r_new))
    {
      const double g0 = dot(dx, b_start);
      double g = dot(dx, b);
      bool at_alpha = true; // do x and b hold the state at alpha?
      for (int k = 0; k < 5 && std::abs(g) > 0.5 * std::abs(g0) && g * g0 < 0; ++k)
      {
        // Secant between (0, g0) and (alpha, g), kept within [alpha/10, alpha].
        const double next = std::clamp(alpha * g0 / (g0 - g), 0.1 * alpha, alpha);
        const double r_try = take(next);
        if (!std::isfinite(r_try))
        {
          at_alpha = false;
          break;
        }
        alpha = next, r_new = r_try, g = dot(dx, b);
      }
      if (!at_alpha)
        r_new = take(alpha);
    }
    ++report.iterations;
    r = r_new;
    report.residuals.push_back(r);
    if (!std::isfinite(r))
      report.reason = "the residual became NaN or Inf";
  }
  VecDestroy(&b_petsc);
  VecDestroy(&dx_petsc);
  if (!report.converged)
    _factorised = false; // the caller restarts elsewhere: start afresh
  return report;
}

} // namespace nct::solver
