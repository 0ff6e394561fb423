// What the eye's two meshers share (cpp/eye/mesh.cpp, the quarter eye;
// cpp/eye/section_mesh.cpp, its meridian section): the boundary groups,
// the parts' names and the writer of gmsh elements.
#pragma once

#include <array>
#include <cstddef>
#include <string>
#include <vector>

namespace nct::eye::detail
{

/// Boundary groups; the values are the physical tags. cavity_wall without,
/// aqueous_wall and vitreous_wall with internal structures.
enum class Group
{
  anterior_cornea = 1,
  anterior_sclera,
  cavity_wall,
  symmetry_x,
  symmetry_z,
  fixed,
  aqueous_wall,
  vitreous_wall
};
constexpr int group_count = 8;
constexpr int part_count = 7;
/// Physical names of the parts, by Part - 1.
inline const std::array<std::string, part_count> part_names{
    "cornea", "limbus", "sclera", "lens_cortex", "lens_nucleus", "zonule", "vitreous_membrane"};

/// Adds elements of one gmsh type to an entity of the current model,
/// tagged consecutively from `next` on.
void add_elements(std::size_t& next, int entity, int type, const std::vector<std::size_t>& nodes,
                  std::size_t per_element);

} // namespace nct::eye::detail
