// The idealised eye's meridian section: the 3D eye's layered shell (and
// diaphragm) swept on a 1D chart into rows of triangles.
#include "eye/geometry.h"
#include "eye/mesh_helpers.h"
#include "eye/shape.h"

#include <gmsh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <functional>
#include <map>
#include <set>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

namespace nct::eye
{

using namespace detail;

namespace
{

/// The nodes of a 1D chart on [0, bounds.back()]: uniform within each
/// piece between consecutive bounds, at the piece's size `size(a, b)`.
std::vector<double> chart_nodes(const std::vector<double>& bounds,
                                const std::function<double(double, double)>& size)
{
  std::vector<double> chart{bounds.front()};
  for (std::size_t i = 0; i + 1 < bounds.size(); ++i) {
    const double a = bounds[i], b = bounds[i + 1];
    const auto n = static_cast<std::size_t>(std::max(1.0, std::ceil((b - a) / size(a, b) - 1e-9)));
    for (std::size_t j = 1; j <= n; ++j)
      chart.push_back(j == n ? b : a + (b - a) * double(j) / double(n));
  }
  return chart;
}

/// The section being assembled: its nodes (gmsh tags and r, y, 0), the
/// triangles by part, counter-clockwise in (r, y), and the boundary
/// segments by group, in the solid's counter-clockwise sense.
struct SectionMesh
{
  std::vector<std::size_t> tags;
  std::vector<double> coords;
  std::array<std::vector<std::size_t>, part_count> triangles;
  /// The humor's triangles, per chamber (meshed humor).
  std::vector<std::vector<std::size_t>> humor;
  std::array<std::vector<std::size_t>, group_count> segments;

  /// Adds the node `tag` at x, exactly on the axis (r = 0) if `on_axis`.
  void add_node(std::size_t tag, Meridian x, bool on_axis)
  {
    coords.insert(coords.end(), {on_axis ? 0.0 : x.r, x.y, 0.0});
    tags.push_back(tag);
  }

  void add_segment(Group g, std::size_t a, std::size_t b)
  {
    auto& list = segments[static_cast<int>(g) - 1];
    list.insert(list.end(), {a, b});
  }

  /// Adds the quadrilateral (a, b, c, d) of a sweep, a, b on layer k and
  /// d, c on k + 1, as two triangles (one where it collapses, b = c).
  void add_cell(Part part, std::size_t a, std::size_t b, std::size_t c, std::size_t d)
  {
    auto& cells = triangles[static_cast<int>(part) - 1];
    cells.insert(cells.end(), {a, d, b});
    if (b != c)
      cells.insert(cells.end(), {b, d, c});
  }
};

/// The shell's chart: nodes in s, uniform within each piece between the
/// part bounds, the junction and the zonule ring, at the piece's part's size.
std::vector<double> shell_chart(const Shape& shape, const Refinement& ref)
{
  std::vector<double> bounds{0, shape.limbus_begin, shape.anterior.junction_s(),
                             shape.limbus_end, shape.anterior.length()};
  if (shape.diaphragm.on)
    insert_bound(bounds, shape.diaphragm.ring_s, 1e-9 * shape.anterior.length());
  const auto size_of = [&](Part p) {
    return p == Part::cornea ? ref.size_cornea : p == Part::limbus ? ref.size_limbus
                                                                   : ref.size_sclera;
  };
  return chart_nodes(
      bounds, [&](double a, double b) { return size_of(shape.part_at((a + b) / 2)); });
}

/// The index of the chart node nearest to s.
std::size_t nearest_node(const std::vector<double>& chart, double s)
{
  return static_cast<std::size_t>(
      std::min_element(chart.begin(), chart.end(),
                       [&](double a, double b) { return std::abs(a - s) < std::abs(b - s); })
      - chart.begin());
}

/// Adds the shell's nodes, tag k nc + j + 1 for chart node j of nc on
/// layer k (k = 0 anterior), its triangles and boundary segments; its
/// inner face is split at the chart node `ring` (the zonule ring) with the
/// internal structures. s runs outwards along the profile (clockwise in
/// (r, y)), the layers inwards.
void add_shell(SectionMesh& section, const Shape& shape, const std::vector<double>& chart,
               std::size_t layers, std::size_t ring)
{
  const std::size_t nc = chart.size(), nl = layers;
  for (std::size_t k = 0; k <= nl; ++k)
    for (std::size_t j = 0; j < nc; ++j) {
      const Meridian a = shape.anterior.at(chart[j]);
      const Meridian p = shape.posterior.at(shape.posterior_s(chart[j]));
      // The axis exactly: r = 0 at the apex on every layer.
      section.add_node(k * nc + j + 1, between(a, p, double(k) / double(nl)), j == 0);
    }
  const auto node = [nc](std::size_t k, std::size_t j) { return k * nc + j + 1; };
  for (std::size_t j = 0; j + 1 < nc; ++j) {
    const Part part = shape.part_at((chart[j] + chart[j + 1]) / 2);
    for (std::size_t k = 0; k < nl; ++k)
      section.add_cell(part, node(k, j), node(k, j + 1), node(k + 1, j + 1), node(k + 1, j));
    section.add_segment(anterior_group(part), node(0, j + 1), node(0, j));
    section.add_segment(inner_group(shape.diaphragm.on, j < ring), node(nl, j), node(nl, j + 1));
  }
  for (std::size_t k = 0; k < nl; ++k) {
    section.add_segment(Group::symmetry_x, node(k, 0), node(k + 1, 0));
    section.add_segment(Group::fixed, node(k + 1, nc - 1), node(k, nc - 1));
  }
}

/// Adds the diaphragm's nodes after the shell's, its triangles and
/// boundary segments. Its chart in rho: the nucleus' bound, the lens
/// equator, the ring; size_lens in the lens, along the band the mean of it
/// and the shell's spacing at the ring. Its last node is the ring: the
/// shell's posterior node at its chart node `ring`, on every layer.
void add_diaphragm(SectionMesh& section, const Diaphragm& dia, const Refinement& ref,
                   const std::vector<double>& shell, std::size_t layers, std::size_t ring)
{
  const std::size_t nc = shell.size(), nl = layers;
  const double ring_h = std::max(shell[ring] - shell[ring - 1],
                                 ring + 1 < nc ? shell[ring + 1] - shell[ring] : 0.0);
  const std::vector<double> rho
      = chart_nodes({0, dia.rho_nucleus, dia.lens_radius, dia.rho_ring}, [&](double a, double) {
          return a < dia.lens_radius ? ref.size_lens : (ref.size_lens + ring_h) / 2;
        });
  const std::size_t nd = rho.size(), base = (nl + 1) * nc;
  const auto node = [&](std::size_t k, std::size_t v) {
    return v + 1 == nd ? nl * nc + ring + 1 : base + k * (nd - 1) + v + 1;
  };
  for (std::size_t k = 0; k <= nl; ++k)
    for (std::size_t v = 0; v + 1 < nd; ++v)
      section.add_node(node(k, v),
                       between(dia.anterior(rho[v]), dia.posterior(rho[v]), double(k) / double(nl)),
                       v == 0);
  for (std::size_t v = 0; v + 1 < nd; ++v) {
    const double mid = (rho[v] + rho[v + 1]) / 2;
    const int annulus = mid < dia.rho_nucleus ? 0 : mid < dia.lens_radius ? 1 : 2;
    for (std::size_t k = 0; k < nl; ++k)
      section.add_cell(diaphragm_part(annulus, k, nl), node(k, v), node(k, v + 1),
                       node(k + 1, v + 1), node(k + 1, v));
    section.add_segment(Group::aqueous_wall, node(0, v + 1), node(0, v));
    section.add_segment(Group::vitreous_wall, node(nl, v), node(nl, v + 1));
  }
  for (std::size_t k = 0; k < nl; ++k)
    section.add_segment(Group::symmetry_x, node(k, 0), node(k + 1, 0));
}

/// A humor chamber's boundary: its wall's nodes (indices into the
/// section's nodes) in order, from the axis round to the axis, or to the
/// cut (`lid`: then the lid from the last one to the axis).
struct Chamber
{
  std::vector<std::size_t> wall;
  bool lid;
  Group wall_group; ///< its cavity's wall
};

/// Adds each chamber's humor: triangles graded from the wall's spacing to
/// `size` by gmsh (a model of its own, removed after), on the wall's own
/// nodes; its axis into "axis", its cut into "humor_lid". A wall node that
/// an earlier chamber holds too (the zonule ring, where the aqueous and
/// the vitreous meet) is a node of its own in each: the chambers' humors
/// are apart (the wall's segments at such a node are added again, on the
/// humor's own node, to the chamber's wall group).
void add_humor(SectionMesh& section, const std::vector<Chamber>& chambers, double size)
{
  const auto at = [&](std::size_t i)
  { return std::array<double, 3>{section.coords[3 * i], section.coords[3 * i + 1], 0.0}; };
  std::size_t next = *std::max_element(section.tags.begin(), section.tags.end()) + 1;
  std::set<std::size_t> taken; // wall nodes of the chambers so far
  for (const Chamber& chamber : chambers)
  {
    const auto& wall = chamber.wall;
    const std::size_t n = wall.size();
    gmsh::model::add("humor");
    std::vector<int> points;
    for (std::size_t j = 0; j < n; ++j)
    {
      const auto x = at(wall[j]);
      auto gap = [&](std::size_t i) { return std::hypot(x[0] - at(i)[0], x[1] - at(i)[1]); };
      points.push_back(gmsh::model::geo::addPoint(
          x[0], x[1], 0, std::max(j > 0 ? gap(wall[j - 1]) : 0, j + 1 < n ? gap(wall[j + 1]) : 0)));
    }
    std::vector<int> loop, wall_lines;
    for (std::size_t j = 0; j + 1 < n; ++j)
    {
      wall_lines.push_back(gmsh::model::geo::addLine(points[j], points[j + 1]));
      loop.push_back(wall_lines.back());
    }
    int lid = -1, axis;
    if (chamber.lid)
    {
      const int centre = gmsh::model::geo::addPoint(0, at(wall.back())[1], 0, size);
      lid = gmsh::model::geo::addLine(points.back(), centre);
      axis = gmsh::model::geo::addLine(centre, points.front());
      loop.insert(loop.end(), {lid, axis});
    }
    else
    {
      axis = gmsh::model::geo::addLine(points.back(), points.front());
      loop.push_back(axis);
    }
    gmsh::model::geo::addPlaneSurface({gmsh::model::geo::addCurveLoop(loop)});
    for (int l : wall_lines)
      gmsh::model::geo::mesh::setTransfiniteCurve(l, 2); // the wall's own nodes only
    gmsh::model::geo::synchronize();
    generate_at_most(2, size);

    // Its nodes into the section's: the wall's by place (unless an earlier
    // chamber's), the rest new.
    std::map<std::array<double, 2>, std::size_t> wall_tag;
    for (auto i : wall)
      wall_tag[{at(i)[0], at(i)[1]}] = section.tags[i];
    std::vector<std::size_t> node_tags;
    std::vector<double> coords, parametric;
    gmsh::model::mesh::getNodes(node_tags, coords, parametric);
    std::map<std::size_t, std::size_t> tag_of, own; // gmsh's -> the section's; wall: section's -> the humor's
    for (std::size_t i = 0; i < node_tags.size(); ++i)
    {
      const auto it = wall_tag.find({coords[3 * i], coords[3 * i + 1]});
      if (it != wall_tag.end() && !taken.count(it->second))
        tag_of[node_tags[i]] = it->second;
      else
      {
        const bool on_axis = std::abs(coords[3 * i]) < 1e-12;
        section.add_node(next, {on_axis ? 0.0 : coords[3 * i], coords[3 * i + 1]}, on_axis);
        tag_of[node_tags[i]] = next++;
      }
      if (it != wall_tag.end())
        own[it->second] = tag_of[node_tags[i]];
    }
    for (std::size_t j = 0; j + 1 < n; ++j)
    {
      const std::size_t a = section.tags[wall[j]], b = section.tags[wall[j + 1]];
      if (own.at(a) != a || own.at(b) != b)
        section.add_segment(chamber.wall_group, own.at(a), own.at(b));
    }
    for (auto i : wall)
      taken.insert(section.tags[i]);
    section.humor.emplace_back();
    for (auto node : element_nodes(2))
      section.humor.back().push_back(tag_of.at(node));
    std::vector<std::pair<int, Group>> lines{{axis, Group::symmetry_x}};
    if (chamber.lid)
      lines.push_back({lid, Group::humor_lid});
    for (auto [line, group] : lines)
    {
      const auto segments = element_nodes(1, line);
      for (std::size_t e = 0; e + 1 < segments.size(); e += 2)
        section.add_segment(group, tag_of.at(segments[e]), tag_of.at(segments[e + 1]));
    }
    gmsh::model::remove();
  }
}

/// Writes the eye's section into a new gmsh model "eye": the nodes, the
/// triangles by part (3 parts, or all with the internal structures) and
/// the boundary segments by group.
void write_section(const SectionMesh& section, bool internal_structures)
{
  gmsh::model::add("eye");
  gmsh::model::addDiscreteEntity(2, 1);
  gmsh::model::mesh::addNodes(2, 1, section.tags, section.coords);
  std::size_t next = 1;
  for (int p = 1; p <= (internal_structures ? part_count : 3); ++p) {
    if (p > 1)
      gmsh::model::addDiscreteEntity(2, p);
    add_elements(next, p, 2, section.triangles[p - 1], 3);
    gmsh::model::addPhysicalGroup(2, {p}, p);
    gmsh::model::setPhysicalName(2, p, part_names[p - 1]);
  }
  const std::vector<const char*> humors
      = section.humor.size() == 1 ? std::vector{"humor"}
                                  : std::vector{"aqueous_humor", "vitreous_humor"};
  for (std::size_t c = 0; c < section.humor.size(); ++c)
  {
    const int tag = humor_tag + static_cast<int>(c);
    gmsh::model::addDiscreteEntity(2, tag);
    add_elements(next, tag, 2, section.humor[c], 3);
    gmsh::model::addPhysicalGroup(2, {tag}, tag);
    gmsh::model::setPhysicalName(2, tag, humors[c]);
  }
  std::vector<std::pair<Group, const char*>> groups{
      {Group::anterior_cornea, "anterior_cornea"}, {Group::anterior_sclera, "anterior_sclera"},
      {Group::symmetry_x, "axis"}, {Group::fixed, "fixed"}};
  if (internal_structures)
    groups.insert(groups.end(), {{Group::aqueous_wall, "aqueous_wall"},
                                 {Group::vitreous_wall, "vitreous_wall"}});
  else
    groups.emplace_back(Group::cavity_wall, "cavity_wall");
  if (!section.humor.empty())
    groups.emplace_back(Group::humor_lid, "humor_lid");
  for (auto [group, name] : groups) {
    const int g = static_cast<int>(group);
    gmsh::model::addDiscreteEntity(1, g);
    add_elements(next, g, 1, section.segments[g - 1], 2);
    gmsh::model::addPhysicalGroup(1, {g}, g);
    gmsh::model::setPhysicalName(1, g, name);
  }
}

/// Meshes the eye's meridian section (r, y) as the current gmsh model
/// "eye" (build_section()): the shell's sweep X(s, t) of the 3D eye on a
/// 1D chart in s, each (s, t) quadrilateral split into two triangles;
/// with the internal structures, the diaphragm's sweep on its chart in
/// rho likewise, its layers meeting the shell's posterior node at the
/// zonule ring (the 3D eye's ring arc, here a point).
void mesh_section(const Shape& shape, const Refinement& ref, bool humor)
{
  const std::size_t layers = static_cast<std::size_t>(ref.layers);
  const Diaphragm& dia = shape.diaphragm;
  const std::vector<double> chart = shell_chart(shape, ref);
  const std::size_t ring = dia.on ? nearest_node(chart, dia.ring_s) : chart.size();
  SectionMesh section;
  add_shell(section, shape, chart, layers, ring);
  if (dia.on)
    add_diaphragm(section, dia, ref, chart, layers, ring);
  if (humor)
  {
    // The shell's inner face: node (layers, j); the diaphragm's faces:
    // their nodes from the axis (index = tag - 1), the ring the shell's.
    const std::size_t nc = chart.size();
    const auto inner = [&](std::size_t j) { return layers * nc + j; };
    std::vector<Chamber> chambers;
    if (!dia.on)
    {
      chambers.push_back({{}, true, Group::cavity_wall});
      for (std::size_t j = 0; j < nc; ++j)
        chambers.back().wall.push_back(inner(j));
    }
    else
    {
      // The aqueous: the inner face to the ring, the diaphragm's anterior
      // face back to the axis; the vitreous: its posterior face out to the
      // ring, the inner face down to the cut.
      const std::size_t nd = (section.tags.size() - (layers + 1) * nc) / (layers + 1) + 1,
                        base = (layers + 1) * nc;
      const auto face = [&](std::size_t k, std::size_t v) { return base + k * (nd - 1) + v; };
      Chamber aqueous{{}, false, Group::aqueous_wall}, vitreous{{}, true, Group::vitreous_wall};
      for (std::size_t j = 0; j <= ring; ++j)
        aqueous.wall.push_back(inner(j));
      for (std::size_t v = nd - 1; v-- > 0;)
        aqueous.wall.push_back(face(0, v));
      for (std::size_t v = 0; v + 1 < nd; ++v)
        vitreous.wall.push_back(face(layers, v));
      for (std::size_t j = ring; j < nc; ++j)
        vitreous.wall.push_back(inner(j));
      chambers = {aqueous, vitreous};
    }
    add_humor(section, chambers, ref.size_humor);
  }
  write_section(section, dia.on);
}

} // namespace

void build_section(const Geometry& g, const Refinement& r, bool humor)
{
  check_refinement(g, r);
  const Shape shape = derive_shape(g);
  try {
    mesh_section(shape, r, humor);
  } catch (const std::string& message) { // gmsh 4.8 throws its last error as a string
    throw std::runtime_error("nct::eye::build_section: gmsh failed: " + message);
  }
}

} // namespace nct::eye
