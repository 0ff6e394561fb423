#include "cavity/cavity.h"

#include <limits>

#include "io/format.h"

namespace nct::cavity
{
namespace
{

using io::format;

std::string where(const solid::Problem::Place& p)
{
  return format("at X = (%.3f, %.3f, %.3f) mm", p.x[0], p.x[1], p.x[2])
         + (p.part.empty() ? "" : " in the " + p.part);
}

/// The solid's checks: inverted elements, and where the residual is largest.
solver::System with_checks(solver::System system, const solid::Problem& problem)
{
  system.inadmissible = [&problem]
  {
    const auto w = problem.smallest_jacobian();
    if (w.value > 0)
      return std::string();
    return (w.value == -std::numeric_limits<double>::infinity()
                ? std::string("det F is NaN ")
                : format("an element inverted: det F = %.3g ", w.value))
           + where(w);
  };
  system.locate = [&problem](const dolfinx::la::Vector<double>& b)
  {
    const auto w = problem.largest_residual(b);
    return format("(%.3e N) ", w.value) + where(w);
  };
  return system;
}

} // namespace

solver::System Open::system()
{
  return with_checks({_problem.u->x().get(), &_none,
                      [this](auto& b, auto&) { _problem.residual(b); },
                      [this](Mat A) { _problem.jacobian(A); }, nullptr, nullptr, nullptr},
                     _problem);
}

Closed::Closed(solid::Problem& problem, std::vector<double> pressures)
    : _problem(problem), _pressures(std::move(pressures)),
      _targets(problem.cavity_volumes())
{
}

void Closed::apply() { _problem.set_cavity_pressures(_pressures); }

void Closed::constraints(std::vector<double>& g) const
{
  const auto volumes = _problem.cavity_volumes();
  const double s = _problem.symmetry_factor();
  for (std::size_t c = 0; c < g.size(); ++c)
    g[c] = (_targets[c] - volumes[c]) / s;
}

void Closed::border(std::vector<dolfinx::la::Vector<double>>& B,
                    std::vector<dolfinx::la::Vector<double>>& C) const
{
  for (std::size_t c = 0; c < B.size(); ++c)
  {
    _problem.cavity_load(c, B[c]);
    _problem.volume_derivative(c, C[c]);
    for (double& v : C[c].mutable_array())
      v = -v;
  }
}

solver::System Closed::system()
{
  auto residual = [this](dolfinx::la::Vector<double>& b, std::vector<double>& g)
  {
    apply();
    _problem.residual(b);
    constraints(g);
  };
  return with_checks({_problem.u->x().get(), &_pressures, residual,
                      [this](Mat A)
                      {
                        apply();
                        _problem.jacobian(A);
                      },
                      [this](auto& B, auto& C) { border(B, C); }, nullptr, nullptr},
                     _problem);
}

} // namespace nct::cavity
