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
    : _problem(problem), _unknowns(std::move(pressures)), _targets(problem.cavity_volumes())
{
}

Closed::Closed(solid::Problem& problem, std::vector<double> pressures,
               std::vector<double> targets, std::vector<double> forces)
    : _problem(problem), _unknowns(std::move(pressures)), _targets(std::move(targets))
{
  _unknowns.insert(_unknowns.end(), forces.begin(), forces.end());
}

std::vector<double>* Closed::unknowns()
{
  // The humors' forces join the unknowns when the dynamics start.
  const auto* humor = _problem.humor_inertia();
  _unknowns.resize(_targets.size() + (humor ? humor->size() : 0), 0.0);
  return &_unknowns;
}

void Closed::apply()
{
  const std::size_t n = _targets.size();
  _problem.set_cavity_pressures(pressures());
  if (auto* humor = _problem.humor_inertia())
    humor->set_forces(std::span<const double>(_unknowns).subspan(n));
}

void Closed::constraints(std::vector<double>& g) const
{
  const auto volumes = _problem.cavity_volumes();
  const double s = _problem.symmetry_factor();
  const std::size_t n = _targets.size();
  for (std::size_t c = 0; c < n; ++c)
    g[c] = (_targets[c] - volumes[c]) / s;
  if (const auto* humor = _problem.humor_inertia())
    humor->constraints(std::span<double>(g).subspan(n));
}

void Closed::border(std::vector<dolfinx::la::Vector<double>>& B,
                    std::vector<dolfinx::la::Vector<double>>& C, std::vector<double>& D) const
{
  const std::size_t n = _targets.size(), ny = B.size();
  for (std::size_t c = 0; c < n; ++c)
  {
    _problem.cavity_load(c, B[c]);
    _problem.volume_derivative(c, C[c]);
    for (double& v : C[c].mutable_array())
      v = -v;
  }
  if (const auto* humor = _problem.humor_inertia())
    for (std::size_t j = 0; n + j < ny; ++j)
    {
      _problem.humor_border(j, B[n + j]);
      std::copy(B[n + j].array().begin(), B[n + j].array().end(),
                C[n + j].mutable_array().begin());
      D[(n + j) * ny + n + j] = humor->compliance(j);
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
  return with_checks({_problem.u->x().get(), unknowns(), residual,
                      [this](Mat A)
                      {
                        apply();
                        _problem.jacobian(A);
                      },
                      [this](auto& B, auto& C, auto& D) { border(B, C, D); }, nullptr, nullptr},
                     _problem);
}

} // namespace nct::cavity
