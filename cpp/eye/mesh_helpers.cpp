// What the eye's two meshers share: the writer of gmsh elements.
#include "eye/mesh_helpers.h"

#include <gmsh.h>

namespace nct::eye::detail
{

void add_elements(std::size_t& next, int entity, int type, const std::vector<std::size_t>& nodes,
                  std::size_t per_element)
{
  std::vector<std::size_t> tags(nodes.size() / per_element);
  for (auto& tag : tags)
    tag = next++;
  gmsh::model::mesh::addElementsByType(entity, type, tags, nodes);
}

} // namespace nct::eye::detail
