// What the eye's two meshers share: the refinement's check, the parts'
// and groups' rules and the writer of gmsh elements.
#include "eye/mesh_helpers.h"
#include "eye/shape.h"
#include "meshio/gmsh_options.h"

#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <utility>

namespace nct::eye::detail
{

void check_refinement(const Geometry& g, const Refinement& r)
{
  if (r.layers < 1)
    reject("mesh.layers", r.layers, "must be >= 1");
  for (auto [key, h] : {std::pair{"mesh.size_cornea", r.size_cornea},
                        {"mesh.size_limbus", r.size_limbus}, {"mesh.size_sclera", r.size_sclera}})
    if (!(h > 0))
      reject(key, h, "must be > 0");
  if (g.internal_structures && !(r.size_lens > 0))
    reject("mesh.size_lens", r.size_lens, "must be > 0");
}

std::size_t insert_bound(std::vector<double>& bounds, double bound, double tolerance)
{
  auto it = std::find_if(bounds.begin(), bounds.end(),
                         [&](double b) { return std::abs(b - bound) < tolerance; });
  if (it == bounds.end())
    it = bounds.insert(std::upper_bound(bounds.begin(), bounds.end(), bound), bound);
  return static_cast<std::size_t>(it - bounds.begin());
}

Group anterior_group(Part part)
{
  return part == Part::cornea ? Group::anterior_cornea : Group::anterior_sclera;
}

Group inner_group(bool internal_structures, bool in_front_of_ring)
{
  if (!internal_structures)
    return Group::cavity_wall;
  return in_front_of_ring ? Group::aqueous_wall : Group::vitreous_wall;
}

Part diaphragm_part(int annulus, std::size_t k, std::size_t layers)
{
  if (annulus == 2)
    return layers > 1 && k + 1 == layers ? Part::vitreous_membrane : Part::zonule;
  const std::size_t quarter = layers / 4;
  if (annulus == 0 && k >= quarter && k < layers - quarter)
    return Part::lens_nucleus;
  return Part::lens_cortex;
}

void add_elements(std::size_t& next, int entity, int type, const std::vector<std::size_t>& nodes,
                  std::size_t per_element)
{
  std::vector<std::size_t> tags(nodes.size() / per_element);
  for (auto& tag : tags)
    tag = next++;
  gmsh::model::mesh::addElementsByType(entity, type, tags, nodes);
}

void generate_at_most(int dim, double size)
{
  meshio::OptionGuard sizes;
  sizes.set("Mesh.MeshSizeMax", size);
  gmsh::model::mesh::generate(dim);
}

std::vector<std::size_t> element_nodes(int dim, int tag)
{
  std::vector<int> types;
  std::vector<std::vector<std::size_t>> elements, nodes;
  gmsh::model::mesh::getElements(types, elements, nodes, dim, tag);
  std::vector<std::size_t> all;
  for (const auto& n : nodes)
    all.insert(all.end(), n.begin(), n.end());
  return all;
}

} // namespace nct::eye::detail
