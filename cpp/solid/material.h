// Material laws and their per-cell parameters.
#pragma once

#include <array>
#include <cstdint>
#include <functional>
#include <map>
#include <memory>
#include <string>
#include <vector>

#include <dolfinx/fem/Function.h>
#include <dolfinx/mesh/MeshTags.h>

#include "form_tags.h"
#include "section/section.h"

namespace nct::solid
{

/// Material laws; the values are the cell tags of forms/solid.py (forms/tags.py).
enum class Law : std::int32_t
{
  fluid = 0, ///< a file mesh's fluid part: the air block's, never in the solid's forms
  hgo = forms::tags::hgo,
  neo_hookean = forms::tags::neo_hookean,
  saint_venant_kirchhoff = forms::tags::saint_venant_kirchhoff,
  compressible_neo_hookean = forms::tags::compressible_neo_hookean
};

/// The most Prony terms a part's viscoelasticity may have (forms/viscoelasticity.py).
constexpr std::size_t max_prony_terms = 3;

/// Parameters of one part (a volume group), read from [material.<part>].
struct Material
{
  Law law;
  double c10, k1, k2, kappa, youngs_modulus, poisson_ratio;
  double dispersion; ///< the HGO fibres' kappa_f, in [0, 1/3]
  /// Prony terms of the matrix's viscoelasticity (forms/viscoelasticity.py):
  /// relative moduli beta_k [-] and relaxation times tau_k [ms]; none: elastic.
  std::vector<double> relative_moduli, relaxation_times;
  double density;   ///< [g/mm^3]
  double viscosity; ///< a fluid's [MPa ms]
  std::vector<std::array<double, 3>> fibre_directions; ///< file meshes only
};

/// Fibre directions (two families, zero when absent) of a part at a
/// reference point, in 3D (the optical axis y). A section (x[0], x[1]) is
/// the 3D plane z = 0: plane, the rule is taken there; axisymmetric about
/// x[1], it is taken at each azimuth phi_k = 2 pi (k + 1/2) / n of the
/// point (r cos phi, z, r sin phi), in the local frame (r, z, theta), for
/// forms/hgo.py's average over the azimuth (n = the fibre field's size / 3).
using FibreRule = std::function<std::array<std::array<double, 3>, 2>(
    const std::string& part, const std::array<double, 3>& X)>;

/// The per-cell (DG0) fields that forms/solid.py reads, by UFL name.
using CellFields = std::map<std::string, std::shared_ptr<dolfinx::fem::Function<double>>>;

/// Fill the per-cell fields from the parts' materials. `parts` maps a
/// volume group tag to its part name; every cell must be in a part.
CellFields cell_fields(const dolfinx::mesh::MeshTags<std::int32_t>& cell_groups,
                       const std::map<std::int32_t, std::string>& parts,
                       const std::map<std::string, Material>& materials,
                       const FibreRule& fibres, section::Dimension dimension,
                       const std::shared_ptr<const dolfinx::fem::FunctionSpace>& scalar,
                       const std::shared_ptr<const dolfinx::fem::FunctionSpace>& vector);

} // namespace nct::solid
