#include "solver/newton.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <sstream>

#include <dolfinx/la/petsc.h>

#include "io/format.h"
#include "solver/dense.h"

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

/// The reason of a diverging solve.
std::string format_growth(double smallest, double r, double limit)
{
  std::ostringstream s;
  s << "diverging: the residual norm grew from " << smallest << " to " << r
    << ", beyond " << limit << " times (solver.max_growth)";
  return s.str();
}

/// Why a preconditioner failed, for messages: ", PC: ..." (with MUMPS'
/// INFOG(1): -9 and -8 its workspace, -10 a singular matrix), or "".
std::string pc_failure(KSP ksp)
{
  PC pc;
  KSPGetPC(ksp, &pc);
  PCFailedReason mine = PC_NOERROR;
  PCGetFailedReasonRank(pc, &mine);
  // Any rank's failure (the lowest code; PC_SETUP_ERROR is -1).
  int why = mine == PC_NOERROR ? 1000 : int(mine);
  MPI_Allreduce(MPI_IN_PLACE, &why, 1, MPI_INT, MPI_MIN, PetscObjectComm((PetscObject)ksp));
  if (why == 1000)
    return "";
  std::string out = std::string(", PC: ") + PCFailedReasons[why];
  Mat F = nullptr;
  PetscBool factor = PETSC_FALSE;
  PetscObjectTypeCompareAny((PetscObject)pc, &factor, PCLU, PCCHOLESKY, "");
  MatSolverType type = nullptr;
  if (factor)
  {
    PCFactorGetMatSolverType(pc, &type);
    PCFactorGetMatrix(pc, &F);
  }
  if (F && type && std::string(type) == MATSOLVERMUMPS)
  {
    PetscInt infog1 = 0, infog2 = 0;
    MatMumpsGetInfog(F, 1, &infog1);
    MatMumpsGetInfog(F, 2, &infog2);
    out += io::format(", MUMPS INFOG(1) = %d, INFOG(2) = %d", int(infog1), int(infog2));
  }
  return out;
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

void to_json(nlohmann::json& j, const Timings& t)
{
  j = {{"residual_s", t.residual},
       {"residuals", t.residuals},
       {"line_search_residuals", t.line_search_residuals},
       {"jacobian_s", t.jacobian},
       {"jacobians", t.jacobians},
       {"border_assemble_s", t.border_assemble},
       {"factorise_s", t.factorise},
       {"factorisations", t.factorisations},
       {"solve_s", t.solve},
       {"linear_solves", t.linear_solves},
       {"krylov_iterations", t.krylov_iterations},
       {"border_s", t.border}};
}

void from_json(const nlohmann::json& j, Timings& t)
{
  j.at("residual_s").get_to(t.residual);
  j.at("residuals").get_to(t.residuals);
  j.at("line_search_residuals").get_to(t.line_search_residuals);
  j.at("jacobian_s").get_to(t.jacobian);
  j.at("jacobians").get_to(t.jacobians);
  j.at("border_assemble_s").get_to(t.border_assemble);
  j.at("factorise_s").get_to(t.factorise);
  j.at("factorisations").get_to(t.factorisations);
  j.at("solve_s").get_to(t.solve);
  j.at("linear_solves").get_to(t.linear_solves);
  j.at("krylov_iterations").get_to(t.krylov_iterations);
  j.at("border_s").get_to(t.border);
}

void set_petsc_options(const std::vector<std::pair<std::string, std::string>>& options,
                       Jacobian jacobian)
{
  // MUMPS with the PORD ordering: the fastest of AMD, AMF, QAMD, PORD and
  // MUMPS' automatic choice on the eye's shell meshes (cases/benchmark-scaling).
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

using Vector = dolfinx::la::Vector<double>;

struct Newton::Work
{
  Work(const System& s, std::vector<Vector>& Z)
      : system(s), x(*s.x), y(*s.y), b(x.map(), x.bs()), dx(x.map(), x.bs()),
        x_old(x.map(), x.bs()), b_start(x.map(), x.bs()), B(y.size(), b), g(y.size()),
        g_start(y.size()), y_old(y.size()), dy(y.size()),
        b_petsc(dolfinx::la::petsc::create_vector_wrap(b)),
        dx_petsc(dolfinx::la::petsc::create_vector_wrap(dx))
  {
    for (std::size_t i = 0; i < y.size(); ++i)
    {
      B_petsc.push_back(dolfinx::la::petsc::create_vector_wrap(B[i]));
      Z_petsc.push_back(dolfinx::la::petsc::create_vector_wrap(Z[i]));
    }
  }
  ~Work()
  {
    VecDestroy(&b_petsc);
    VecDestroy(&dx_petsc);
    for (std::size_t i = 0; i < B_petsc.size(); ++i)
      VecDestroy(&B_petsc[i]), VecDestroy(&Z_petsc[i]);
  }
  Work(const Work&) = delete;
  Work& operator=(const Work&) = delete;

  /// b, g at the current state; the residual norm.
  double residual(Timings& timings)
  {
    const double t = MPI_Wtime();
    system.residual(b, g);
    timings.residual += MPI_Wtime() - t;
    ++timings.residuals;
    double r2 = dot(b, b);
    for (double gi : g)
      r2 += gi * gi;
    return std::sqrt(r2);
  }
  /// dx . R + dy . G at (r, c): the line search's slope.
  double slope(const Vector& r, const std::vector<double>& c) const
  {
    double s = dot(dx, r);
    for (std::size_t i = 0; i < dy.size(); ++i)
      s += dy[i] * c[i];
    return s;
  }
  /// (x, y) = (x, y)_old - alpha (dx, dy); the residual norm there.
  double take(double alpha, Timings& timings)
  {
    for (std::size_t i = 0; i < x.array().size(); ++i)
      x.mutable_array()[i] = x_old.array()[i] - alpha * dx.array()[i];
    for (std::size_t i = 0; i < y.size(); ++i)
      y[i] = y_old[i] - alpha * dy[i];
    return residual(timings);
  }
  /// Why the current state is unusable (an inverted element first: it is
  /// often why the residual is NaN), given its residual norm; empty if usable.
  std::string unusable(double r) const
  {
    std::string why = system.inadmissible ? system.inadmissible() : std::string();
    if (why.empty() && !std::isfinite(r))
      why = "the residual is NaN or Inf";
    return why;
  }

  const System& system;
  Vector& x;
  std::vector<double>& y;
  Vector b, dx, x_old, b_start;
  std::vector<Vector> B;
  std::vector<double> g, g_start, y_old, dy;
  Vec b_petsc, dx_petsc;
  std::vector<Vec> B_petsc, Z_petsc;
};

void Newton::factorise()
{
  const double t = MPI_Wtime();
  KSPSetReusePreconditioner(_ksp, PETSC_FALSE);
  KSPSetOperators(_ksp, _A, _A);
  KSPSetUp(_ksp);
  timings.factorise += MPI_Wtime() - t;
  ++timings.factorisations;
  _factorised = _fresh = true;
  _refactorise = false;
  _uses = 0;
  if (_anderson)
    _anderson->reset();
}

bool Newton::enlarge_workspace(bool forced)
{
  PC pc;
  KSPGetPC(_ksp, &pc);
  Mat F = nullptr;
  MatSolverType type = nullptr;
  PetscBool factor = PETSC_FALSE;
  PetscObjectTypeCompareAny((PetscObject)pc, &factor, PCLU, PCCHOLESKY, "");
  if (factor)
  {
    PCFactorGetMatSolverType(pc, &type);
    PCFactorGetMatrix(pc, &F);
  }
  if (!F || !type || std::string(type) != MATSOLVERMUMPS)
    return false;
  // INFOG is global: every rank takes the same branch.
  PetscInt infog1 = 0, icntl14 = 0;
  MatMumpsGetInfog(F, 1, &infog1);
  MatMumpsGetIcntl(F, 14, &icntl14);
  // -8, -9, -11, -12, -14, -15: a workspace (integer or real, for the
  // factors or the solution) smaller than the analysis estimated, as when
  // pivoting delays more pivots than planned (on several ranks that
  // depends on round-off in the assembly's order).
  const bool short_of_space = infog1 == -8 || infog1 == -9 || infog1 == -11 || infog1 == -12
                              || infog1 == -14 || infog1 == -15;
  if (!short_of_space && !forced)
    return false;
  const PetscInt more = std::max<PetscInt>(2 * icntl14, 40);
  if (more > 1280)
    return false; // 64 times the default: not a matter of workspace
  const char* prefix = nullptr;
  KSPGetOptionsPrefix(_ksp, &prefix);
  PetscOptionsSetValue(nullptr, ("-" + std::string(prefix ? prefix : "") + "mat_mumps_icntl_14").c_str(),
                       std::to_string(more).c_str());
  int rank = 0;
  MPI_Comm_rank(PetscObjectComm((PetscObject)_ksp), &rank);
  if (rank == 0)
    std::cout << io::format("  linear solver: MUMPS ran short of workspace (%s); its allowance "
                            "ICNTL(14) raised from %d to %d %%, the matrix factorised anew",
                            forced ? "a test's retry"
                                   : io::format("INFOG(1) = %d", int(infog1)).c_str(),
                            int(icntl14), int(more))
              << std::endl;
  PCReset(pc);
  return true;
}

KSPConvergedReason Newton::linear_solve(Vec rhs, Vec sol, const NewtonSettings& settings)
{
  auto once = [&](PetscInt& its)
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
  const bool krylov = settings.jacobian == Jacobian::krylov;
  PetscInt its = 0;
  KSPConvergedReason reason = once(its);
  // MUMPS short of workspace: more of it, the same matrix again. A test
  // forces such retries on good factorisations (NCT_TEST_MUMPS_RETRY=n).
  static int test_retries = []
  {
    const char* n = std::getenv("NCT_TEST_MUMPS_RETRY");
    return n ? std::atoi(n) : 0;
  }();
  while (_fresh && (reason == KSP_DIVERGED_PC_FAILED || test_retries > 0)
         && enlarge_workspace(reason != KSP_DIVERGED_PC_FAILED && test_retries-- > 0))
  {
    factorise();
    reason = once(its);
  }
  if (krylov && reason < 0 && !_fresh)
  {
    factorise();
    reason = once(its);
  }
  if (krylov && its > settings.krylov_refactorise)
    _refactorise = true;
  return reason;
}

std::string Newton::newton_step(Work& w, bool assemble, const NewtonSettings& settings)
{
  const std::size_t ny = w.y.size();
  if (assemble)
  {
    const double t = MPI_Wtime();
    w.system.jacobian(_A);
    ++timings.jacobians;
    timings.jacobian += MPI_Wtime() - t;
    _fresh = false;
    if (settings.jacobian != Jacobian::krylov || !_factorised || _refactorise)
      factorise();
    else
    {
      // The new operator under the kept factorisation.
      KSPSetReusePreconditioner(_ksp, PETSC_TRUE);
      KSPSetOperators(_ksp, _A, _A);
    }
  }
  KSPConvergedReason reason = linear_solve(w.b_petsc, w.dx_petsc, settings);
  if (ny > 0 && reason > 0)
  {
    // The border: Z = K^-1 B, then the Schur complement S = C Z - D.
    const double t = MPI_Wtime();
    if (assemble || !_border_current)
    {
      _D.assign(ny * ny, 0.0);
      w.system.border(w.B, _C, _D);
      timings.border_assemble += MPI_Wtime() - t;
      for (std::size_t i = 0; i < ny && reason > 0; ++i)
        reason = linear_solve(w.B_petsc[i], w.Z_petsc[i], settings);
      _border_current = reason > 0;
    }
    std::vector<double> S(ny * ny), rhs(ny);
    for (std::size_t i = 0; i < ny; ++i)
    {
      rhs[i] = dot(_C[i], w.dx) - w.g[i];
      for (std::size_t j = 0; j < ny; ++j)
        S[i * ny + j] = dot(_C[i], _Z[j]) - _D[i * ny + j];
    }
    w.dy = solve_dense(S, rhs);
    for (std::size_t j = 0; j < ny; ++j)
      for (std::size_t k = 0; k < w.dx.array().size(); ++k)
        w.dx.mutable_array()[k] -= w.dy[j] * _Z[j].array()[k];
    timings.border += MPI_Wtime() - t;
  }
  if (reason < 0)
    return std::string("the linear solver failed (") + KSPConvergedReasons[reason]
           + pc_failure(_ksp) + ")";
  if (!std::all_of(w.dy.begin(), w.dy.end(), [](double v) { return std::isfinite(v); }))
    return "the bordered system is singular (a constraint does not depend on the field)";
  if (!std::isfinite(dot(w.dx, w.dx)))
    return "the linear solver returned NaN or Inf (a singular or ill-conditioned Jacobian)";
  ++_uses;
  if (_anderson)
  {
    // The step and the state as one vector of owned entries and y.
    const std::size_t owned = w.x.map()->size_local() * w.x.bs();
    std::vector<double> state(owned + ny), step(owned + ny);
    std::copy_n(w.x.array().begin(), owned, state.begin());
    std::copy(w.y.begin(), w.y.end(), state.begin() + owned);
    std::copy_n(w.dx.array().begin(), owned, step.begin());
    std::copy(w.dy.begin(), w.dy.end(), step.begin() + owned);
    _anderson->accelerate(state, step);
    std::copy_n(step.begin(), owned, w.dx.mutable_array().begin());
    std::copy(step.begin() + owned, step.end(), w.dy.begin());
  }
  w.dx.scatter_fwd();
  return "";
}

std::string Newton::take_step(Work& w, const NewtonSettings& settings, double& alpha, double& r)
{
  std::copy(w.b.array().begin(), w.b.array().end(), w.b_start.mutable_array().begin());
  w.g_start = w.g;
  std::copy(w.x.array().begin(), w.x.array().end(), w.x_old.mutable_array().begin());
  w.y_old = w.y;
  alpha = 1.0;
  r = w.take(alpha, timings);
  const int residuals_before = timings.residuals;
  std::string why = w.unusable(r);
  while (!why.empty() && alpha > 1.0 / 64)
    why = w.unusable(r = w.take(alpha /= 2, timings));
  if (!why.empty())
    return why + " even with the Newton step cut to 1/64";
  if (settings.line_search)
  {
    // Energy line search: find alpha where the residual is orthogonal to
    // the step, s(alpha) = dx . R + dy . G = 0 (the energy's directional
    // derivative), by secant steps from alpha = 1, kept within
    // [alpha/10, alpha]; an unusable state ends it at the last alpha.
    const double s0 = w.slope(w.b_start, w.g_start);
    double s = w.slope(w.b, w.g);
    bool at_alpha = true; // do x, y and b, g hold the state at alpha?
    for (int k = 0; k < 5 && std::abs(s) > 0.5 * std::abs(s0) && s * s0 < 0; ++k)
    {
      const double next = std::clamp(alpha * s0 / (s0 - s), 0.1 * alpha, alpha);
      const double r_try = w.take(next, timings);
      if (!w.unusable(r_try).empty())
      {
        at_alpha = false;
        break;
      }
      alpha = next, r = r_try, s = w.slope(w.b, w.g);
    }
    if (!at_alpha)
      r = w.take(alpha, timings);
  }
  timings.line_search_residuals += timings.residuals - residuals_before;
  return "";
}

NewtonReport Newton::solve(const System& system, const NewtonSettings& settings)
{
  const std::size_t ny = system.y->size();
  NewtonReport report;
  // The border's C and Z are kept with the factorisation they were made
  // with: a kept (modified Newton) Jacobian keeps its border too.
  if (_Z.size() != ny || (ny > 0 && _Z[0].map() != system.x->map()))
  {
    _C.clear(), _Z.clear();
    for (std::size_t i = 0; i < ny; ++i)
      _C.emplace_back(system.x->map(), system.x->bs()),
          _Z.emplace_back(system.x->map(), system.x->bs());
    _border_current = false;
  }
  const bool accelerate = settings.jacobian == Jacobian::reuse && settings.anderson > 0;
  if (!accelerate)
    _anderson.reset();
  else if (!_anderson)
    _anderson.emplace(system.x->map()->comm(), settings.anderson, ny);
  if (_anderson)
    _anderson->reset(); // a new problem: no secants across solves
  _uses = 0;
  Work w(system, _Z);

  std::vector<double> step_sizes; // max norm of each taken step
  double r = w.residual(timings);
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
    // The first step of a solve is no test of the kept factorisation: from
    // new loads it often raises the residual norm even with the exact
    // Jacobian (a dynamic step's inertia, seen at every puff step).
    const std::size_t n = report.residuals.size();
    const bool slow = (n >= 3
                       && report.residuals[n - 1]
                              > settings.reuse_contraction * report.residuals[n - 2])
                      || _uses >= settings.reuse_iterations;
    const bool assemble = settings.jacobian != Jacobian::reuse || !_factorised || slow;
    report.reason = newton_step(w, assemble, settings);
    if (!report.reason.empty())
      break;
    double alpha = 1;
    report.reason = take_step(w, settings, alpha, r);
    ++report.iterations;
    if (!report.reason.empty())
      break;
    report.residuals.push_back(r);
    // The increment test: with q the contraction of the last two steps,
    // the distance to the solution is about |dx_k| q / (1 - q).
    step_sizes.push_back(alpha * max_norm(w.dx, w.dy));
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
    report.reason += "; the residual is largest " + system.locate(w.b);
  if (!report.converged)
    reset(); // the caller restarts elsewhere: start afresh
  return report;
}

} // namespace nct::solver
