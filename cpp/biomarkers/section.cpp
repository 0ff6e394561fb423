#include "biomarkers/section.h"

#include "meshio/model.h"

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>
#include <string>

#include <dolfinx/fem/DirichletBC.h>

namespace nct::biomarkers
{
namespace
{

constexpr double on_plane = 1e-8; // [mm]

double interpolate(const std::vector<double>& x, const std::vector<double>& f, double x0)
{
  auto it = std::upper_bound(x.begin(), x.end(), x0);
  const std::size_t i = std::clamp<std::size_t>(it - x.begin(), 1, x.size() - 1) - 1;
  const double s = (x0 - x[i]) / (x[i + 1] - x[i]);
  return (1 - s) * f[i] + s * f[i + 1];
}

} // namespace

Profile SectionState::profile() const
{
  // The axis node appears once; the others also at -x.
  Profile p;
  for (std::size_t i = x.size(); i-- > 1;)
    p.x.push_back(-x[i]), p.y.push_back(y[i]);
  p.x.insert(p.x.end(), x.begin(), x.end());
  p.y.insert(p.y.end(), y.begin(), y.end());
  return p;
}

double SectionState::displacement_at(double X0) const { return interpolate(X, uy, X0); }

Section::Section(const solid::Problem& problem, const std::vector<std::int32_t>& facets,
                 const char* surface)
    : _comm(problem.u->function_space()->mesh()->comm()), _problem(problem)
{
  const auto& V = *problem.u->function_space();
  // A 2D mesh is the eye's meridian section: the plane z = 0 itself.
  const auto dofs
      = dolfinx::fem::locate_dofs_topological(V, V.mesh()->topology().dim() - 1, facets);
  const std::vector<double> X = V.tabulate_dof_coordinates(false);
  const std::int32_t owned = V.dofmap()->index_map->size_local();
  std::vector<double> local;
  for (std::int32_t d : dofs)
    if (d < owned && std::abs(X[3 * d + 2]) < on_plane)
    {
      _nodes.push_back(d);
      local.insert(local.end(), {X[3 * d], X[3 * d + 1]});
    }
  _X = meshio::all_gather(_comm, local);
  const std::size_t n = _X.size() / 2;
  _order.resize(n);
  std::iota(_order.begin(), _order.end(), 0);
  std::sort(_order.begin(), _order.end(),
            [&](auto a, auto b) { return _X[2 * a] < _X[2 * b]; });
  if (n < 3 || std::abs(_X[2 * _order[0]]) > on_plane)
    throw std::runtime_error(std::string("the horizontal section of the ") + surface
                             + " holds " + std::to_string(n)
                             + " nodes, none on the axis: the profile needs the axis "
                               "and at least two more");
}

SectionState Section::sample() const
{
  // v_old holds the velocity of the last converged step (zero until the
  // dynamics start).
  const auto u = _problem.u->x()->array(), v = _problem.v_old->x()->array();
  const int bs = _problem.u->x()->bs();
  std::vector<double> local;
  for (std::int32_t d : _nodes)
    local.insert(local.end(), {u[bs * d], u[bs * d + 1], v[bs * d], v[bs * d + 1]});
  const std::vector<double> all = meshio::all_gather(_comm, local);
  SectionState s;
  for (std::size_t i : _order)
  {
    s.X.push_back(_X[2 * i]);
    s.x.push_back(_X[2 * i] + all[4 * i]);
    s.y.push_back(_X[2 * i + 1] + all[4 * i + 1]);
    s.uy.push_back(all[4 * i + 1]);
    s.vx.push_back(all[4 * i + 2]);
    s.vy.push_back(all[4 * i + 3]);
  }
  return s;
}

} // namespace nct::biomarkers
