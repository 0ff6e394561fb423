#include "solid/humor_inertia.h"

#include <stdexcept>

#include <dolfinx/fem/assembler.h>
#include <dolfinx/fem/utils.h>

#include "humor_inertia_p1_full.h"
#include "humor_inertia_p1_full_axisymmetric.h"
#include "humor_inertia_p1_full_plane.h"
#include "humor_inertia_p2_full.h"
#include "humor_inertia_p2_full_axisymmetric.h"
#include "humor_inertia_p2_full_plane.h"
#include "io/checkpoint.h"
#include "solid/problem.h"

namespace nct::solid
{
namespace
{
using namespace dolfinx;

/// The compiled forms of forms/humor_inertia.py for one element.
struct Kernels
{
  ufcx_form* moment;
  ufcx_form* load;
  ufcx_form* tangent;
};

#define NCT_HUMOR_KERNELS(v)                                                     \
  Kernels{form_humor_inertia_##v##_moment, form_humor_inertia_##v##_load,        \
          form_humor_inertia_##v##_tangent}

#define NCT_HUMOR_KERNELS_OF(e, d)                                               \
  return e.degree == 1 ? NCT_HUMOR_KERNELS(p1_full##d) : NCT_HUMOR_KERNELS(p2_full##d);

Kernels kernels(const Element& e)
{
  switch (e.dimension)
  {
  case section::Dimension::three:
    NCT_HUMOR_KERNELS_OF(e, )
  case section::Dimension::axisymmetric:
    NCT_HUMOR_KERNELS_OF(e, _axisymmetric)
  case section::Dimension::plane:
    NCT_HUMOR_KERNELS_OF(e, _plane)
  }
  throw std::invalid_argument("humor_inertia: unknown dimension");
}

} // namespace

HumorInertia::HumorInertia(
    const Element& element, std::shared_ptr<const fem::Function<double>> u,
    const std::map<std::string, std::shared_ptr<const fem::Constant<double>>>& constants,
    const mesh::MeshTags<std::int32_t>& facets, std::size_t cavities,
    std::vector<int> components, double density)
    : _components(std::move(components)), _density(density), _volumes(cavities, 0.0)
{
  if (cavities == 0 || cavities > 2 || _components.empty())
    throw std::invalid_argument("humor_inertia: needs one or two cavities and a component");
  const Kernels k = kernels(element);
  const int gdim = u->function_space()->mesh()->geometry().dim();
  auto all = constants;
  for (const char* name : {"g_1", "g_2"})
  {
    _g.push_back(std::make_shared<fem::Constant<double>>(std::vector<double>(gdim, 0.0)));
    all[name] = _g.back();
  }
  for (const char* name : {"dt", "alpha_m", "beta", "gamma"})
    _time[name] = constants.at(name);
  const std::map<std::string, std::shared_ptr<const fem::Function<double>>> coeffs = {{"u", u}};
  const std::map<fem::IntegralType, const mesh::MeshTags<int>*> subdomains
      = {{fem::IntegralType::exterior_facet, &facets}};
  const auto& V = u->function_space();
  _moment = std::make_shared<fem::Form<double>>(fem::create_form<double>(
      *k.moment, {}, coeffs, all, subdomains, u->function_space()->mesh()));
  _load = std::make_shared<fem::Form<double>>(
      fem::create_form<double>(*k.load, {V}, coeffs, all, subdomains));
  _tangent = std::make_shared<fem::Form<double>>(
      fem::create_form<double>(*k.tangent, {V, V}, coeffs, all, subdomains));
  _forces.assign(size(), 0.0);
  _m_old.assign(size(), 0.0);
  _m_rate.assign(size(), 0.0);
  _m_accel.assign(size(), 0.0);
}

HumorInertia::Step HumorInertia::step() const
{
  Step s{_time.at("dt")->value[0], _time.at("alpha_m")->value[0], _time.at("beta")->value[0],
         _time.at("gamma")->value[0], 0};
  s.c = (1 - s.alpha_m) / (s.beta * s.dt * s.dt);
  return s;
}

std::vector<double> HumorInertia::moments() const
{
  std::vector<double> m(size());
  for (std::size_t j = 0; j < size(); ++j)
  {
    for (std::size_t c = 0; c < _g.size(); ++c)
      std::fill(_g[c]->value.begin(), _g[c]->value.end(), 0.0);
    _g[cavity(j)]->value[component(j)] = 1.0;
    m[j] = fem::assemble_scalar(*_moment);
  }
  MPI_Allreduce(MPI_IN_PLACE, m.data(), static_cast<int>(m.size()), MPI_DOUBLE, MPI_SUM,
                _moment->mesh()->comm());
  weigh_by_forces();
  return m;
}

void HumorInertia::weigh_by_forces() const
{
  for (auto& g : _g)
    std::fill(g->value.begin(), g->value.end(), 0.0);
  for (std::size_t j = 0; j < size(); ++j)
    _g[cavity(j)]->value[component(j)] = _forces[j] / _volumes[cavity(j)];
}

void HumorInertia::start(const std::vector<double>& volumes)
{
  if (volumes.size() != _volumes.size())
    throw std::invalid_argument("humor_inertia: one volume per cavity");
  _volumes = volumes;
  std::fill(_forces.begin(), _forces.end(), 0.0);
  _m_old = moments();
  std::fill(_m_rate.begin(), _m_rate.end(), 0.0);
  std::fill(_m_accel.begin(), _m_accel.end(), 0.0);
}

void HumorInertia::set_forces(std::span<const double> f)
{
  std::copy(f.begin(), f.end(), _forces.begin());
  weigh_by_forces();
}

void HumorInertia::add_residual(std::span<double> b) const
{
  fem::assemble_vector<double>(b, *_load);
}

const fem::Form<double>& HumorInertia::jacobian_form() const { return *_tangent; }

void HumorInertia::constraints(std::span<double> g) const
{
  const Step s = step();
  const auto m = moments();
  // M* of a = c (M - M*), the acceleration at n+1-alpha_m (forms/dynamics.py).
  const double a_old = ((1 - s.alpha_m) * (1 - 2 * s.beta) / (2 * s.beta) - s.alpha_m) / s.c;
  for (std::size_t j = 0; j < size(); ++j)
  {
    const double V = _volumes[cavity(j)];
    const double target = _m_old[j] + s.dt * _m_rate[j] + a_old * _m_accel[j];
    g[j] = (m[j] - target) / V - _forces[j] / (_density * V * s.c);
  }
}

void HumorInertia::border(std::size_t j, la::Vector<double>& b) const
{
  for (auto& g : _g)
    std::fill(g->value.begin(), g->value.end(), 0.0);
  _g[cavity(j)]->value[component(j)] = 1.0 / _volumes[cavity(j)];
  std::fill(b.mutable_array().begin(), b.mutable_array().end(), 0.0);
  fem::assemble_vector<double>(b.mutable_array(), *_load);
  b.scatter_rev(std::plus<double>());
  weigh_by_forces();
}

double HumorInertia::compliance(std::size_t j) const
{
  return -1.0 / (_density * _volumes[cavity(j)] * step().c);
}

double HumorInertia::mean_pressure_shift(std::size_t c) const
{
  const auto m = moments();
  double shift = 0;
  for (std::size_t j = 0; j < size(); ++j)
    if (cavity(j) == c)
      shift -= _forces[j] / _volumes[c] * m[j] / _volumes[c];
  return shift;
}

double HumorInertia::kinetic_energy() const
{
  double e = 0;
  for (std::size_t j = 0; j < size(); ++j)
    e += 0.5 * _density * _m_rate[j] * _m_rate[j] / _volumes[cavity(j)];
  return e;
}

void HumorInertia::advance()
{
  const Step s = step();
  const auto m = moments();
  for (std::size_t j = 0; j < size(); ++j)
  {
    const double a = (m[j] - _m_old[j] - s.dt * _m_rate[j]) / (s.beta * s.dt * s.dt)
                     - (1 - 2 * s.beta) / (2 * s.beta) * _m_accel[j];
    _m_rate[j] += s.dt * ((1 - s.gamma) * _m_accel[j] + s.gamma * a);
    _m_accel[j] = a;
    _m_old[j] = m[j];
  }
}

void HumorInertia::save(io::CheckpointWriter& checkpoint) const
{
  std::vector<double> state = _volumes;
  for (const auto* v : {&_m_old, &_m_rate, &_m_accel})
    state.insert(state.end(), v->begin(), v->end());
  const std::int64_t none[] = {0};
  checkpoint.add("solid/humor_inertia", state, static_cast<int>(state.size()), none,
                 dolfinx::MPI::rank(_moment->mesh()->comm()) == 0 ? 1 : 0);
}

void HumorInertia::restore(const io::CheckpointReader& checkpoint)
{
  const std::size_t n = size();
  std::vector<double> state(_volumes.size() + 3 * n);
  const std::int64_t none[] = {0};
  checkpoint.read("solid/humor_inertia", state, static_cast<int>(state.size()), none);
  auto at = state.begin();
  for (auto* v : {&_volumes, &_m_old, &_m_rate, &_m_accel})
  {
    std::copy(at, at + v->size(), v->begin());
    at += v->size();
  }
  weigh_by_forces();
}

} // namespace nct::solid
