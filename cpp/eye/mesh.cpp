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
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <numbers>
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

/// Meshes a quarter-disc chart in a temporary gmsh model and reads it back.
Chart mesh_chart(const ChartSpec& spec)
{
  namespace geo = gmsh::model::geo;
  const std::vector<double>& radii = spec.radii;
  const std::size_t na = radii.size();
  const auto size_at = [&spec](int, int, double x, double y, double) {
    return spec.size(std::hypot(x, y));
  };

  const meshio::TemporaryModel chart_model("eye_chart");

  const int origin = geo::addPoint(0, 0, 0);
  std::vector<int> along_x(na), along_z(na), arcs(na), rings(na);
  int last_x = origin, last_z = origin;
  for (std::size_t i = 0; i < na; ++i) {
    const int px = geo::addPoint(radii[i], 0, 0), pz = geo::addPoint(0, radii[i], 0);
    along_x[i] = geo::addLine(last_x, px);
    along_z[i] = geo::addLine(last_z, pz);
    arcs[i] = geo::addCircleArc(px, origin, pz);
    std::vector<int> loop{along_x[i], arcs[i], -along_z[i]};
    if (i > 0)
      loop.push_back(-arcs[i - 1]);
    rings[i] = geo::addPlaneSurface({geo::addCurveLoop(loop)});
    last_x = px;
    last_z = pz;
  }
  if (spec.ring_arc >= 0)
    geo::mesh::setTransfiniteCurve(arcs[spec.ring_arc], spec.ring_points);
  geo::synchronize();

  OptionGuard options;
  options.set("Mesh.MeshSizeFromPoints", 0);
  options.set("Mesh.MeshSizeFromCurvature", 0);
  options.set("Mesh.MeshSizeExtendFromBoundary", 0);
  gmsh::model::mesh::setSizeCallback(size_at);
  gmsh::model::mesh::generate(2);

  Chart chart;
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
  for (std::size_t i = 0; i < na; ++i) {
    gmsh::model::mesh::getNodes(tags, xyz, uvw, 1, arcs[i], true, false);
    for (std::size_t t : tags)
      chart.s[index.at(t)] = radii[i];
  }
  // Nodes on the transfinite arc get phi = j pi / (2 (M - 1)) exactly.
  if (spec.ring_arc >= 0) {
    std::vector<std::size_t> ring_tags;
    gmsh::model::mesh::getNodes(ring_tags, xyz, uvw, 1, arcs[spec.ring_arc], true, false);
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

  for (std::size_t i = 0; i < na; ++i) {
    std::vector<std::size_t> element_tags, node_tags; // gmsh 4.8 rejects reused non-empty vectors
    gmsh::model::mesh::getElementsByType(2, element_tags, node_tags, rings[i]);
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

  const auto add_side = [&](int curve, Group group) {
    std::vector<std::size_t> element_tags, node_tags;
    gmsh::model::mesh::getElementsByType(1, element_tags, node_tags, curve);
    for (std::size_t t = 0; t < element_tags.size(); ++t)
      chart.side_edges[edge_key(index.at(node_tags[2 * t]), index.at(node_tags[2 * t + 1]))] = group;
  };
  for (std::size_t i = 0; i < na; ++i) {
    add_side(along_x[i], Group::symmetry_z);
    add_side(along_z[i], Group::symmetry_x);
  }
  if (spec.fixed_outer)
    add_side(arcs.back(), Group::fixed);
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
struct Assembly
{
  std::vector<Vec3> x;
  std::vector<int> owner; ///< lowest part using the node (part_count + 1: none)
  std::array<std::vector<std::size_t>, part_count> tets;
  std::array<std::vector<std::size_t>, group_count> faces;
};

/// A layered body: a chart swept through `layers` layers (layer 0 the
/// anterior surface). Chart nodes that are `collapsed` are one node on all
/// layers (a ring where the layers meet).
struct Body
{
  const Chart& chart;
  std::size_t layers;
  std::function<std::size_t(std::size_t k, std::size_t v)> tag; ///< node tag of (layer, chart node)
  std::function<bool(std::size_t v)> collapsed;
  std::function<Part(std::size_t triangle, std::size_t k)> part;
  std::function<Group(std::size_t triangle, bool posterior)> cap; ///< group of the layer 0 / N faces
};

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
void sweep(Assembly& mesh, const Body& body)
{
  const Chart& chart = body.chart;
  const std::size_t nl = body.layers;
  const auto at = [&](std::size_t tag) -> const Vec3& { return mesh.x[tag - 1]; };
  struct Local
  {
    std::size_t k, v;
  };
  const std::array<std::array<int, 3>, 4> outward{{{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}}};
  for (std::size_t i = 0; i < chart.triangles.size(); ++i) {
    const auto& v = chart.triangles[i];
    for (std::size_t k = 0; k < nl; ++k) {
      const int part = static_cast<int>(body.part(i, k));
      const auto b = [&](int j) { return Local{k, v[j]}; };
      const auto t = [&](int j) { return Local{k + 1, v[j]}; };
      std::array<std::array<Local, 4>, 3> prism{{{b(0), b(1), b(2), t(2)},
                                                  {b(0), b(1), t(2), t(1)},
                                                  {b(0), t(0), t(1), t(2)}}};
      for (auto& local : prism) {
        if (chart.orientation[i] < 0)
          std::swap(local[2], local[3]);
        Tet tet;
        for (int j = 0; j < 4; ++j)
          tet[j] = body.tag(local[j].k, local[j].v);
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
          const std::array<Local, 3> face{local[f[0]], local[f[1]], local[f[2]]};
          const auto on_layer = [&](std::size_t layer) {
            return std::all_of(face.begin(), face.end(), [&](const Local& n) {
              return n.k == layer || body.collapsed(n.v);
            });
          };
          Group group;
          if (on_layer(0))
            group = body.cap(i, false);
          else if (on_layer(nl))
            group = body.cap(i, true);
          else {
            // A side face spans one chart edge: exactly two distinct chart nodes.
            const std::size_t e0 = face[0].v, e1 = face[1].v != e0 ? face[1].v : face[2].v;
            if (e0 == e1 || (face[2].v != e0 && face[2].v != e1))
              continue;
            const auto side = chart.side_edges.find(edge_key(e0, e1));
            if (side == chart.side_edges.end())
              continue;
            group = side->second;
          }
          auto& list = mesh.faces[static_cast<int>(group) - 1];
          for (int j = 0; j < 3; ++j)
            list.push_back(tet[f[j]]);
        }
      }
    }
  }
}

/// Puts the node (r, y) at azimuth (c, s) = (cos phi, sin phi).
Vec3 place(Meridian p, double c, double s) { return {p.r * c, p.y, p.r * s}; }

/// Meshes both bodies and writes the mesh into a new gmsh model "eye" as
/// discrete entities with physical groups.
void build_eye(const Shape& shape, const Refinement& ref)
{
  const Diaphragm& dia = shape.diaphragm;
  const std::size_t nl = static_cast<std::size_t>(ref.layers);

  // Shell chart: rings at the part bounds, the junction and the zonule ring.
  // Size: the least over the parts of the part's size plus `gradation`
  // times the distance to the part, so sizes change smoothly (at most
  // 0.3 mm per mm) and never exceed the part's own size inside it.
  const double gradation = 0.3;
  const std::array<double, 3> size{ref.size_cornea, ref.size_limbus, ref.size_sclera};
  const std::array<double, 4> bounds{0, shape.limbus_begin, shape.limbus_end,
                                     shape.anterior.length()};
  ChartSpec shell_spec;
  shell_spec.size = [=](double s) {
    double h = size[0] + gradation * std::max(0.0, s - bounds[1]);
    for (std::size_t p = 1; p < 3; ++p)
      h = std::min(h, size[p] + gradation * std::max({0.0, bounds[p] - s, s - bounds[p + 1]}));
    return h;
  };
  shell_spec.radii = {shape.limbus_begin, shape.anterior.junction_s(), shape.limbus_end,
                      shape.anterior.length()};
  shell_spec.fixed_outer = true;
  if (dia.on) {
    // The ring arc, merged with an existing one it (nearly) coincides with.
    shell_spec.ring_arc = static_cast<int>(
        insert_bound(shell_spec.radii, dia.ring_s, 1e-9 * shape.anterior.length()));
    const double chart_arc = std::numbers::pi / 2 * dia.ring_s;
    shell_spec.ring_points =
        1 + std::max(2, static_cast<int>(std::ceil(chart_arc / shell_spec.size(dia.ring_s))));
  }
  const Chart shell = mesh_chart(shell_spec);
  std::vector<Part> shell_part;
  for (std::size_t i = 0; i < shell_spec.radii.size(); ++i) {
    const double lo = i > 0 ? shell_spec.radii[i - 1] : 0, mid = (lo + shell_spec.radii[i]) / 2;
    shell_part.push_back(shape.part_at(mid));
  }

  // Shell nodes: tag k nc + v + 1 for chart node v on layer k.
  const std::size_t nc = shell.s.size();
  Assembly mesh;
  mesh.x.resize(nc * (nl + 1));
  for (std::size_t v = 0; v < nc; ++v) {
    const Meridian a = shape.anterior.at(shell.s[v]);
    const Meridian p = shape.posterior.at(shape.posterior_s(shell.s[v]));
    for (std::size_t k = 0; k <= nl; ++k) {
      const double t = double(k) / double(nl);
      mesh.x[k * nc + v] = place(between(a, p, t), shell.cos_phi[v], shell.sin_phi[v]);
    }
  }
  mesh.owner.assign(mesh.x.size(), part_count + 1);
  sweep(mesh, Body{shell, nl, [nc](std::size_t k, std::size_t v) { return k * nc + v + 1; },
                   [](std::size_t) { return false; },
                   [&](std::size_t i, std::size_t) { return shell_part[shell.annulus[i]]; },
                   [&](std::size_t i, bool posterior) {
                     if (!posterior)
                       return anterior_group(shell_part[shell.annulus[i]]);
                     return inner_group(dia.on, shell.annulus[i] <= shell_spec.ring_arc);
                   }});

  if (dia.on) {
    // Diaphragm chart: rings at the nucleus bound, the lens equator and the
    // ring, whose arc has the shell ring's points; the size grades linearly
    // along the band from size_lens to the ring's node spacing.
    const int m = shell_spec.ring_points;
    const double ring_h = std::numbers::pi / 2 * dia.rho_ring / (m - 1);
    ChartSpec spec;
    spec.radii = {dia.rho_nucleus, dia.lens_radius, dia.rho_ring};
    spec.ring_arc = 2;
    spec.ring_points = m;
    const double lens_h = ref.size_lens, lr = dia.lens_radius;
    const double band = dia.rho_ring - dia.lens_radius;
    spec.size = [=](double rho) {
      return rho <= lr ? lens_h : lens_h + (ring_h - lens_h) * std::min(1.0, (rho - lr) / band);
    };
    const Chart chart = mesh_chart(spec);
    const std::size_t nd = chart.s.size();

    // Ring nodes are the shell's posterior nodes on its ring, by index;
    // the other nodes get consecutive tags after the shell's.
    std::vector<std::size_t> ring_of(nd, std::size_t(-1)), free_index(nd, std::size_t(-1));
    for (std::size_t j = 0; j < chart.ring.size(); ++j)
      ring_of[chart.ring[j]] = shell.ring[j];
    std::size_t nf = 0;
    for (std::size_t v = 0; v < nd; ++v)
      if (ring_of[v] == std::size_t(-1))
        free_index[v] = nf++;
    const std::size_t base = mesh.x.size();
    mesh.x.resize(base + nf * (nl + 1));
    mesh.owner.resize(mesh.x.size(), part_count + 1);
    for (std::size_t v = 0; v < nd; ++v) {
      if (free_index[v] == std::size_t(-1))
        continue;
      const Meridian a = dia.anterior(chart.s[v]), p = dia.posterior(chart.s[v]);
      for (std::size_t k = 0; k <= nl; ++k) {
        const double t = double(k) / double(nl);
        mesh.x[base + k * nf + free_index[v]]
            = place(between(a, p, t), chart.cos_phi[v], chart.sin_phi[v]);
      }
    }
    sweep(mesh,
          Body{chart, nl,
               [&](std::size_t k, std::size_t v) {
                 return ring_of[v] != std::size_t(-1) ? nl * nc + ring_of[v] + 1
                                                      : base + k * nf + free_index[v] + 1;
               },
               [&](std::size_t v) { return ring_of[v] != std::size_t(-1); },
               [&](std::size_t i, std::size_t k) { return diaphragm_part(chart.annulus[i], k, nl); },
               [](std::size_t, bool posterior) {
                 return posterior ? Group::vitreous_wall : Group::aqueous_wall;
               }});
  }

  gmsh::model::add("eye");
  const std::array<std::string, group_count> group_names{
      "anterior_cornea", "anterior_sclera", "cavity_wall", "symmetry_x",
      "symmetry_z",      "fixed",           "aqueous_wall", "vitreous_wall"};
  const int parts = dia.on ? 7 : 3;
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
  std::size_t next = 1;
  for (int p = 1; p <= parts; ++p) {
    add_elements(next, p, 4, mesh.tets[p - 1], 4);
    gmsh::model::addPhysicalGroup(3, {p}, p);
    gmsh::model::setPhysicalName(3, p, part_names[p - 1]);
  }
  for (int s = 1; s <= group_count; ++s) {
    const bool used = dia.on ? s != static_cast<int>(Group::cavity_wall)
                             : s <= static_cast<int>(Group::fixed);
    if (!used)
      continue;
    gmsh::model::addDiscreteEntity(2, s);
    add_elements(next, s, 2, mesh.faces[s - 1], 3);
    gmsh::model::addPhysicalGroup(2, {s}, s);
    gmsh::model::setPhysicalName(2, s, group_names[s - 1]);
  }
}

} // namespace

void build(const Geometry& g, const Refinement& r)
{
  check_refinement(g, r);
  const Shape shape = derive_shape(g);
  try {
    OptionGuard quiet;
    quiet.set("General.Terminal", 0);
    build_eye(shape, r);
  } catch (const std::string& message) { // gmsh 4.8 throws its last error as a string
    throw std::runtime_error("nct::eye::build: gmsh failed: " + message);
  }
}

} // namespace nct::eye
