#include "solid/viscoelasticity.h"

#include <algorithm>
#include <numeric>

#include <dolfinx/fem/assembler.h>
#include <dolfinx/fem/utils.h>

#include "io/checkpoint.h"
#include "solid/material.h"
#include "solid/problem.h"

#include "viscoelasticity_p1_full.h"
#include "viscoelasticity_p1_full_axisymmetric.h"
#include "viscoelasticity_p1_full_plane.h"
#include "viscoelasticity_p1_reduced.h"
#include "viscoelasticity_p1_reduced_axisymmetric.h"
#include "viscoelasticity_p1_reduced_plane.h"
#include "viscoelasticity_p2_full.h"
#include "viscoelasticity_p2_full_axisymmetric.h"
#include "viscoelasticity_p2_full_plane.h"
#include "viscoelasticity_p2_reduced.h"
#include "viscoelasticity_p2_reduced_axisymmetric.h"
#include "viscoelasticity_p2_reduced_plane.h"

namespace nct::solid
{
namespace
{
using namespace dolfinx;

/// The compiled kernels of forms/viscoelasticity.py for one element.
struct Kernels
{
  ufcx_form* R;
  ufcx_form* J;
  ufcx_form* work;
  ufcx_expression* stress_new;
  ufcx_expression* overstress_new; ///< every term's, one after the other
  ufcx_function_space* (*space)(const char*);
};

#define NCT_VISCO_KERNELS(v)                                                     \
  Kernels{form_viscoelasticity_##v##_R,                                          \
          form_viscoelasticity_##v##_J,                                          \
          form_viscoelasticity_##v##_work,                                       \
          expression_viscoelasticity_##v##_stress_new,                           \
          expression_viscoelasticity_##v##_overstress_new,                       \
          functionspace_form_viscoelasticity_##v##_R}

#define NCT_VISCO_KERNELS_OF(e, d)                                               \
  if (e.degree == 1)                                                             \
    return e.reduced_quadrature ? NCT_VISCO_KERNELS(p1_reduced##d)              \
                                : NCT_VISCO_KERNELS(p1_full##d);                \
  return e.reduced_quadrature ? NCT_VISCO_KERNELS(p2_reduced##d)                \
                              : NCT_VISCO_KERNELS(p2_full##d);

Kernels kernels(const Element& e)
{
  switch (e.dimension)
  {
  case section::Dimension::three:
    NCT_VISCO_KERNELS_OF(e, )
  case section::Dimension::axisymmetric:
    NCT_VISCO_KERNELS_OF(e, _axisymmetric)
  case section::Dimension::plane:
    NCT_VISCO_KERNELS_OF(e, _plane)
  }
  throw std::invalid_argument("viscoelasticity: unknown dimension");
}

constexpr int voigt = 6; // entries of a stored symmetric tensor

/// A key per cell that does not depend on the partition: a hash of its
/// nodes' input indices, sorted (the cell's own node order, which fixes
/// where its quadrature points lie, is the input's on every partition).
std::vector<std::int64_t> cell_keys(const mesh::Mesh& mesh, std::int32_t cells)
{
  const auto& xdofs = mesh.geometry().dofmap();
  const auto& input = mesh.geometry().input_global_indices();
  std::vector<std::int64_t> keys(cells);
  for (std::int32_t c = 0; c < cells; ++c)
  {
    std::vector<std::int64_t> nodes;
    for (auto n : xdofs.links(c))
      nodes.push_back(input[n]);
    std::sort(nodes.begin(), nodes.end());
    keys[c] = static_cast<std::int64_t>(
        io::fnv1a(nodes.data(), nodes.size() * sizeof(std::int64_t)) >> 1);
  }
  return keys;
}

} // namespace

Viscoelasticity::Viscoelasticity(
    const Element& element,
    const std::map<std::string, std::shared_ptr<const fem::Function<double>>>& coefficients,
    const std::map<std::string, std::shared_ptr<const fem::Constant<double>>>& constants,
    const mesh::MeshTags<std::int32_t>& cells)
{
  const Kernels k = kernels(element);
  auto mesh = std::const_pointer_cast<mesh::Mesh>(coefficients.at("u")->function_space()->mesh());
  auto Q = std::make_shared<fem::FunctionSpace>(
      fem::create_functionspace(k.space, "stress_old", mesh));
  auto coeffs = coefficients;
  _stress_old = std::make_shared<fem::Function<double>>(Q);
  coeffs["stress_old"] = _stress_old;
  for (std::size_t t = 0; t < max_prony_terms; ++t)
  {
    _overstress_old.push_back(std::make_shared<fem::Function<double>>(Q));
    coeffs["overstress_old_" + std::to_string(t + 1)] = _overstress_old.back();
  }
  auto pick = [&](const ufcx_form& object)
  {
    std::map<std::string, std::shared_ptr<const fem::Function<double>>> c;
    for (const auto& name : fem::get_coefficient_names(object))
      c[name] = coeffs.at(name);
    return c;
  };
  const auto& V = coefficients.at("u")->function_space();
  const std::map<fem::IntegralType, const mesh::MeshTags<int>*> subdomains
      = {{fem::IntegralType::cell, &cells}};
  _R = std::make_shared<fem::Form<double>>(
      fem::create_form<double>(*k.R, {V}, pick(*k.R), constants, subdomains));
  _J = std::make_shared<fem::Form<double>>(
      fem::create_form<double>(*k.J, {V, V}, pick(*k.J), constants, subdomains));
  _work_form = std::make_shared<fem::Form<double>>(
      fem::create_form<double>(*k.work, {}, pick(*k.work), constants, subdomains, mesh));
  auto expression = [&](ufcx_expression* e)
  {
    return std::make_shared<fem::Expression<double>>(
        fem::create_expression<double>(*e, coeffs, constants, mesh));
  };
  const std::int32_t owned = mesh->topology().index_map(mesh->topology().dim())->size_local();
  _cells.resize(owned);
  std::iota(_cells.begin(), _cells.end(), 0);
  _stress_new = expression(k.stress_new);
  _overstress_new = expression(k.overstress_new);
}

void Viscoelasticity::evaluate(
    const fem::Expression<double>& e,
    const std::vector<std::shared_ptr<fem::Function<double>>>& fields) const
{
  const auto& space = *fields.front()->function_space();
  const auto n = static_cast<std::int32_t>(_cells.size());
  const std::size_t points = e.X().second[0], size = e.value_size();
  struct Table
  {
    double& operator()(std::size_t i, std::size_t j) { return data[i * cols + j]; }
    std::vector<double> data;
    std::size_t cols;
  } values{std::vector<double>(n * points * size), points * size};
  e.eval(std::span<const std::int32_t>(_cells), values);
  // A blocked quadrature space: point p of cell c holds dof cell_dofs(c)[p];
  // field f takes entries 6f to 6f+5 of the expression's value.
  const auto& dofmap = *space.dofmap();
  for (std::size_t f = 0; f < fields.size(); ++f)
  {
    auto x = fields[f]->x()->mutable_array();
    for (std::int32_t c = 0; c < n; ++c)
    {
      auto dofs = dofmap.cell_dofs(c);
      for (std::size_t p = 0; p < points; ++p)
        for (int i = 0; i < voigt; ++i)
          x[dofs[p] * voigt + i] = values(c, p * size + f * voigt + i);
    }
    fields[f]->x()->scatter_fwd();
  }
}

void Viscoelasticity::start()
{
  evaluate(*_stress_new, {_stress_old});
  for (auto& q : _overstress_old)
    q->x()->set(0.0);
  _work = 0;
}

void Viscoelasticity::add_residual(std::span<double> b) const
{
  fem::assemble_vector<double>(b, *_R);
}

void Viscoelasticity::advance()
{
  double w = fem::assemble_scalar(*_work_form);
  MPI_Allreduce(MPI_IN_PLACE, &w, 1, MPI_DOUBLE, MPI_SUM,
                _stress_old->function_space()->mesh()->comm());
  _work += w;
  // Each Q_k,n+1 reads S_iso,n: update the terms first.
  evaluate(*_overstress_new, _overstress_old);
  evaluate(*_stress_new, {_stress_old});
}

std::vector<double> Viscoelasticity::cell_blocks(const fem::Function<double>& f) const
{
  const auto& mesh = *f.function_space()->mesh();
  const std::int32_t n = mesh.topology().index_map(mesh.topology().dim())->size_local();
  const auto& dofmap = *f.function_space()->dofmap();
  const std::size_t points = dofmap.cell_dofs(0).size();
  auto x = f.x()->array();
  std::vector<double> blocks(n * points * voigt);
  for (std::int32_t c = 0; c < n; ++c)
  {
    auto dofs = dofmap.cell_dofs(c);
    for (std::size_t p = 0; p < points; ++p)
      for (int i = 0; i < voigt; ++i)
        blocks[(c * points + p) * voigt + i] = x[dofs[p] * voigt + i];
  }
  return blocks;
}

void Viscoelasticity::save(io::CheckpointWriter& checkpoint) const
{
  const auto& mesh = *_stress_old->function_space()->mesh();
  const std::int32_t n = mesh.topology().index_map(mesh.topology().dim())->size_local();
  const auto keys = cell_keys(mesh, n);
  const int bs = static_cast<int>(_stress_old->function_space()->dofmap()->cell_dofs(0).size())
                 * voigt;
  checkpoint.add("solid/viscoelasticity/stress_old", cell_blocks(*_stress_old), bs, keys, n);
  for (std::size_t t = 0; t < _overstress_old.size(); ++t)
    checkpoint.add("solid/viscoelasticity/overstress_old_" + std::to_string(t + 1),
                   cell_blocks(*_overstress_old[t]), bs, keys, n);
  const double work[] = {_work};
  const std::int64_t none[] = {0};
  checkpoint.add("solid/viscoelasticity/work", work, 1, none,
                 dolfinx::MPI::rank(mesh.comm()) == 0 ? 1 : 0);
}

void Viscoelasticity::restore(const io::CheckpointReader& checkpoint)
{
  const auto& mesh = *_stress_old->function_space()->mesh();
  const std::int32_t n = mesh.topology().index_map(mesh.topology().dim())->size_local();
  const auto keys = cell_keys(mesh, n);
  const auto& dofmap = *_stress_old->function_space()->dofmap();
  const std::size_t points = dofmap.cell_dofs(0).size();
  std::vector<double> blocks(n * points * voigt);
  auto read = [&](const std::string& name, fem::Function<double>& f)
  {
    checkpoint.read(name, blocks, static_cast<int>(points * voigt), keys);
    auto x = f.x()->mutable_array();
    for (std::int32_t c = 0; c < n; ++c)
    {
      auto dofs = dofmap.cell_dofs(c);
      for (std::size_t p = 0; p < points; ++p)
        for (int i = 0; i < voigt; ++i)
          x[dofs[p] * voigt + i] = blocks[(c * points + p) * voigt + i];
    }
    f.x()->scatter_fwd();
  };
  read("solid/viscoelasticity/stress_old", *_stress_old);
  for (std::size_t t = 0; t < _overstress_old.size(); ++t)
    read("solid/viscoelasticity/overstress_old_" + std::to_string(t + 1), *_overstress_old[t]);
  double work[] = {0};
  const std::int64_t none[] = {0};
  checkpoint.read("solid/viscoelasticity/work", work, 1, none);
  _work = work[0];
}

} // namespace nct::solid
