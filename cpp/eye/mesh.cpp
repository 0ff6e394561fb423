// The layered quarter-eye mesh: a quarter-disc chart meshed in 2D, swept
// through the layers between the anterior and posterior surfaces into
// tetrahedra, for the shell and, with the internal structures, the
// diaphragm.
#include "eye/geometry.h"
#include "eye/mesh_helpers.h"
#include "eye/shape.h"
#include "meshio/gmsh_options.h"

#include <gmsh.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace nct::eye
{

using namespace detail;

namespace
{

using meshio::OptionGuard;

/// How to mesh a quarter-disc chart: circular arcs at `radii` (increasing;
/// annulus i lies between radii[i - 1] and radii[i], annulus 0 is the
/// sector inside radii[0]), the element size as a function of the chart
/// radius, optionally one arc meshed transfinitely with `ring_points`
/// nodes uniform in phi, and whether the outer arc is the fixed face.
struct ChartSpec
{
  std::vector<double> radii;
  std::function<double(double)> size;
  int ring_arc = -1;
  int ring_points = 0;
  bool fixed_outer = false;
};

/// The meshed chart: per node the chart radius s and (cos, sin) of phi;
/// per triangle its sorted node indices, chart orientation and annulus.
struct Chart
{
  std::vector<double> s, cos_phi, sin_phi;
  std::vector<std::array<std::size_t, 3>> triangles;
  std::vector<int> orientation; ///< +1 if the sorted triangle is counter-clockwise
  std::vector<int> annulus;
  std::unordered_map<std::uint64_t, Group> side_edges; ///< boundary edge key -> group
  std::vector<std::size_t> ring; ///< nodes of the transfinite arc, by increasing phi
};

/// Key of the undirected chart edge (a, b).
std::uint64_t edge_key(std::size_t a, std::size_t b)
{
  return (std::uint64_t(std::min(a, b)) << 32) | std::uint64_t(std::max(a, b));
}

/// The gmsh entities of a quarter-disc chart: per annulus its side on the
/// x axis (z = 0 in the eye), on the y axis (x = 0), its outer arc and its
/// surface.
struct ChartEntities
{
  std::vector<int> along_x, along_z, arcs, annuli;
};

/// Draws the annuli of a quarter-disc chart with circular arcs at `radii`
/// in the current model (geo kernel, not synchronised).
ChartEntities draw_chart(const std::vector<double>& radii)
{
  namespace geo = gmsh::model::geo;
  const std::size_t na = radii.size();
  const int origin = geo::addPoint(0, 0, 0);
  ChartEntities drawn{std::vector<int>(na), std::vector<int>(na), std::vector<int>(na),
                      std::vector<int>(na)};
  int last_x = origin, last_z = origin;
  for (std::size_t i = 0; i < na; ++i) {
    const int px = geo::addPoint(radii[i], 0, 0), pz = geo::addPoint(0, radii[i], 0);
    drawn.along_x[i] = geo::addLine(last_x, px);
    drawn.along_z[i] = geo::addLine(last_z, pz);
    drawn.arcs[i] = geo::addCircleArc(px, origin, pz);
    std::vector<int> loop{drawn.along_x[i], drawn.arcs[i], -drawn.along_z[i]};
    if (i > 0)
      loop.push_back(-drawn.arcs[i - 1]);
    drawn.annuli[i] = geo::addPlaneSurface({geo::addCurveLoop(loop)});
    last_x = px;
    last_z = pz;
  }
  return drawn;
}

/// Reads the meshed chart's nodes into `chart` (chart radius, exact on the
/// arcs, and azimuth); returns the node index of each gmsh node tag.
std::unordered_map<std::size_t, std::size_t> read_chart_nodes(Chart& chart, const ChartSpec& spec,
                                                              const ChartEntities& drawn)
{
  std::vector<std::size_t> tags;
  std::vector<double> xyz, uvw;
  gmsh::model::mesh::getNodes(tags, xyz, uvw, -1, -1, false, false);
  std::unordered_map<std::size_t, std::size_t> index;
  const std::size_t n = tags.size();
  chart.s.resize(n);
  chart.cos_phi.resize(n);
  chart.sin_phi.resize(n);
  for (std::size_t i = 0; i < n; ++i) {
    index[tags[i]] = i;
    const double x = xyz[3 * i], y = xyz[3 * i + 1], s = std::hypot(x, y);
    chart.s[i] = s;
    chart.cos_phi[i] = s > 0 ? x / s : 1;
    chart.sin_phi[i] = s > 0 ? y / s : 0;
  }
  // Nodes on the rings get their radius exactly.
  for (std::size_t i = 0; i < spec.radii.size(); ++i) {
    gmsh::model::mesh::getNodes(tags, xyz, uvw, 1, drawn.arcs[i], true, false);
    for (std::size_t t : tags)
      chart.s[index.at(t)] = spec.radii[i];
  }
  return index;
}

/// Lists the nodes of the chart's transfinite arc in `chart.ring` by
/// increasing phi and puts them at phi = j pi / (2 (M - 1)) exactly.
void read_ring_arc(Chart& chart, const ChartSpec& spec, const ChartEntities& drawn,
                   const std::unordered_map<std::size_t, std::size_t>& index)
{
  std::vector<std::size_t> ring_tags;
  std::vector<double> xyz, uvw;
  gmsh::model::mesh::getNodes(ring_tags, xyz, uvw, 1, drawn.arcs[spec.ring_arc], true, false);
  for (std::size_t t : ring_tags)
    chart.ring.push_back(index.at(t));
  std::sort(chart.ring.begin(), chart.ring.end(), [&](std::size_t a, std::size_t b) {
    return std::atan2(chart.sin_phi[a], chart.cos_phi[a])
           < std::atan2(chart.sin_phi[b], chart.cos_phi[b]);
  });
  const std::size_t m = chart.ring.size();
  if (m != static_cast<std::size_t>(spec.ring_points))
    throw std::runtime_error("nct::eye::build: gmsh put " + std::to_string(m)
                             + " nodes on the zonule ring arc instead of "
                             + std::to_string(spec.ring_points));
  for (std::size_t j = 0; j < m; ++j) {
    const double phi = std::numbers::pi / 2 * double(j) / double(m - 1);
    chart.cos_phi[chart.ring[j]] = j + 1 == m ? 0.0 : std::cos(phi);
    chart.sin_phi[chart.ring[j]] = j + 1 == m ? 1.0 : std::sin(phi);
  }
}

/// Reads the meshed chart's triangles, annulus by annulus, into `chart`.
void read_chart_triangles(Chart& chart, const ChartEntities& drawn,
                          const std::unordered_map<std::size_t, std::size_t>& index)
{
  for (std::size_t i = 0; i < drawn.annuli.size(); ++i) {
    std::vector<std::size_t> element_tags, node_tags; // gmsh 4.8 rejects reused non-empty vectors
    gmsh::model::mesh::getElementsByType(2, element_tags, node_tags, drawn.annuli[i]);
    for (std::size_t t = 0; t < element_tags.size(); ++t) {
      std::array<std::size_t, 3> v{index.at(node_tags[3 * t]), index.at(node_tags[3 * t + 1]),
                                   index.at(node_tags[3 * t + 2])};
      std::sort(v.begin(), v.end());
      const auto x = [&](std::size_t k) { return chart.s[k] * chart.cos_phi[k]; };
      const auto y = [&](std::size_t k) { return chart.s[k] * chart.sin_phi[k]; };
      const double area2 = (x(v[1]) - x(v[0])) * (y(v[2]) - y(v[0]))
                           - (y(v[1]) - y(v[0])) * (x(v[2]) - x(v[0]));
      chart.triangles.push_back(v);
      chart.orientation.push_back(area2 > 0 ? 1 : -1);
      chart.annulus.push_back(static_cast<int>(i));
    }
  }
}

/// Reads the chart's boundary edges into `chart.side_edges`: on the x axis
/// symmetry_z, on the y axis symmetry_x, on the outer arc fixed (if asked).
void read_chart_sides(Chart& chart, const ChartSpec& spec, const ChartEntities& drawn,
                      const std::unordered_map<std::size_t, std::size_t>& index)
{
  const auto add_side = [&](int curve, Group group) {
    std::vector<std::size_t> element_tags, node_tags;
    gmsh::model::mesh::getElementsByType(1, element_tags, node_tags, curve);
    for (std::size_t t = 0; t < element_tags.size(); ++t) {
      const std::size_t a = index.at(node_tags[2 * t]), b = index.at(node_tags[2 * t + 1]);
      chart.side_edges[edge_key(a, b)] = group;
    }
  };
  for (std::size_t i = 0; i < drawn.arcs.size(); ++i) {
    add_side(drawn.along_x[i], Group::symmetry_z);
    add_side(drawn.along_z[i], Group::symmetry_x);
  }
  if (spec.fixed_outer)
    add_side(drawn.arcs.back(), Group::fixed);
}

/// Meshes a quarter-disc chart in a temporary gmsh model and reads it back.
Chart mesh_chart(const ChartSpec& spec)
{
  const auto size_at = [&spec](int, int, double x, double y, double) {
    return spec.size(std::hypot(x, y));
  };
  const meshio::TemporaryModel chart_model("eye_chart");
  const ChartEntities drawn = draw_chart(spec.radii);
  if (spec.ring_arc >= 0)
    gmsh::model::geo::mesh::setTransfiniteCurve(drawn.arcs[spec.ring_arc], spec.ring_points);
  gmsh::model::geo::synchronize();

  OptionGuard options;
  options.set("Mesh.MeshSizeFromPoints", 0);
  options.set("Mesh.MeshSizeFromCurvature", 0);
  options.set("Mesh.MeshSizeExtendFromBoundary", 0);
  gmsh::model::mesh::setSizeCallback(size_at);
  gmsh::model::mesh::generate(2);

  Chart chart;
  const auto index = read_chart_nodes(chart, spec, drawn);
  if (spec.ring_arc >= 0)
    read_ring_arc(chart, spec, drawn, index);
  read_chart_triangles(chart, drawn, index);
  read_chart_sides(chart, spec, drawn, index);
  return chart;
}

using Tet = std::array<std::size_t, 4>;

/// Signed volume of the tetrahedron (a, b, c, d).
double signed_volume(const Vec3& a, const Vec3& b, const Vec3& c, const Vec3& d)
{
  const Vec3 u{b[0] - a[0], b[1] - a[1], b[2] - a[2]};
  const Vec3 v{c[0] - a[0], c[1] - a[1], c[2] - a[2]};
  const Vec3 w{d[0] - a[0], d[1] - a[1], d[2] - a[2]};
  return (u[0] * (v[1] * w[2] - v[2] * w[1]) - u[1] * (v[0] * w[2] - v[2] * w[0])
          + u[2] * (v[0] * w[1] - v[1] * w[0])) / 6;
}

/// The mesh being assembled: nodes by tag - 1, tets by part, boundary
/// triangles by group (node tags, flattened).
struct QuarterMesh
{
  std::vector<Vec3> x;
  std::vector<int> owner; ///< lowest part using the node (part_count + 1: none)
  std::array<std::vector<std::size_t>, part_count> tets;
  std::array<std::vector<std::size_t>, group_count> faces;
  std::vector<std::size_t> humor; ///< the humor's tets (meshed humor)
};

/// A layered body: a chart swept through `layers` layers (layer 0 the
/// anterior surface). Chart nodes that are `collapsed` are one node on all
/// layers (a ring where the layers meet).
struct Body
{
  const Chart& chart;
  std::size_t layers;
  /// The node tag of chart node v on layer k.
  std::function<std::size_t(std::size_t k, std::size_t v)> node_tag;
  std::function<bool(std::size_t v)> collapsed;
  /// The part of the cell over a chart triangle in layer k.
  std::function<Part(std::size_t triangle, std::size_t k)> part_of;
  /// The group of the faces over a chart triangle on layer 0 (anterior) or N (posterior).
  std::function<Group(std::size_t triangle, bool posterior)> cap_group;
};

/// Chart node v on layer k of a body.
struct LayerNode
{
  std::size_t k, v;
};

/// The group of a tet's face over the chart triangle i of the body, or
/// none inside it: a cap if the face lies on layer 0 or N (a collapsed node
/// lies on every layer), else the group of the chart's boundary edge that
/// the face spans.
std::optional<Group> face_group(const Body& body, std::size_t i,
                                const std::array<LayerNode, 3>& face)
{
  const auto on_layer = [&](std::size_t layer) {
    return std::all_of(face.begin(), face.end(),
                       [&](const LayerNode& n) { return n.k == layer || body.collapsed(n.v); });
  };
  if (on_layer(0))
    return body.cap_group(i, false);
  if (on_layer(body.layers))
    return body.cap_group(i, true);
  // A side face spans one chart edge: exactly two distinct chart nodes.
  const std::size_t e0 = face[0].v, e1 = face[1].v != e0 ? face[1].v : face[2].v;
  if (e0 == e1 || (face[2].v != e0 && face[2].v != e1))
    return std::nullopt;
  const auto side = body.chart.side_edges.find(edge_key(e0, e1));
  if (side == body.chart.side_edges.end())
    return std::nullopt;
  return side->second;
}

/// Splits the body's prisms into tets and collects its boundary triangles.
///
/// The prism rule's tets (b0,b1,b2,t2), (b0,b1,t1,t2), (b0,t0,t1,t2), the
/// second with t1, t2 swapped so that all three have the orientation of the
/// chart triangle, made positive by swapping the last two nodes of
/// clockwise ones; tets with a repeated node (at a collapsed ring) are
/// dropped, the others tile the collapsed prism and split its quad faces
/// by the same diagonal rule (lower chart index bottom to higher top) as
/// the neighbours. Each tet's faces are listed outwards (face j opposite
/// node j); those on the boundary go to their group. Each node is put on
/// the lowest-numbered part's volume that uses it (owner).
void sweep(QuarterMesh& mesh, const Body& body)
{
  const Chart& chart = body.chart;
  const std::size_t nl = body.layers;
  const auto at = [&](std::size_t tag) -> const Vec3& { return mesh.x[tag - 1]; };
  const std::array<std::array<int, 3>, 4> outward{{{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}}};
  for (std::size_t i = 0; i < chart.triangles.size(); ++i) {
    const auto& v = chart.triangles[i];
    for (std::size_t k = 0; k < nl; ++k) {
      const int part = static_cast<int>(body.part_of(i, k));
      const auto b = [&](int j) { return LayerNode{k, v[j]}; };
      const auto t = [&](int j) { return LayerNode{k + 1, v[j]}; };
      std::array<std::array<LayerNode, 4>, 3> prism{{{b(0), b(1), b(2), t(2)},
                                                      {b(0), b(1), t(2), t(1)},
                                                      {b(0), t(0), t(1), t(2)}}};
      for (auto& corners : prism) {
        if (chart.orientation[i] < 0)
          std::swap(corners[2], corners[3]);
        Tet tet;
        for (int j = 0; j < 4; ++j)
          tet[j] = body.node_tag(corners[j].k, corners[j].v);
        Tet sorted = tet;
        std::sort(sorted.begin(), sorted.end());
        if (std::adjacent_find(sorted.begin(), sorted.end()) != sorted.end())
          continue; // collapsed at the ring
        if (!(signed_volume(at(tet[0]), at(tet[1]), at(tet[2]), at(tet[3])) > 0)) {
          const Vec3& c = at(tet[0]);
          std::ostringstream message;
          message << "nct::eye::build: inverted tetrahedron near (" << c[0] << ", " << c[1]
                  << ", " << c[2] << "); the sweep folds for this geometry and refinement";
          throw std::runtime_error(message.str());
        }
        mesh.tets[part - 1].insert(mesh.tets[part - 1].end(), tet.begin(), tet.end());
        for (std::size_t n : tet)
          mesh.owner[n - 1] = std::min(mesh.owner[n - 1], part);

        for (const auto& f : outward) {
          const auto group = face_group(body, i, {corners[f[0]], corners[f[1]], corners[f[2]]});
          if (!group)
            continue;
          auto& list = mesh.faces[static_cast<int>(*group) - 1];
          for (int j = 0; j < 3; ++j)
            list.push_back(tet[f[j]]);
        }
      }
    }
  }
}

/// Puts the node (r, y) at azimuth (c, s) = (cos phi, sin phi).
Vec3 revolve(Meridian p, double c, double s) { return {p.r * c, p.y, p.r * s}; }

/// The shell's chart: rings at the part bounds, the junction and, with the
/// internal structures, the zonule ring, its arc transfinite. Size: the
/// least over the parts of the part's size plus `gradation` times the
/// distance to the part, so sizes change smoothly (at most 0.3 mm per mm)
/// and never exceed the part's own size inside it.
ChartSpec shell_chart_spec(const Shape& shape, const Refinement& ref)
{
  const Diaphragm& dia = shape.diaphragm;
  const double gradation = 0.3;
  const std::array<double, 3> size{ref.size_cornea, ref.size_limbus, ref.size_sclera};
  const std::array<double, 4> bounds{0, shape.limbus_begin, shape.limbus_end,
                                     shape.anterior.length()};
  ChartSpec spec;
  spec.size = [=](double s) {
    double h = size[0] + gradation * std::max(0.0, s - bounds[1]);
    for (std::size_t p = 1; p < 3; ++p)
      h = std::min(h, size[p] + gradation * std::max({0.0, bounds[p] - s, s - bounds[p + 1]}));
    return h;
  };
  spec.radii = {shape.limbus_begin, shape.anterior.junction_s(), shape.limbus_end,
                shape.anterior.length()};
  spec.fixed_outer = true;
  if (dia.on) {
    // The ring arc, merged with an existing one it (nearly) coincides with.
    spec.ring_arc = static_cast<int>(
        insert_bound(spec.radii, dia.ring_s, 1e-9 * shape.anterior.length()));
    const double chart_arc = std::numbers::pi / 2 * dia.ring_s;
    spec.ring_points
        = 1 + std::max(2, static_cast<int>(std::ceil(chart_arc / spec.size(dia.ring_s))));
  }
  return spec;
}

/// Adds the shell's nodes, tag k nc + v + 1 for chart node v of nc on
/// layer k, and its cells, each annulus of its chart in one part.
void add_shell(QuarterMesh& mesh, const Shape& shape, const ChartSpec& spec, const Chart& shell,
               std::size_t layers)
{
  std::vector<Part> annulus_part;
  for (std::size_t i = 0; i < spec.radii.size(); ++i) {
    const double lo = i > 0 ? spec.radii[i - 1] : 0, mid = (lo + spec.radii[i]) / 2;
    annulus_part.push_back(shape.part_at(mid));
  }
  const std::size_t nc = shell.s.size();
  mesh.x.resize(nc * (layers + 1));
  for (std::size_t v = 0; v < nc; ++v) {
    const Meridian a = shape.anterior.at(shell.s[v]);
    const Meridian p = shape.posterior.at(shape.posterior_s(shell.s[v]));
    for (std::size_t k = 0; k <= layers; ++k) {
      const double t = double(k) / double(layers);
      mesh.x[k * nc + v] = revolve(between(a, p, t), shell.cos_phi[v], shell.sin_phi[v]);
    }
  }
  mesh.owner.assign(mesh.x.size(), part_count + 1);
  const bool internal_structures = shape.diaphragm.on;
  sweep(mesh, Body{shell, layers, [nc](std::size_t k, std::size_t v) { return k * nc + v + 1; },
                   [](std::size_t) { return false; },
                   [&](std::size_t i, std::size_t) { return annulus_part[shell.annulus[i]]; },
                   [&](std::size_t i, bool posterior) {
                     if (!posterior)
                       return anterior_group(annulus_part[shell.annulus[i]]);
                     return inner_group(internal_structures, shell.annulus[i] <= spec.ring_arc);
                   }});
}

/// The diaphragm's chart: rings at the nucleus' bound, the lens equator and
/// the zonule ring, whose arc has the shell ring's `ring_points`; the size
/// grades linearly along the band from size_lens to the ring's node spacing.
ChartSpec diaphragm_chart_spec(const Diaphragm& dia, const Refinement& ref, int ring_points)
{
  const double ring_h = std::numbers::pi / 2 * dia.rho_ring / (ring_points - 1);
  ChartSpec spec;
  spec.radii = {dia.rho_nucleus, dia.lens_radius, dia.rho_ring};
  spec.ring_arc = 2;
  spec.ring_points = ring_points;
  const double lens_h = ref.size_lens, lr = dia.lens_radius;
  const double band = dia.rho_ring - dia.lens_radius;
  spec.size = [=](double rho) {
    return rho <= lr ? lens_h : lens_h + (ring_h - lens_h) * std::min(1.0, (rho - lr) / band);
  };
  return spec;
}

/// Adds the diaphragm's nodes and cells. Its ring nodes are the shell's
/// posterior nodes on the shell's ring, by index; its other nodes get
/// consecutive tags after the shell's.
void add_diaphragm(QuarterMesh& mesh, const Diaphragm& dia, const Chart& chart, const Chart& shell,
                   std::size_t layers)
{
  const std::size_t nc = shell.s.size(), nd = chart.s.size(), none = std::size_t(-1);
  std::vector<std::size_t> shell_ring_node(nd, none), free_index(nd, none);
  for (std::size_t j = 0; j < chart.ring.size(); ++j)
    shell_ring_node[chart.ring[j]] = shell.ring[j];
  std::size_t nf = 0;
  for (std::size_t v = 0; v < nd; ++v)
    if (shell_ring_node[v] == none)
      free_index[v] = nf++;
  const std::size_t base = mesh.x.size();
  mesh.x.resize(base + nf * (layers + 1));
  mesh.owner.resize(mesh.x.size(), part_count + 1);
  for (std::size_t v = 0; v < nd; ++v) {
    if (free_index[v] == none)
      continue;
    const Meridian a = dia.anterior(chart.s[v]), p = dia.posterior(chart.s[v]);
    for (std::size_t k = 0; k <= layers; ++k) {
      const double t = double(k) / double(layers);
      mesh.x[base + k * nf + free_index[v]]
          = revolve(between(a, p, t), chart.cos_phi[v], chart.sin_phi[v]);
    }
  }
  sweep(mesh, Body{chart, layers,
                   [&](std::size_t k, std::size_t v) {
                     return shell_ring_node[v] != none ? layers * nc + shell_ring_node[v] + 1
                                                       : base + k * nf + free_index[v] + 1;
                   },
                   [&](std::size_t v) { return shell_ring_node[v] != none; },
                   [&](std::size_t i, std::size_t k) {
                     return diaphragm_part(chart.annulus[i], k, layers);
                   },
                   [](std::size_t, bool posterior) {
                     return posterior ? Group::vitreous_wall : Group::aqueous_wall;
                   }});
}

/// The inner face's boundary as polylines of node tags: along the plane
/// z = 0 and the plane x = 0 from the apex (on both) to the cut, and the
/// cut's arc from the plane z = 0 to x = 0. Edges used by one triangle
/// only, classified by the exact zero of the chart's sides.
std::array<std::vector<std::size_t>, 3> inner_face_boundary(const QuarterMesh& mesh,
                                                           const std::vector<std::size_t>& wall)
{
  std::map<std::pair<std::size_t, std::size_t>, int> uses;
  for (std::size_t t = 0; t < wall.size(); t += 3)
    for (int j = 0; j < 3; ++j)
    {
      const std::size_t a = wall[t + j], b = wall[t + (j + 1) % 3];
      ++uses[{std::min(a, b), std::max(a, b)}];
    }
  const auto at = [&](std::size_t tag) -> const Vec3& { return mesh.x[tag - 1]; };
  // 0: z = 0, 1: x = 0, 2: the cut.
  std::array<std::multimap<std::size_t, std::size_t>, 3> next;
  for (auto [edge, n] : uses)
  {
    if (n != 1)
      continue;
    const auto [a, b] = edge;
    const int side = at(a)[2] == 0 && at(b)[2] == 0 ? 0 : at(a)[0] == 0 && at(b)[0] == 0 ? 1 : 2;
    next[side].insert({a, b});
    next[side].insert({b, a});
  }
  const auto chain = [&](int side, std::size_t start)
  {
    std::vector<std::size_t> line{start};
    for (std::size_t previous = 0;;)
    {
      std::size_t step = 0;
      auto [lo, hi] = next[side].equal_range(line.back());
      for (auto it = lo; it != hi; ++it)
        if (it->second != previous)
          step = it->second;
      if (step == 0)
        return line;
      previous = line.back();
      line.push_back(step);
    }
  };
  std::size_t apex = 0;
  for (auto [a, b] : next[0])
    if (at(a)[0] == 0)
      apex = a;
  std::array<std::vector<std::size_t>, 3> lines{chain(0, apex), chain(1, apex), {}};
  lines[2] = chain(2, lines[0].back());
  if (lines[2].back() != lines[1].back())
    throw std::runtime_error("nct::eye::build: the inner face's boundary is not one loop");
  return lines;
}

/// Adds the humor inside the shell's inner face ("cavity_wall"), down to
/// the cut, bounded by the symmetry planes: its faces on the planes and on
/// the cut (the lid) triangulated by gmsh on the wall's own boundary
/// nodes (a model of its own), then its tetrahedra inside the closed
/// surface of the wall's and those triangles (a second model), graded
/// from the wall's spacing to `size`; both removed after. Its faces on the
/// planes join "symmetry_z" and "symmetry_x", on the cut "humor_lid".
void add_humor(QuarterMesh& mesh, double size)
{
  const auto& wall = mesh.faces[static_cast<int>(Group::cavity_wall) - 1];
  const auto lines = inner_face_boundary(mesh, wall);
  const auto at = [&](std::size_t tag) -> const Vec3& { return mesh.x[tag - 1]; };
  const auto gap = [&](std::size_t a, std::size_t b)
  { return std::hypot(at(a)[0] - at(b)[0], at(a)[1] - at(b)[1], at(a)[2] - at(b)[2]); };

  // The planes' faces and the lid, on the boundary's nodes.
  gmsh::model::add("humor_faces");
  std::map<std::size_t, int> point;
  for (const auto& line : lines)
    for (std::size_t j = 0; j < line.size(); ++j)
      if (!point.count(line[j]))
      {
        const double h = std::max(j > 0 ? gap(line[j], line[j - 1]) : 0.0,
                                  j + 1 < line.size() ? gap(line[j], line[j + 1]) : 0.0);
        point[line[j]] = gmsh::model::geo::addPoint(at(line[j])[0], at(line[j])[1],
                                                    at(line[j])[2], h);
      }
  const double y_cut = at(lines[2].front())[1];
  const int centre = gmsh::model::geo::addPoint(0, y_cut, 0, size);
  std::array<std::vector<int>, 3> curves;
  for (int l = 0; l < 3; ++l)
    for (std::size_t j = 0; j + 1 < lines[l].size(); ++j)
    {
      curves[l].push_back(gmsh::model::geo::addLine(point[lines[l][j]], point[lines[l][j + 1]]));
      gmsh::model::geo::mesh::setTransfiniteCurve(curves[l].back(), 2); // the wall's own nodes
    }
  const int axis = gmsh::model::geo::addLine(centre, point[lines[0].front()]);
  const int radial_z = gmsh::model::geo::addLine(point[lines[0].back()], centre);
  const int radial_x = gmsh::model::geo::addLine(point[lines[1].back()], centre);
  auto surface = [](std::vector<int> loop) {
    return gmsh::model::geo::addPlaneSurface({gmsh::model::geo::addCurveLoop(loop)});
  };
  std::vector<int> loop_z = curves[0], loop_x = curves[1], loop_lid = curves[2];
  loop_z.insert(loop_z.end(), {radial_z, axis});
  loop_x.insert(loop_x.end(), {radial_x, axis});
  loop_lid.insert(loop_lid.end(), {radial_x, -radial_z});
  const std::array<int, 3> faces{surface(loop_z), surface(loop_x), surface(loop_lid)};
  gmsh::model::geo::synchronize();
  generate_at_most(2, size);

  // Every face's node by place: the wall's are the shell's, the rest new.
  std::map<Vec3, std::size_t> tag_at;
  for (auto tag : wall)
    tag_at[at(tag)] = tag;
  const auto tag_of = [&](const Vec3& x)
  {
    auto [it, fresh] = tag_at.insert({x, mesh.x.size() + 1});
    if (fresh)
    {
      mesh.x.push_back(x);
      mesh.owner.push_back(part_count + 1);
    }
    return it->second;
  };
  std::array<std::vector<std::size_t>, 3> face_triangles;
  for (int f = 0; f < 3; ++f)
  {
    std::vector<std::size_t> node_tags;
    std::vector<double> coords, parametric;
    gmsh::model::mesh::getNodes(node_tags, coords, parametric, 2, faces[f], true, false);
    std::map<std::size_t, std::size_t> tag;
    for (std::size_t i = 0; i < node_tags.size(); ++i)
    {
      Vec3 x{coords[3 * i], coords[3 * i + 1], coords[3 * i + 2]};
      if (f == 0)
        x[2] = 0; // exactly on the plane
      else if (f == 1)
        x[0] = 0;
      else
        x[1] = y_cut;
      tag[node_tags[i]] = tag_of(x);
    }
    for (auto n : element_nodes(2, faces[f]))
      face_triangles[f].push_back(tag.at(n));
  }
  gmsh::model::remove();

  // The tetrahedra inside the closed surface.
  gmsh::model::add("humor");
  std::vector<std::size_t> surface_nodes, surface_triangles = wall;
  for (const auto& t : face_triangles)
    surface_triangles.insert(surface_triangles.end(), t.begin(), t.end());
  surface_nodes = surface_triangles;
  std::sort(surface_nodes.begin(), surface_nodes.end());
  surface_nodes.erase(std::unique(surface_nodes.begin(), surface_nodes.end()), surface_nodes.end());
  std::vector<double> coords;
  for (auto tag : surface_nodes)
    coords.insert(coords.end(), at(tag).begin(), at(tag).end());
  gmsh::model::addDiscreteEntity(2, 1);
  gmsh::model::mesh::addNodes(2, 1, surface_nodes, coords);
  std::size_t next = 1;
  add_elements(next, 1, 2, surface_triangles, 3);
  gmsh::model::geo::addVolume({gmsh::model::geo::addSurfaceLoop({1})});
  gmsh::model::geo::synchronize();
  gmsh::model::mesh::generate(3);
  std::vector<std::size_t> node_tags;
  std::vector<double> xyz, parametric;
  // gmsh renumbers the nodes: the surface's are found by place.
  gmsh::model::mesh::getNodes(node_tags, xyz, parametric, -1, -1, false, false);
  std::map<std::size_t, std::size_t> tag;
  const std::size_t known = mesh.x.size();
  std::size_t on_surface = 0;
  for (std::size_t i = 0; i < node_tags.size(); ++i)
  {
    tag[node_tags[i]] = tag_of({xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]});
    on_surface += tag[node_tags[i]] <= known;
  }
  if (on_surface != surface_nodes.size())
    throw std::runtime_error("nct::eye::build: gmsh's humor does not keep its surface's nodes ("
                             + std::to_string(on_surface) + " of "
                             + std::to_string(surface_nodes.size()) + ")");
  const auto tets = element_nodes(3); // linear tetrahedra only
  for (std::size_t e = 0; e + 4 <= tets.size(); e += 4)
  {
    Tet tet;
    for (int j = 0; j < 4; ++j)
      tet[j] = tag.at(tets[e + j]);
    if (signed_volume(at(tet[0]), at(tet[1]), at(tet[2]), at(tet[3])) < 0)
      std::swap(tet[2], tet[3]);
    mesh.humor.insert(mesh.humor.end(), tet.begin(), tet.end());
  }
  gmsh::model::remove();
  if (mesh.humor.empty())
    throw std::runtime_error("nct::eye::build: gmsh made no tetrahedra in the humor");
  for (auto [f, group] : {std::pair{0, Group::symmetry_z}, std::pair{1, Group::symmetry_x},
                          std::pair{2, Group::humor_lid}})
  {
    auto& list = mesh.faces[static_cast<int>(group) - 1];
    list.insert(list.end(), face_triangles[f].begin(), face_triangles[f].end());
  }
}

/// Writes the mesh into a new gmsh model "eye" as discrete entities with
/// physical groups: each node on the volume of the lowest part using it,
/// the tets by part, the boundary triangles by group (the groups of the
/// eye with or without the internal structures).
void write_quarter_eye(const QuarterMesh& mesh, bool internal_structures)
{
  gmsh::model::add("eye");
  const std::array<std::string, group_count> group_names{
      "anterior_cornea", "anterior_sclera", "cavity_wall", "symmetry_x",
      "symmetry_z",      "fixed",           "aqueous_wall", "vitreous_wall", "humor_lid"};
  const int parts = internal_structures ? 7 : 3;
  for (int p = 1; p <= parts; ++p) {
    gmsh::model::addDiscreteEntity(3, p);
    std::vector<std::size_t> tags;
    std::vector<double> coords;
    for (std::size_t n = 0; n < mesh.x.size(); ++n)
      if (mesh.owner[n] == p) {
        tags.push_back(n + 1);
        coords.insert(coords.end(), mesh.x[n].begin(), mesh.x[n].end());
      }
    gmsh::model::mesh::addNodes(3, p, tags, coords);
  }
  if (!mesh.humor.empty()) {
    // The humor's own nodes: those no part uses.
    gmsh::model::addDiscreteEntity(3, humor_tag);
    std::vector<std::size_t> tags;
    std::vector<double> coords;
    for (std::size_t n = 0; n < mesh.x.size(); ++n)
      if (mesh.owner[n] == part_count + 1) {
        tags.push_back(n + 1);
        coords.insert(coords.end(), mesh.x[n].begin(), mesh.x[n].end());
      }
    gmsh::model::mesh::addNodes(3, humor_tag, tags, coords);
  }
  std::size_t next = 1;
  for (int p = 1; p <= parts; ++p) {
    add_elements(next, p, 4, mesh.tets[p - 1], 4);
    gmsh::model::addPhysicalGroup(3, {p}, p);
    gmsh::model::setPhysicalName(3, p, part_names[p - 1]);
  }
  if (!mesh.humor.empty()) {
    add_elements(next, humor_tag, 4, mesh.humor, 4);
    gmsh::model::addPhysicalGroup(3, {humor_tag}, humor_tag);
    gmsh::model::setPhysicalName(3, humor_tag, "humor");
  }
  for (int s = 1; s <= group_count; ++s) {
    const bool used = s == static_cast<int>(Group::humor_lid)
                          ? !mesh.humor.empty()
                      : internal_structures ? s != static_cast<int>(Group::cavity_wall)
                                                && s <= static_cast<int>(Group::vitreous_wall)
                                            : s <= static_cast<int>(Group::fixed);
    if (!used)
      continue;
    gmsh::model::addDiscreteEntity(2, s);
    add_elements(next, s, 2, mesh.faces[s - 1], 3);
    gmsh::model::addPhysicalGroup(2, {s}, s);
    gmsh::model::setPhysicalName(2, s, group_names[s - 1]);
  }
}

/// Meshes the shell and, with the internal structures, the diaphragm, and
/// writes the quarter eye into a new gmsh model "eye" (build()).
void mesh_quarter_eye(const Shape& shape, const Refinement& ref, bool humor)
{
  const std::size_t layers = static_cast<std::size_t>(ref.layers);
  const ChartSpec shell_spec = shell_chart_spec(shape, ref);
  const Chart shell = mesh_chart(shell_spec);
  QuarterMesh mesh;
  add_shell(mesh, shape, shell_spec, shell, layers);
  if (shape.diaphragm.on) {
    const Chart chart
        = mesh_chart(diaphragm_chart_spec(shape.diaphragm, ref, shell_spec.ring_points));
    add_diaphragm(mesh, shape.diaphragm, chart, shell, layers);
  }
  if (humor && shape.diaphragm.on)
    throw std::invalid_argument("nct::eye::build: the 3D eye's humor is meshed without the "
                                "internal structures only");
  if (humor)
    add_humor(mesh, ref.size_humor);
  write_quarter_eye(mesh, shape.diaphragm.on);
}

} // namespace

void build(const Geometry& g, const Refinement& r, bool humor)
{
  check_refinement(g, r);
  const Shape shape = derive_shape(g);
  try {
    OptionGuard quiet;
    quiet.set("General.Terminal", 0);
    mesh_quarter_eye(shape, r, humor);
  } catch (const std::string& message) { // gmsh 4.8 throws its last error as a string
    throw std::runtime_error("nct::eye::build: gmsh failed: " + message);
  }
}

} // namespace nct::eye
