#include "solid/material.h"

#include <cmath>
#include <map>
#include <stdexcept>

namespace nct::solid
{

CellFields cell_fields(const dolfinx::mesh::MeshTags<std::int32_t>& cell_groups,
                       const std::map<std::int32_t, std::string>& parts,
                       const std::map<std::string, Material>& materials,
                       const FibreRule& fibres, section::Dimension dimension,
                       const std::shared_ptr<const dolfinx::fem::FunctionSpace>& scalar,
                       const std::shared_ptr<const dolfinx::fem::FunctionSpace>& vector)
{
  using dolfinx::fem::Function;
  CellFields f;
  for (const char* name : {"c10", "k1", "k2", "dispersion", "kappa", "youngs_modulus",
                           "poisson_ratio", "density", "is_hgo", "is_neo_hookean",
                           "is_saint_venant_kirchhoff", "is_compressible_neo_hookean"})
    f[name] = std::make_shared<Function<double>>(scalar);
  for (std::size_t k = 1; k <= max_prony_terms; ++k)
    for (const char* name : {"modulus_", "relaxation_time_"})
      f[name + std::to_string(k)] = std::make_shared<Function<double>>(scalar);
  for (const char* name : {"fibre_1", "fibre_2"})
    f[name] = std::make_shared<Function<double>>(vector);
  f["fibre_1"]->name = "fibre_1";
  f["fibre_2"]->name = "fibre_2";

  const auto& mesh = *scalar->mesh();
  const int tdim = mesh.topology().dim();
  const std::int32_t num_cells = mesh.topology().index_map(tdim)->size_local()
                                 + mesh.topology().index_map(tdim)->num_ghosts();
  std::vector<std::int32_t> group(num_cells, -1);
  for (std::size_t i = 0; i < cell_groups.indices().size(); ++i)
    group[cell_groups.indices()[i]] = cell_groups.values()[i];

  const auto& xg = mesh.geometry().x();
  const auto& xdofs = mesh.geometry().dofmap();
  const auto& sdofs = *scalar->dofmap();
  const auto& vdofs = *vector->dofmap();
  const int bs = vdofs.bs(); // 3, or 3 per azimuth (axisymmetric)
  for (std::int32_t c = 0; c < num_cells; ++c)
  {
    auto part = parts.find(group[c]);
    if (part == parts.end())
      throw std::runtime_error("a cell belongs to no material part (volume group "
                               + std::to_string(group[c]) + ")");
    const Material& m = materials.at(part->second);
    const std::int32_t d = sdofs.cell_dofs(c)[0];
    // Benign values where a law's parameter is unused keep every kernel finite.
    const bool hgo = m.law == Law::hgo;
    f["c10"]->x()->mutable_array()[d] = m.c10;
    f["k1"]->x()->mutable_array()[d] = hgo ? m.k1 : 0.0;
    f["k2"]->x()->mutable_array()[d] = hgo ? m.k2 : 1.0;
    f["dispersion"]->x()->mutable_array()[d] = hgo ? m.dispersion : 0.0;
    f["kappa"]->x()->mutable_array()[d] = m.kappa;
    f["youngs_modulus"]->x()->mutable_array()[d] = m.youngs_modulus;
    f["poisson_ratio"]->x()->mutable_array()[d] = m.poisson_ratio;
    f["density"]->x()->mutable_array()[d] = m.density;
    f["is_hgo"]->x()->mutable_array()[d] = hgo;
    f["is_neo_hookean"]->x()->mutable_array()[d] = m.law == Law::neo_hookean;
    f["is_saint_venant_kirchhoff"]->x()->mutable_array()[d]
        = m.law == Law::saint_venant_kirchhoff;
    f["is_compressible_neo_hookean"]->x()->mutable_array()[d]
        = m.law == Law::compressible_neo_hookean;
    // Unused Prony terms: beta = 0 (with a benign tau).
    for (std::size_t k = 0; k < max_prony_terms; ++k)
    {
      const bool used = k < m.relative_moduli.size();
      f["modulus_" + std::to_string(k + 1)]->x()->mutable_array()[d]
          = used ? m.relative_moduli[k] : 0.0;
      f["relaxation_time_" + std::to_string(k + 1)]->x()->mutable_array()[d]
          = used ? m.relaxation_times[k] : 1.0;
    }

    std::array<double, 3> X{0, 0, 0};
    auto nodes = xdofs.links(c);
    for (auto n : nodes)
      for (int j = 0; j < 3; ++j)
        X[j] += xg[3 * n + j] / nodes.size();
    if (!hgo)
      continue; // no fibres: zero
    const std::int32_t dv = vdofs.cell_dofs(c)[0];
    auto set = [&](int k, const std::array<std::array<double, 3>, 2>& a)
    {
      for (int j = 0; j < 3; ++j)
      {
        f["fibre_1"]->x()->mutable_array()[bs * dv + 3 * k + j] = a[0][j];
        f["fibre_2"]->x()->mutable_array()[bs * dv + 3 * k + j] = a[1][j];
      }
    };
    if (dimension != section::Dimension::axisymmetric)
    {
      set(0, fibres(part->second, X));
      continue;
    }
    for (int k = 0; k < bs / 3; ++k)
    {
      // The rule at azimuth phi, in (e_r, e_z, e_theta) there.
      const double phi = 2 * M_PI * (k + 0.5) / (bs / 3), c = std::cos(phi), s = std::sin(phi);
      auto a = fibres(part->second, {X[0] * c, X[1], X[0] * s});
      for (auto& d : a)
        d = {d[0] * c + d[2] * s, d[1], -d[0] * s + d[2] * c};
      set(k, a);
    }
  }
  for (auto& [name, fn] : f)
    fn->x()->scatter_fwd();
  return f;
}

} // namespace nct::solid
