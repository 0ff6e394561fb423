// Anderson acceleration of a fixed-point iteration, here the modified
// Newton iteration on a kept factorisation.
#pragma once

#include <span>
#include <vector>

#include <mpi.h>

namespace nct::solver
{

/// Anderson acceleration (type II, depth m) of x_{k+1} = x_k - f(x_k):
///
///     gamma = argmin | f_k - dF gamma |_2,
///     x_{k+1} = x_k - f_k - (dX - dF) gamma,
///
/// with dX, dF the differences of the last m + 1 iterates and steps
/// (H. F. Walker, P. Ni, SIAM J. Numer. Anal. 49 (2011) 1715-1735). With
/// f = P^-1 R for a fixed P it is GMRES on the linearised problem,
/// preconditioned by P (ibid., section 2): a modified Newton iteration whose
/// kept Jacobian treats a few modes badly (a thin shell's soft modes, whose
/// stiffness changes fast) converges in about as many extra iterations as
/// there are such modes, instead of stalling.
///
/// A vector is a rank's owned entries followed by the global unknowns that
/// every rank holds (a bordered system's multipliers, counted once).
class Anderson
{
public:
  /// `depth` m >= 1 past steps; `global` trailing entries held by every rank.
  Anderson(MPI_Comm comm, int depth, std::size_t global);

  /// Forget the history: the map changed (a new factorisation), or a new
  /// problem starts (a new load or time step).
  void reset() { _dX.clear(), _dF.clear(), _have_last = false; }

  /// Replace the step f (= f(x), x_{k+1} = x - f without acceleration) by
  /// the accelerated one and remember (x, f).
  void accelerate(std::span<const double> x, std::span<double> f);

  /// Past steps in use now.
  std::size_t size() const { return _dF.size(); }

private:
  /// u . v over every rank, the global entries once.
  std::vector<double> dots(const std::vector<std::pair<const double*, const double*>>& pairs,
                           std::size_t n) const;

  MPI_Comm _comm;
  std::size_t _depth, _global;
  std::vector<std::vector<double>> _dX, _dF;
  std::vector<double> _x_last, _f_last;
  bool _have_last = false;
};

} // namespace nct::solver
