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

/// The max norm of (x, y) over every rank.
double max_norm(const dolfinx::la::Vector<double>& x, const std::vector<double>& y)
{
  const std::int32_t n = x.map()->size_local() * x.bs();
  double m = 0;
  for (std::int32_t i = 0; i < n; ++i)
    m = std::max(m, std::abs(x.array()[i]));
  for (double v : y)
    m = std::max(m, std::abs(v));
  MPI_Allreduce(MPI_IN_PLACE, &m, 1, MPI_DOUBLE, MPI_MAX, x.map()->comm());
  return m;
}

/// x = S^-1 r for a small dense S (row-major), by Gaussian elimination
/// with partial pivoting; NaN if S is singular.
std::vector<double> solve_dense(std::vector<double> S, std::vector<double> r)
{
  const std::size_t n = r.size();
  for (std::size_t k = 0; k < n; ++k)
  {
    std::size_t p = k;
    for (std::size_t i = k + 1; i < n; ++i)
      if (std::abs(S[i * n + k]) > std::abs(S[p * n + k]))
        p = i;
    if (S[p * n + k] == 0)
      return std::vector<double>(n, std::nan(""));
    for (std::size_t j = 0; j < n; ++j)
      std::swap(S[k * n + j], S[p * n + j]);
    std::swap(r[k], r[p]);
    for (std::size_t i = k + 1; i < n; ++i)
    {
      const double f = S[i * n + k] / S[k * n + k];
      for (std::size_t j = k; j < n; ++j)
        S[i * n + j] -= f * S[k * n + j];
      r[i] -= f * r[k];
    }
  }
  for (std::size_t k = n; k-- > 0;)
  {
    for (std::size_t j = k + 1; j < n; ++j)
      r[k] -= S[k * n + j] * r[j];
    r[k] /= S[k * n + k];
  }
  return r;
}

/// The reason of a diverging solve.
std::string format_growth(double smallest, double r, double limit)
{
  std::ostringstream s;
  s << "diverging: the residual norm grew from " << smallest << " to " << r
    << ", beyond " << limit << " times (solver.max_growth)";
  return s.str();
}

} // namespace

Timings& Timings::operator+=(const Timings& o)
{
  residual += o.residual, residuals += o.residuals;
  line_search_residuals += o.line_search_residuals;
  jacobian += o.jacobian, jacobians += o.jacobians, border_assemble += o.border_assemble;
  factorise += o.factorise, factorisations += o.factorisations;
  solve += o.solve, linear_solves += o.linear_solves, krylov_iterations += o.krylov_iterations;
  border += o.border;
  return *this;
}

Timings Timings::operator-(const Timings& o) const
{
  Timings d = *this;
  d.residual -= o.residual, d.residuals -= o.residuals;
  d.line_search_residuals -= o.line_search_residuals;
  d.jacobian -= o.jacobian, d.jacobians -= o.jacobians, d.border_assemble -= o.border_assemble;
  d.factorise -= o.factorise, d.factorisations -= o.factorisations;
  d.solve -= o.solve, d.linear_solves -= o.linear_solves;
  d.krylov_iterations -= o.krylov_iterations, d.border -= o.border;
  return d;
}

void set_petsc_options(const std::vector<std::pair<std::string, std::string>>& options,
                       Jacobian jacobian)
{
  // MUMPS with the PORD ordering: the fastest of AMD, AMF, QAMD, PORD and
  // MUMPS' automatic choice on the eye's shell meshes (scripts/benchmark.sh).
  std::map<std::string, std::string> all = {{"ksp_type", "preonly"},
                                            {"pc_type", "lu"},
                                            {"pc_factor_mat_solver_type", "mumps"},
                                            {"mat_mumps_icntl_7", "4"}};
  if (jacobian == Jacobian::krylov)
  {
    // Right preconditioning: the tolerance is on the true residual.
    all["ksp_type"] = "gmres";
    all["ksp_pc_side"] = "right";
    all["ksp_rtol"] = "1e-8";
    all["ksp_gmres_restart"] = "100";
    all["ksp_max_it"] = "100";
  }
  for (auto& [k, v] : options)
    all[k.rfind("-", 0) == 0 ? k.substr(1) : k] = v;
  for (auto& [k, v] : all)
    PetscOptionsSetValue(nullptr, ("-" + k).c_str(), v.empty() ? nullptr : v.c_str());
}

Newton::Newton(MPI_Comm comm, Mat A, const std::string& prefix) : _A(A)
{
  KSPCreate(comm, &_ksp);
  if (!prefix.empty())
    KSPSetOptionsPrefix(_ksp, prefix.c_str());
  KSPSetFromOptions(_ksp);
}

Newton::~Newton()
{
  if (_ksp)
    KSPDestroy(&_ksp);
}

NewtonReport Newton::solve(const System& system, const NewtonSettings& settings)
{
  using Vector = dolfinx::la::Vector<double>;
  Vector& x = *system.x;
  std::vector<double>& y = *system.y;
  const std::size_t ny = y.size();
  NewtonReport report;
  Vector b(x.map(), x.bs()), dx(x.map(), x.bs()), x_old(x.map(), x.bs()),
      b_start(x.map(), x.bs());
  // The border's C and Z are kept with the factorisation they were made
  // with: a kept (modified Newton) Jacobian keeps its border too.
  if (_Z.size() != ny || (ny > 0 && _Z[0].map() != x.map()))
  {
    _C.clear(), _Z.clear();
    for (std::size_t i = 0; i < ny; ++i)
      _C.push_back(b), _Z.push_back(b);
    _border_current = false;
  }
  std::vector<Vector> B(ny, b);
  std::vector<Vector>&C = _C, &Z = _Z;
  std::vector<double> g(ny), g_start(ny), y_old(ny), dy(ny);
  Vec b_petsc = dolfinx::la::petsc::create_vector_wrap(b);
  Vec dx_petsc = dolfinx::la::petsc::create_vector_wrap(dx);
  std::vector<Vec> B_petsc, Z_petsc;
  for (std::size_t i = 0; i < ny; ++i)
  {
    B_petsc.push_back(dolfinx::la::petsc::create_vector_wrap(B[i]));
    Z_petsc.push_back(dolfinx::la::petsc::create_vector_wrap(Z[i]));
  }

  auto assemble_residual = [&]
  {
    double t = MPI_Wtime();
    system.residual(b, g);
    timings.residual += MPI_Wtime() - t;
    ++timings.residuals;
    double r2 = dot(b, b);
    for (double gi : g)
      r2 += gi * gi;
    return std::sqrt(r2);
  };
  // dx . R + dy . G: the line search's slope.
  auto slope = [&](const Vector& r, const std::vector<double>& c)
  {
    double s = dot(dx, r);
    for (std::size_t i = 0; i < ny; ++i)
      s += dy[i] * c[i];
    return s;
  };
  const bool krylov = settings.jacobian == Jacobian::krylov;
  // A factorisation of the current Jacobian, A, as the KSP's preconditioner.
  auto factorise = [&]
  {
    const double t = MPI_Wtime();
    KSPSetReusePreconditioner(_ksp, PETSC_FALSE);
    KSPSetOperators(_ksp, _A, _A);
    KSPSetUp(_ksp);
    timings.factorise += MPI_Wtime() - t;
    ++timings.factorisations;
    _factorised = _fresh = true;
    _refactorise = false;
  };
  // sol = A^-1 rhs; under Jacobian::krylov a failed or slow solve
  // refactorises (now, or at the next Jacobian).
  auto solve_once = [&](Vec rhs, Vec sol, PetscInt& its)
  {
    const double t = MPI_Wtime();
    KSPSolve(_ksp, rhs, sol);
    KSPConvergedReason reason;
    KSPGetConvergedReason(_ksp, &reason);
    KSPGetIterationNumber(_ksp, &its);
    ++timings.linear_solves;
    timings.krylov_iterations += std::max<PetscInt>(its, 1);
    timings.solve += MPI_Wtime() - t;
    return reason;
  };
  auto linear_solve = [&](Vec rhs, Vec sol)
  {
    PetscInt its = 0;
    KSPConvergedReason reason = solve_once(rhs, sol, its);
    if (krylov && reason < 0 && !_fresh)
    {
      factorise();
      reason = solve_once(rhs, sol, its);
    }
    if (krylov && its > settings.krylov_refactorise)
      _refactorise = true;
    return reason;
  };

  std::vector<double> step_sizes; // max norm of each taken step
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
    // The first step of a solve is no test of the kept factorisation: from
    // new loads it often raises the residual norm even with the exact
    // Jacobian (a dynamic step's inertia, seen at every puff step).
    const bool slow
        = n >= 3 && report.residuals[n - 1] > settings.reuse_contraction * report.residuals[n - 2];
    const bool assemble = settings.jacobian != Jacobian::reuse || !_factorised || slow;
    if (assemble)
    {
      const double t = MPI_Wtime();
      system.jacobian(_A);
      ++timings.jacobians;
      timings.jacobian += MPI_Wtime() - t;
      _fresh = false;
      if (!krylov || !_factorised || _refactorise)
        factorise();
      else
      {
        // The new operator under the kept factorisation.
        KSPSetReusePreconditioner(_ksp, PETSC_TRUE);
        KSPSetOperators(_ksp, _A, _A);
      }
    }
    KSPConvergedReason ksp_reason = linear_solve(b_petsc, dx_petsc);
    if (ny > 0 && ksp_reason > 0)
    {
      // The border: Z = K^-1 B, then the Schur complement S = C Z.
      const double t_border = MPI_Wtime();
      if (assemble || !_border_current)
      {
        system.border(B, C);
        timings.border_assemble += MPI_Wtime() - t_border;
        for (std::size_t i = 0; i < ny && ksp_reason > 0; ++i)
          ksp_reason = linear_solve(B_petsc[i], Z_petsc[i]);
        _border_current = ksp_reason > 0;
      }
      std::vector<double> S(ny * ny), rhs(ny);
      for (std::size_t i = 0; i < ny; ++i)
      {
        rhs[i] = dot(C[i], dx) - g[i];
        for (std::size_t j = 0; j < ny; ++j)
          S[i * ny + j] = dot(C[i], Z[j]);
      }
      dy = solve_dense(S, rhs);
      for (std::size_t j = 0; j < ny; ++j)
        for (std::size_t k = 0; k < dx.array().size(); ++k)
          dx.mutable_array()[k] -= dy[j] * Z[j].array()[k];
      timings.border += MPI_Wtime() - t_border;
    }
    if (ksp_reason < 0)
    {
      report.reason = std::string("the linear solver failed (")
                      + KSPConvergedReasons[ksp_reason] + ")";
      break;
    }
    if (!std::all_of(dy.begin(), dy.end(), [](double v) { return std::isfinite(v); }))
    {
      report.reason = "the bordered system is singular (a constraint does not depend "
                      "on the field)";
      break;
    }
    if (!std::isfinite(dot(dx, dx)))
    {
      report.reason = "the linear solver returned NaN or Inf (a singular or "
                      "ill-conditioned Jacobian)";
      break;
    }
    dx.scatter_fwd();
    std::copy(b.array().begin(), b.array().end(), b_start.mutable_array().begin());
    g_start = g;

    // Step length. (x, y)(alpha) = (x, y)_old - alpha (dx, dy). "energy":
    // find alpha where the residual is orthogonal to the step, s(alpha)
    // = dx . R + dy . G = 0 (the energy's directional derivative), by
    // secant steps from alpha = 1; a non-finite residual halves alpha.
    // Full steps otherwise.
    std::copy(x.array().begin(), x.array().end(), x_old.mutable_array().begin());
    y_old = y;
    auto take = [&](double alpha)
    {
      for (std::size_t i = 0; i < x.array().size(); ++i)
        x.mutable_array()[i] = x_old.array()[i] - alpha * dx.array()[i];
      for (std::size_t i = 0; i < ny; ++i)
        y[i] = y_old[i] - alpha * dy[i];
      return assemble_residual();
    };
    // Why the state at the last take() is unusable; empty if it is usable.
    // An inverted element first: it is often why the residual is NaN.
    auto unusable = [&](double r_try) -> std::string
    {
      std::string why = system.inadmissible ? system.inadmissible() : std::string();
      if (why.empty() && !std::isfinite(r_try))
        why = "the residual is NaN or Inf";
      return why;
    };
    double alpha = 1.0, r_new = take(alpha);
    const int residuals_before = timings.residuals;
    std::string why = unusable(r_new);
    while (!why.empty() && alpha > 1.0 / 64)
      why = unusable(r_new = take(alpha /= 2));
    if (!why.empty())
    {
      report.reason = why + " even with the Newton step cut to 1/64";
      ++report.iterations;
      break;
    }
    if (settings.line_search)
    {
      const double s0 = slope(b_start, g_start);
      double s = slope(b, g);
      bool at_alpha = true; // do x, y and b, g hold the state at alpha?
      for (int k = 0; k < 5 && std::abs(s) > 0.5 * std::abs(s0) && s * s0 < 0; ++k)
      {
        // Secant between (0, s0) and (alpha, s), kept within [alpha/10, alpha].
        const double next = std::clamp(alpha * s0 / (s0 - s), 0.1 * alpha, alpha);
        const double r_try = take(next);
        if (!unusable(r_try).empty())
        {
          at_alpha = false;
          break;
        }
        alpha = next, r_new = r_try, s = slope(b, g);
      }
      if (!at_alpha)
        r_new = take(alpha);
    }
    timings.line_search_residuals += timings.residuals - residuals_before;
    ++report.iterations;
    r = r_new;
    report.residuals.push_back(r);
    // The increment test: with q the contraction of the last two steps,
    // the distance to the solution is about |dx_k| q / (1 - q).
    step_sizes.push_back(alpha * max_norm(dx, dy));
    if (settings.increment_tol > 0 && step_sizes.size() >= 2 && std::isfinite(r))
    {
      const double last = step_sizes.back(), q = last / step_sizes[step_sizes.size() - 2];
      if (q < 1 && last * q / (1 - q) <= settings.increment_tol)
      {
        report.converged = true;
        break;
      }
    }
    const double smallest
        = *std::min_element(report.residuals.begin(), report.residuals.end());
    if (r > settings.max_growth * smallest)
      report.reason = format_growth(smallest, r, settings.max_growth);
  }
  if (!report.converged && system.locate)
    report.reason += "; the residual is largest " + system.locate(b);
  VecDestroy(&b_petsc);
  VecDestroy(&dx_petsc);
  for (std::size_t i = 0; i < ny; ++i)
  {
    VecDestroy(&B_petsc[i]);
    VecDestroy(&Z_petsc[i]);
  }
  if (!report.converged)
    reset(); // the caller restarts elsewhere: start afresh
  return report;
}

} // namespace nct::solver
