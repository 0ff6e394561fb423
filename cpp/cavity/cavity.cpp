#include "cavity/cavity.h"

namespace nct::cavity
{

solver::System Open::system()
{
  return {_problem.u->x().get(), &_none,
          [this](auto& b, auto&) { _problem.residual(b); },
          [this](Mat A) { _problem.jacobian(A); }, nullptr};
}

Closed::Closed(solid::Problem& problem, std::vector<double> pressures)
    : _problem(problem), _pressures(std::move(pressures)),
      _targets(problem.cavity_volumes())
{
}

solver::System Closed::system()
{
  auto residual = [this](dolfinx::la::Vector<double>& b, std::vector<double>& g)
  {
    _problem.set_cavity_pressures(_pressures);
    _problem.residual(b);
    const auto volumes = _problem.cavity_volumes();
    const double s = _problem.symmetry_factor();
    for (std::size_t c = 0; c < g.size(); ++c)
      g[c] = (_targets[c] - volumes[c]) / s;
  };
  auto border = [this](auto& B, auto& C)
  {
    for (std::size_t c = 0; c < B.size(); ++c)
    {
      _problem.cavity_load(c, B[c]);
      _problem.volume_derivative(c, C[c]);
      for (double& v : C[c].mutable_array())
        v = -v;
    }
  };
  return {_problem.u->x().get(), &_pressures, residual,
          [this](Mat A)
          {
            _problem.set_cavity_pressures(_pressures);
            _problem.jacobian(A);
          },
          border};
}

} // namespace nct::cavity
