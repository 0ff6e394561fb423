// A fit on an emulator of the forward model (cpp/emulator): the Gaussian
// likelihood of the readings with the emulator's own uncertainty beside
// the readings' noise (Kennedy and O'Hagan 2001, eq. 5 without the
// discrepancy):
//
//   -2 log L = e^T S^-1 e + log det S + const,   e = m(theta) - y,
//   S = diag(sd^2) + C(theta),
//
// m and C the emulator's mean and covariance at the observation points
// (the curves' components correlate every frame; the readings are
// independent). For Levenberg-Marquardt the residuals are r = L^-1 e
// (S = L L^T), one residual sqrt(log det S - log det diag(sd^2)) and the
// priors', so that |r|^2 / 2 = -log L + const; their Jacobian is exact:
// dr/dtheta_j = L^-1 de/dtheta_j - Phi(L^-1 dS/dtheta_j L^-T) r, Phi the
// lower triangle with half the diagonal (the Cholesky factor's derivative,
// Murray 2016, arXiv:1602.07527).
#pragma once

#include <filesystem>
#include <vector>

#include <Eigen/Dense>

#include "emulator/emulator.h"
#include "fit/fit.h"

namespace nct::scene
{
class Scene;
}

namespace nct::fit
{

/// Check a fit's emulator against the fit: each emulator input a fitted
/// parameter (the same keys) or fixed by the scene with the fit's and the
/// patient's overrides, inside the box; the parameters' bounds and priors
/// inside it; each observation one the emulator answers (the apex or
/// whole-eye curve within its clock, the anterior profile at its frames
/// and places, a reading it holds within the range its training spanned).
/// Sets fit.emulator_inputs; throws scene::Error naming the key, the value
/// and the box.
void attach_emulator(Fit& fit, const scene::Scene& scene);

/// The likelihood of a fit's readings on its emulator.
class EmulatedLikelihood
{
public:
  explicit EmulatedLikelihood(const Fit& fit);

  /// The residuals for the solver: the whitened observations, the log
  /// determinant's, then the priors'.
  std::size_t residuals() const { return _y.size() + 1 + _priors; }

  /// The point's residuals and, when asked, their Jacobian
  /// (residuals x parameters).
  struct Evaluation
  {
    Eigen::VectorXd r;        ///< as residuals() lists them
    Eigen::MatrixXd jacobian; ///< when asked
    Eigen::VectorXd model;    ///< the emulator's mean at the observation points
    Eigen::VectorXd model_sd; ///< its SD there
    double chi2 = 0;          ///< e^T S^-1 e (the priors apart)
  };
  Evaluation evaluate(const std::vector<double>& theta, bool jacobian) const;

  /// log L + log prior at theta (flat in the fitted variables inside the
  /// bounds, -infinity outside); by the Woodbury identity, O(points x
  /// components^2).
  double log_posterior(const std::vector<double>& theta) const;

  /// How far the answer theta would move were the model's values at the
  /// observation points `values` (a forward run's) instead of the
  /// emulator's: the Gauss-Newton step -(J^T J)^-1 J^T L^-1 (values - m).
  Eigen::VectorXd shift(const std::vector<double>& theta, const std::vector<double>& values) const;

  /// The discrepancy's mean at the observation points (zero without one).
  const Eigen::VectorXd& discrepancy_mean() const { return _delta; }

  /// The emulator's inputs at the fitted variables theta.
  std::vector<double> inputs(const std::vector<double>& theta) const;

private:
  /// The emulator's mean, its gradient (points x parameters; zero without
  /// `derivatives`) and the covariance's parts at theta: factor F (points x components), the
  /// components' variances v and their gradients, a diagonal d (with the
  /// readings' noise) and its gradient.
  struct Parts
  {
    Eigen::VectorXd mean, v, d;
    Eigen::MatrixXd gradient, F, dv, dd; // dv: components x parameters; dd: points x parameters
  };
  Parts parts(const std::vector<double>& theta, bool derivatives = true) const;

  const Fit& _fit;
  std::vector<std::size_t> _curve_rows; ///< the curve and profile points' rows
  /// Their fixed part: mean offset, factor (points x components, zero rows
  /// for the readings), truncation (zero for the readings).
  Eigen::VectorXd _offset, _truncation, _delta;
  Eigen::MatrixXd _factor;
  std::vector<std::pair<std::size_t, std::string>> _reading_rows; ///< row, reading
  Eigen::VectorXd _y, _sd2;
  std::size_t _priors = 0;
};

} // namespace nct::fit
