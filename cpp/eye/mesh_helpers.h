// What the eye's two meshers share (cpp/eye/mesh.cpp, the quarter eye;
// cpp/eye/section_mesh.cpp, its meridian section): the boundary groups,
// the parts' names and rules, the refinement's check and the writer of
// gmsh elements.
#pragma once

#include "eye/geometry.h"

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
  vitreous_wall,
  humor_lid
};
constexpr int group_count = 9;
constexpr int part_count = 7;
/// The humor's surface (a section's, meshed): its physical tag, apart
/// from the parts' and the air's (cpp/air/domain.h: 8, 11 to 16); with
/// the internal structures the aqueous' (and the vitreous' the next).
constexpr int humor_tag = 20;
/// Physical names of the parts, by Part - 1.
inline const std::array<std::string, part_count> part_names{
    "cornea", "limbus", "sclera", "lens_cortex", "lens_nucleus", "zonule", "vitreous_membrane"};

/// Throws std::invalid_argument naming the first mesh.* key of r that is
/// impossible (mesh.size_lens only with g's internal structures).
void check_refinement(const Geometry& g, const Refinement& r);

/// Inserts `bound` into the increasing `bounds` unless one lies within
/// `tolerance` of it; returns the index of that bound.
std::size_t insert_bound(std::vector<double>& bounds, double bound, double tolerance);

/// The group of the shell's anterior face over `part`.
Group anterior_group(Part part);

/// The group of the shell's inner face: the cavity's wall, or with the
/// internal structures the aqueous wall in front of the zonule ring and the
/// vitreous wall behind it.
Group inner_group(bool internal_structures, bool in_front_of_ring);

/// The part of the diaphragm's cell in layer k of `layers` over the chart
/// annulus `annulus` (0 inside the nucleus' bound, 1 the rest of the lens,
/// 2 the band): nucleus in the middle layers [floor(N/4), N - floor(N/4))
/// of the nucleus' annulus, else cortex in the lens; in the band the
/// vitreous membrane on the posterior-most layer (if N > 1), else zonule.
Part diaphragm_part(int annulus, std::size_t k, std::size_t layers);

// The humor's meshing (both meshers): gmsh fills the closed wall of a
// cavity on the wall's own nodes, graded from their spacing.

/// Meshes the current gmsh model to dimension `dim` with elements of at
/// most `size` (the global option restored after, for the meshing that follows).
void generate_at_most(int dim, double size);
/// The nodes of every element of dimension `dim` on entity `tag` (-1: all)
/// of the current model, concatenated in gmsh's order.
std::vector<std::size_t> element_nodes(int dim, int tag = -1);

/// Adds elements of one gmsh type to an entity of the current model,
/// tagged consecutively from `next` on.
void add_elements(std::size_t& next, int entity, int type, const std::vector<std::size_t>& nodes,
                  std::size_t per_element);

} // namespace nct::eye::detail
