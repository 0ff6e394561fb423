// [solver]: Newton's stopping and globalisation, the step control, the
// linear solver.
#include "settings/settings.h"

namespace nct
{
namespace
{
constexpr double inf = std::numeric_limits<double>::infinity();
} // namespace

void visit(scene::Visitor& v, SolverSettings& s)
{
  auto& n = s.newton;
  v.integer({"solver.max_iterations", "25", "", 1, 500,
             "Newton iterations per load step before the step is cut"},
            n.max_iterations);
  v.real({"solver.rtol", "1e-9", "", 1e-16, 1e-1,
          "Newton: residual norm relative to the step's first residual"},
         n.rtol);
  v.real({"solver.atol", "1e-11", "N", 0, 1, "Newton: absolute residual norm"}, n.atol);
  v.choice({"solver.line_search", "energy", "", -inf, inf,
            "Newton step length: energy = secant search for the zero of the residual projected "
            "on the step (non-finite residuals halve it); none = full steps"},
           n.line_search, {{"energy", true}, {"none", false}});
  v.choice({"solver.jacobian", "reuse", "", -inf, inf,
            "reuse = keep the factorised Jacobian while each Newton iteration cuts the residual "
            "by solver.reuse_contraction (modified Newton, fewer factorisations); "
            "every_iteration = full Newton (quadratic convergence, a factorisation per "
            "iteration); krylov = full Newton whose linear solves are GMRES preconditioned by "
            "the last factorisation, refactorised when GMRES needs more than "
            "solver.krylov_refactorise iterations"},
           n.jacobian,
           {{"reuse", solver::Jacobian::reuse},
            {"every_iteration", solver::Jacobian::every_iteration},
            {"krylov", solver::Jacobian::krylov}});
  v.real({"solver.reuse_contraction", "0.7", "", 0.01, 0.99,
          "solver.jacobian = reuse: refactorise once a Newton iteration (after a solve's "
          "first) cuts the residual norm by less than this factor (0.7 with the Anderson "
          "acceleration, which keeps a factorisation longer; 0.25 without)"},
         n.reuse_contraction);
  v.choice({"solver.factorisation", "lu", "", -inf, inf,
            "the solid's factorised Jacobian: lu = MUMPS LU of the Jacobian (Newton converges "
            "quadratically with a fresh one, also near limit points); ldlt = MUMPS LDL^T of its "
            "upper triangle taken as symmetric, a third cheaper to factorise and half to "
            "assemble, the follower pressures' skew part left to the iteration (linear "
            "convergence; it can stall near a limit load or with nearly incompressible parts); "
            "not with solver.jacobian = krylov"},
           s.ldlt, {{"lu", false}, {"ldlt", true}});
  v.integer({"solver.reuse_iterations", "1000", "", 1, 1000,
             "solver.jacobian = reuse: refactorise after this many iterations on one "
             "factorisation within a solve"},
            n.reuse_iterations);
  v.integer({"solver.anderson", "5", "", 0, 50,
             "solver.jacobian = reuse: Anderson acceleration of the iteration on the kept "
             "factorisation over this many past steps (nonlinear GMRES; Walker & Ni 2011); 0 = "
             "plain modified Newton"},
            n.anderson);
  v.integer({"solver.krylov_refactorise", "10", "", 1, 1000,
             "solver.jacobian = krylov: refactorise the preconditioner once a linear solve needs "
             "more GMRES iterations than this"},
            n.krylov_refactorise);
  v.choice({"solver.predictor", "extrapolate", "", -inf, inf,
            "a step's first Newton iterate: previous = the last converged state; extrapolate = "
            "a load ramp's secant through the last two, the solid's time step's "
            "constant-acceleration state u_n + dt v_n + dt^2/2 a_n (the air's and the coupled "
            "system's: the secant)"},
           s.extrapolate, {{"previous", false}, {"extrapolate", true}});
  v.real({"solver.increment_tol", "0", "mm", 0, 1,
          "Newton also converges when its error estimate from the last two steps, |dx| q/(1-q) "
          "with q the steps' ratio (max norm, the unknowns' units: mm, mm/ms, MPa), is below "
          "this; 0 = off (the residual tests only)"},
         n.increment_tol);
  v.real({"solver.max_growth", "1e4", "", 2, 1e12,
          "Newton counts as diverging (and the step is cut) once the residual norm exceeds this "
          "multiple of its smallest value in the solve"},
         n.max_growth);
  v.integer({"solver.max_step_cuts", "8", "", 0, 30,
             "a failed load step is halved, down to 2^-max_step_cuts of the nominal step; "
             "failing there stops the run"},
            s.max_step_cuts);
  v.options({"solver.petsc", "{}", "", -inf, inf,
             "PETSc options for the linear solver (default: MUMPS LU), e.g. ksp_type = \"cg\""},
            s.petsc);
}

} // namespace nct
