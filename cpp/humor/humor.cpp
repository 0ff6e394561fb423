#include "humor/humor.h"

#include <stdexcept>

#include "humor/flow.h"
#include "humor/navier_stokes.h"
#include "io/format.h"

namespace nct::humor
{
namespace
{

/// The massless humor (cavity.humor_inertia = "none"): the cavities alone.
class Massless final : public Humor
{
public:
  using Humor::Humor;
  const char* name() const override { return "none"; }
};

/// The humor translating with the eye (forms/humor_inertia.py): its mass
/// is in the solid's forms (solid::HumorInertia), its inertial forces
/// among the closed cavities' unknowns; here its record.
class Translation final : public Humor
{
public:
  using Humor::Humor;
  const char* name() const override { return "translation"; }
  /// The multiplier is the pressure at the volume's origin; the humor's
  /// mean pressure is shifted from it by its inertial force.
  double pressure_shift(std::size_t c) const override
  {
    return _solid.humor_inertia()->mean_pressure_shift(c);
  }
  /// Each cavity's humor's axial inertial force on the eye, whole model.
  void state(const std::vector<std::string>& cavities, biomarkers::Columns& columns) const override
  {
    const auto& h = *_solid.humor_inertia();
    for (std::size_t j = 0; j < h.size(); ++j)
      if (h.component(j) == 1)
        columns.push_back({cavities[h.cavity(j)] + "_humor_inertia_N",
                           -h.forces()[j] * _solid.symmetry_factor()});
  }
  void energies(biomarkers::Columns& columns) const override
  {
    columns.push_back({"humor_kinetic_energy_mJ", kinetic_energy() * _solid.symmetry_factor()});
  }
  double kinetic_energy() const override { return _solid.humor_inertia()->kinetic_energy(); }
};

} // namespace

std::unique_ptr<Humor> make(solid::Problem& solid, const Mesh& mesh, const CavitySettings& cavity,
                            double dt)
{
  using Inertia = CavitySettings::HumorInertia;
  if (cavity.meshed_humor() && !mesh.humor)
    throw std::logic_error("humor::make: a meshed humor without its mesh");
  switch (cavity.humor_inertia)
  {
  case Inertia::translation:
    if (!solid.humor_inertia()) // no cavity to translate in
      break;
    return std::make_unique<Translation>(solid);
  case Inertia::flow:
    return std::make_unique<Flow>(solid, *mesh.humor, mesh.boundaries, cavity.humor_density);
  case Inertia::navier_stokes:
    // Continuity rows scaled by the humor's speed under a puff, 0.2 m/s;
    // the stabilisation bounded by the nominal time step, as the air's.
    return std::make_unique<NavierStokes>(solid, mesh.solid, mesh.walls, *mesh.humor,
                                          mesh.boundaries, cavity.humor_density,
                                          cavity.humor_viscosity, 0.2, dt);
  case Inertia::none:
    break;
  }
  return std::make_unique<Massless>(solid);
}

void describe_mesh(nlohmann::json& summary, io::RunFolder& folder, const dolfinx::mesh::Mesh& mesh,
                   std::int64_t dofs, const char* unknowns, std::size_t wall_nodes,
                   const char* name)
{
  const auto& t = mesh.topology();
  const std::int64_t cells = t.index_map(t.dim())->size_global();
  summary["humor_cells"] = cells;
  summary["humor_dofs"] = dofs;
  folder.log(io::format("humor: %lld cells, %lld %s unknowns, %zu wall nodes "
                        "(cavity.humor_inertia = \"%s\")",
                        (long long)cells, (long long)dofs, unknowns, wall_nodes, name));
}

} // namespace nct::humor
