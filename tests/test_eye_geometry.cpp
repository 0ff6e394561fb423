// Tests of the idealised eye: derived numbers, fibres and the gmsh mesh.
#include "eye/geometry.h"

#include <gmsh.h>
#include <gtest/gtest.h>

#include "settings/settings.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <functional>
#include <iostream>
#include <limits>
#include <map>
#include <numbers>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <vector>

namespace
{

using nct::eye::Derived;
using nct::eye::Geometry;
using nct::eye::Part;
using nct::eye::Refinement;
using Vec3 = std::array<double, 3>;

constexpr double pi = std::numbers::pi;

/// Composite Simpson rule of f over [a, b] with n (even) panels.
double simpson(const std::function<double(double)>& f, double a, double b, int n = 2000)
{
  const double h = (b - a) / n;
  double sum = f(a) + f(b);
  for (int i = 1; i < n; ++i)
    sum += (i % 2 ? 4 : 2) * f(a + i * h);
  return sum * h / 3;
}

/// Whole-revolution volume under a piecewise profile r^2(y): a sphere
/// (radius R, centre y c) above y_junction, a sphere about the origin
/// (radius Rsc) below, from cut_y to the apex.
double revolved_volume(double R, double c, double Rsc, double y_junction, double cut_y,
                       double apex_y)
{
  const auto cap = [&](double y) { return pi * (R * R - (y - c) * (y - c)); };
  const auto zone = [&](double y) { return pi * (Rsc * Rsc - y * y); };
  return simpson(zone, cut_y, y_junction) + simpson(cap, y_junction, apex_y);
}

double inner_radius(const Geometry& g) { return g.sclera_outer_radius - g.sclera_thickness; }

Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 cross(const Vec3& a, const Vec3& b)
{
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double norm(const Vec3& a) { return std::sqrt(dot(a, a)); }

TEST(EyeDerive, DefaultGeometryIsConsistent)
{
  const Geometry g = nct::scene::defaults<Geometry>();
  const Derived d = nct::eye::derive(g);
  const double Ra = g.cornea_anterior_radius, Rp = g.cornea_posterior_radius;
  const double Rs = g.sclera_outer_radius, Ri = inner_radius(g);
  const double tol = 1e-12;

  // Apices on their spheres, central thickness between them.
  EXPECT_NEAR(d.apex_y - d.anterior_centre_y, Ra, tol);
  EXPECT_NEAR(d.apex_y - g.cornea_central_thickness - d.posterior_centre_y, Rp, tol);

  // Junctions on both of their spheres.
  EXPECT_NEAR(d.junction_anterior_r, g.limbus_diameter / 2, tol);
  EXPECT_NEAR(std::hypot(d.junction_anterior_r, d.junction_anterior_y), Rs, tol);
  EXPECT_NEAR(std::hypot(d.junction_anterior_r, d.junction_anterior_y - d.anterior_centre_y), Ra,
              tol);
  EXPECT_GT(d.junction_posterior_r, 0);
  EXPECT_NEAR(std::hypot(d.junction_posterior_r, d.junction_posterior_y), Ri, tol);
  EXPECT_NEAR(std::hypot(d.junction_posterior_r, d.junction_posterior_y - d.posterior_centre_y),
              Rp, tol);

  // Peripheral thickness: J - t n lands on the posterior sphere, and the
  // cornea thickens towards the periphery.
  const double nr = d.junction_anterior_r / Ra;
  const double ny = (d.junction_anterior_y - d.anterior_centre_y) / Ra;
  const double t = d.peripheral_thickness;
  EXPECT_NEAR(std::hypot(d.junction_anterior_r - t * nr,
                         d.junction_anterior_y - t * ny - d.posterior_centre_y),
              Rp, 1e-10);
  EXPECT_GT(t, g.cornea_central_thickness);
  EXPECT_LT(t, 2 * g.cornea_central_thickness);

  // Cavity volume against a quadrature of pi r(y)^2 dy.
  const double quadrature = revolved_volume(Rp, d.posterior_centre_y, Ri, d.junction_posterior_y,
                                            g.cut_y, d.apex_y - g.cornea_central_thickness);
  EXPECT_NEAR(d.cavity_volume / quadrature, 1, 1e-12);
  std::cout << "[ derive   ] apex_y " << d.apex_y << ", posterior junction (" << d.junction_posterior_r
            << ", " << d.junction_posterior_y << "), peripheral thickness " << t
            << ", cavity volume " << d.cavity_volume << " mm^3\n";
}

/// Expects derive(g) to throw std::invalid_argument naming `key`.
void expect_rejected(const Geometry& g, const std::string& key)
{
  try {
    nct::eye::derive(g);
    ADD_FAILURE() << "no exception for " << key;
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("geometry." + key), std::string::npos) << e.what();
  }
}

TEST(EyeDerive, ImpossibleGeometriesNameTheKey)
{
  Geometry g = nct::scene::defaults<Geometry>();
  g.cornea_posterior_radius = 2.0; // too small to reach the inner sclera
  expect_rejected(g, "cornea_posterior_radius");
  g = nct::scene::defaults<Geometry>();
  g.cut_y = 10.0; // above the posterior junction
  expect_rejected(g, "cut_y");
  g = nct::scene::defaults<Geometry>();
  g.cut_y = -11.5; // below the inner sphere
  expect_rejected(g, "cut_y");
  g = nct::scene::defaults<Geometry>();
  g.limbus_width = 14.0; // wider than the cornea can hold
  expect_rejected(g, "limbus_width");
  g = nct::scene::defaults<Geometry>();
  g.sclera_thickness = 0;
  expect_rejected(g, "sclera_thickness");
  g = nct::scene::defaults<Geometry>();
  g.limbus_diameter = 16.0; // wider than the anterior corneal sphere
  expect_rejected(g, "limbus_diameter");
  g = nct::scene::defaults<Geometry>();
  g.cornea_central_thickness = -0.1;
  expect_rejected(g, "cornea_central_thickness");
  g = nct::scene::defaults<Geometry>();
  g.cornea_central_thickness = 3.0; // posterior sphere misses the anterior junction
  expect_rejected(g, "cornea_posterior_radius");
  g = nct::scene::defaults<Geometry>();
  g.sclera_thickness = 3.0; // the sweep lines fold at the posterior junction
  expect_rejected(g, "sclera_thickness");
}

TEST(EyeFibres, DirectionsPerPart)
{
  const Geometry g = nct::scene::defaults<Geometry>();
  const Derived d = nct::eye::derive(g);
  const double tol = 1e-14;

  // Cornea: unit, tangent to the anterior sphere; e_x, e_z at the apex.
  const auto apex = nct::eye::fibres(g, Part::cornea, {0, d.apex_y, 0});
  EXPECT_NEAR(apex[0][0], 1, tol);
  EXPECT_NEAR(apex[1][2], 1, tol);
  const Vec3 X{2.0, 11.5, 3.0};
  const Vec3 n = sub(X, {0, d.anterior_centre_y, 0});
  for (const Vec3& f : nct::eye::fibres(g, Part::cornea, X)) {
    EXPECT_NEAR(norm(f), 1, tol);
    EXPECT_NEAR(dot(f, n), 0, tol);
  }

  // Limbus: e_phi, second family zero; the axis gives a finite unit vector.
  const auto limbus = nct::eye::fibres(g, Part::limbus, {3.0, 9.0, 4.0});
  EXPECT_NEAR(limbus[0][0], -0.8, tol);
  EXPECT_NEAR(limbus[0][1], 0, tol);
  EXPECT_NEAR(limbus[0][2], 0.6, tol);
  EXPECT_EQ(norm(limbus[1]), 0);
  EXPECT_NEAR(norm(nct::eye::fibres(g, Part::limbus, {0, 9.0, 0})[0]), 1, tol);

  // Sclera: none.
  for (const Vec3& f : nct::eye::fibres(g, Part::sclera, {5.0, 0, 5.0}))
    EXPECT_EQ(norm(f), 0);
}

/// The current gmsh model read back through the API.
struct MeshData
{
  std::unordered_map<std::size_t, Vec3> x;
  std::map<std::string, std::vector<std::size_t>> tets;      ///< by volume group name
  std::map<std::string, std::vector<std::size_t>> triangles; ///< by surface group name
  std::map<std::pair<int, int>, std::string> names;          ///< (dim, tag) -> name
};

MeshData read_mesh()
{
  MeshData m;
  std::vector<std::size_t> tags;
  std::vector<double> xyz, uvw;
  gmsh::model::mesh::getNodes(tags, xyz, uvw, -1, -1, false, false);
  for (std::size_t i = 0; i < tags.size(); ++i)
    m.x[tags[i]] = {xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]};
  gmsh::vectorpair groups;
  gmsh::model::getPhysicalGroups(groups);
  for (const auto& [dim, tag] : groups) {
    std::string name;
    gmsh::model::getPhysicalName(dim, tag, name);
    m.names[{dim, tag}] = name;
    std::vector<int> entities;
    gmsh::model::getEntitiesForPhysicalGroup(dim, tag, entities);
    auto& list = dim == 3 ? m.tets[name] : m.triangles[name];
    for (int entity : entities) {
      std::vector<std::size_t> element_tags, node_tags;
      gmsh::model::mesh::getElementsByType(dim == 3 ? 4 : 2, element_tags, node_tags, entity);
      list.insert(list.end(), node_tags.begin(), node_tags.end());
    }
  }
  return m;
}

/// Minimum ICN (inverse condition number, = SICN for linear tets) of the
/// current model's tets, from gmsh's AnalyseMeshQuality plugin.
double min_quality()
{
  gmsh::plugin::setNumber("AnalyseMeshQuality", "ICNMeasure", 1);
  gmsh::plugin::setNumber("AnalyseMeshQuality", "DimensionOfElements", 3);
  gmsh::plugin::setNumber("AnalyseMeshQuality", "CreateView", 1);
  gmsh::plugin::setNumber("AnalyseMeshQuality", "Recompute", 1);
  gmsh::plugin::run("AnalyseMeshQuality");
  std::vector<int> views;
  gmsh::view::getTags(views);
  double q = std::numeric_limits<double>::infinity();
  for (int view : views) {
    std::string type;
    std::vector<std::size_t> elements;
    std::vector<std::vector<double>> data;
    double time = 0;
    int components = 0;
    gmsh::view::getModelData(view, 0, type, elements, data, time, components);
    for (const auto& value : data)
      q = std::min(q, value[0]);
    gmsh::view::remove(view);
  }
  return q;
}

/// Numbers measured on a built mesh.
struct MeshReport
{
  std::size_t nodes = 0, tets = 0;
  double solid = 0, min_volume = 0, solid_error = 0, chord_prediction = 0, next_order = 0;
  double cavity_error = 0;
  double min_quality = 0;
};

/// Builds the eye, checks it and reports its numbers; removes the model.
MeshReport check_mesh(const Geometry& g, const Refinement& r)
{
  nct::eye::build(g, r);
  const MeshData m = read_mesh();
  const Derived d = nct::eye::derive(g);
  const double Ra = g.cornea_anterior_radius, Rp = g.cornea_posterior_radius;
  const double Rs = g.sclera_outer_radius, Ri = inner_radius(g);
  MeshReport report;
  report.nodes = m.x.size();

  // Physical groups and their tags.
  const std::map<std::pair<int, int>, std::string> expected{
      {{3, 1}, "cornea"},          {{3, 2}, "limbus"},          {{3, 3}, "sclera"},
      {{2, 1}, "anterior_cornea"}, {{2, 2}, "anterior_sclera"}, {{2, 3}, "cavity_wall"},
      {{2, 4}, "symmetry_x"},      {{2, 5}, "symmetry_z"},      {{2, 6}, "fixed"}};
  EXPECT_EQ(m.names, expected);

  // Tets: positive volumes and their sum.
  double volume = 0;
  report.min_volume = std::numeric_limits<double>::infinity();
  for (const auto& [name, nodes] : m.tets) {
    EXPECT_FALSE(nodes.empty()) << name;
    for (std::size_t i = 0; i < nodes.size(); i += 4) {
      const Vec3& a = m.x.at(nodes[i]);
      const double v = dot(sub(m.x.at(nodes[i + 1]), a),
                           cross(sub(m.x.at(nodes[i + 2]), a), sub(m.x.at(nodes[i + 3]), a))) / 6;
      report.min_volume = std::min(report.min_volume, v);
      volume += v;
      ++report.tets;
    }
  }
  EXPECT_GT(report.min_volume, 0);

  // Boundary triangles: the six groups close the solid (divergence
  // theorem, so all are oriented outwards and none is missing), and the
  // cavity volume from the cavity wall about x0, which lies on the three
  // flat faces closing the cavity; the minus as n points into the cavity.
  const Vec3 x0{0, g.cut_y, 0};
  double enclosed = 0, cavity = 0;
  // Chord gaps: volume between the triangles and their spheres, to leading
  // order and a bound of the next order, on the outer and inner surface.
  double gap_outer = 0, gap_inner = 0, next_order = 0;
  for (const auto& [name, nodes] : m.triangles) {
    EXPECT_FALSE(nodes.empty()) << name;
    for (std::size_t i = 0; i < nodes.size(); i += 3) {
      const Vec3 &a = m.x.at(nodes[i]), &b = m.x.at(nodes[i + 1]), &c = m.x.at(nodes[i + 2]);
      const Vec3 an = cross(sub(b, a), sub(c, a)); // 2 A n
      const Vec3 centroid{(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3,
                          (a[2] + b[2] + c[2]) / 3};
      enclosed += dot(centroid, an) / 6;
      if (name == "cavity_wall")
        cavity -= 4 * dot(sub(centroid, x0), an) / 6;

      // A triangle inscribed in a sphere of radius R lies inside it by
      // R - sqrt(R^2 - q) = q/(2R) (1 + O(q/R^2)), q = sum_i lambda_i |p_i - x|^2
      // at x; q averages (sum of squared edges)/12 over the triangle, and
      // q <= sum of squared edges bounds the relative next order by 4x.
      const bool anterior = name.rfind("anterior_", 0) == 0;
      if (!anterior && name != "cavity_wall")
        continue;
      const double cap_c = anterior ? d.anterior_centre_y : d.posterior_centre_y;
      const double cap_R = anterior ? Ra : Rp;
      const auto on_cap = [&](const Vec3& p) {
        return std::abs(norm(sub(p, {0, cap_c, 0})) - cap_R) < 1e-9;
      };
      const double R = on_cap(a) && on_cap(b) && on_cap(c) ? cap_R : anterior ? Rs : Ri;
      const double edges2 = dot(sub(b, a), sub(b, a)) + dot(sub(c, b), sub(c, b))
                            + dot(sub(a, c), sub(a, c));
      const double gap = norm(an) / 2 * edges2 / (24 * R);
      (anterior ? gap_outer : gap_inner) += gap;
      next_order += gap * edges2 / (R * R);
    }
  }
  EXPECT_NEAR(enclosed / volume, 1, 1e-12);

  // Solid volume: the tets fill the polyhedron whose nodes lie on the
  // exact surfaces, so the error is the inner chord gap (adds solid) minus
  // the outer one (removes solid), up to the next order.
  const double outer = revolved_volume(Ra, d.anterior_centre_y, Rs, d.junction_anterior_y,
                                       g.cut_y, d.apex_y);
  const double inner = revolved_volume(Rp, d.posterior_centre_y, Ri, d.junction_posterior_y,
                                       g.cut_y, d.apex_y - g.cornea_central_thickness);
  const double solid = (outer - inner) / 4;
  report.solid_error = volume - solid;
  report.solid = solid;
  report.chord_prediction = gap_inner - gap_outer;
  report.next_order = next_order;
  EXPECT_NEAR(report.solid_error, report.chord_prediction, next_order)
      << "solid " << solid << " mesh " << volume;

  report.cavity_error = cavity / d.cavity_volume - 1;
  EXPECT_LT(std::abs(report.cavity_error), 0.01);

  // Flat faces: exact coordinates.
  const auto for_nodes = [](int tag, const std::function<void(const Vec3&)>& f) {
    std::vector<std::size_t> tags;
    std::vector<double> xyz;
    gmsh::model::mesh::getNodesForPhysicalGroup(2, tag, tags, xyz);
    EXPECT_FALSE(tags.empty());
    for (std::size_t i = 0; i < tags.size(); ++i)
      f({xyz[3 * i], xyz[3 * i + 1], xyz[3 * i + 2]});
  };
  for_nodes(4, [](const Vec3& p) { EXPECT_EQ(p[0], 0); });
  for_nodes(5, [](const Vec3& p) { EXPECT_EQ(p[2], 0); });
  for_nodes(6, [&](const Vec3& p) { EXPECT_EQ(p[1], g.cut_y); });

  // The apex is a node.
  const bool apex = std::any_of(m.x.begin(), m.x.end(), [&](const auto& node) {
    return norm(sub(node.second, {0, d.apex_y, 0})) < 1e-12;
  });
  EXPECT_TRUE(apex);

  report.min_quality = min_quality();
  EXPECT_GT(report.min_quality, 0);
  gmsh::model::remove();
  return report;
}

/// Starts gmsh once per test suite.
class GmshSuite : public ::testing::Test
{
protected:
  static void SetUpTestSuite()
  {
    gmsh::initialize();
    gmsh::option::setNumber("General.Terminal", 0);
  }
  static void TearDownTestSuite() { gmsh::finalize(); }
};

class EyeMesh : public GmshSuite, public ::testing::WithParamInterface<int>
{
};

/// The same refinement with every in-plane size halved.
Refinement halved(Refinement r)
{
  r.size_cornea /= 2;
  r.size_limbus /= 2;
  r.size_sclera /= 2;
  r.size_lens /= 2;
  return r;
}

TEST_P(EyeMesh, ChecksOutAndConverges)
{
  const Geometry g = nct::scene::defaults<Geometry>();
  Refinement r = nct::scene::defaults<Refinement>();
  r.layers = GetParam();
  const MeshReport coarse = check_mesh(g, r);
  const MeshReport fine = check_mesh(g, halved(r));
  for (const auto& [label, m] : {std::pair{"sizes", coarse}, std::pair{"sizes / 2", fine}})
    std::cout << "[ mesh     ] layers " << GetParam() << ", " << label << ": " << m.nodes
              << " nodes, " << m.tets << " tets, solid volume " << m.solid << " error "
              << m.solid_error << " mm^3 (chord prediction " << m.chord_prediction << " +- "
              << m.next_order << "), cavity error "
              << 100 * m.cavity_error << " %, min ICN " << m.min_quality << "\n";
  EXPECT_LT(std::abs(fine.cavity_error), std::abs(coarse.cavity_error));
  EXPECT_LT(std::abs(fine.solid_error), std::abs(coarse.solid_error));
}

INSTANTIATE_TEST_SUITE_P(Layers, EyeMesh, ::testing::Values(3, 5));

using EyeMeshDefault = GmshSuite;

TEST_F(EyeMeshDefault, RefinementReport)
{
  const auto start = std::chrono::steady_clock::now();
  nct::eye::build(nct::scene::defaults<Geometry>(), nct::scene::defaults<Refinement>());
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::vector<std::size_t> tets, nodes, tags;
  std::vector<double> xyz, uvw;
  gmsh::model::mesh::getElementsByType(4, tets, nodes);
  gmsh::model::mesh::getNodes(tags, xyz, uvw, -1, -1, false, false);
  const double q = min_quality();
  std::cout << "[ default  ] " << tags.size() << " nodes, " << tets.size() << " tets, min ICN "
            << q << ", build() " << 1e3 * seconds << " ms\n";
  EXPECT_GT(q, 0);
  gmsh::model::remove();
}

TEST_F(EyeMeshDefault, RejectsBadRefinement)
{
  Refinement r = nct::scene::defaults<Refinement>();
  r.layers = 0;
  try {
    nct::eye::build(nct::scene::defaults<Geometry>(), r);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("mesh.layers"), std::string::npos) << e.what();
  }
}

// ---- Internal structures (lens, zonule band, vitreous membrane) ----

Geometry internal_geometry()
{
  Geometry g = nct::scene::defaults<Geometry>();
  g.internal_structures = true;
  return g;
}

TEST(EyeDerive, InternalStructureVolumes)
{
  const Geometry g = internal_geometry();
  const Derived d = nct::eye::derive(g);
  const Derived off = nct::eye::derive(nct::scene::defaults<Geometry>());
  EXPECT_EQ(off.aqueous_volume, 0);
  EXPECT_EQ(off.vitreous_volume, 0);
  EXPECT_EQ(d.cavity_volume, off.cavity_volume);

  // The meridian shapes rebuilt from the keys, integrated in shells
  // 2 pi r (y_top(r) - y_bottom(r)) dr up to the ring radius, which lies
  // above the equator of the inner sphere for the defaults.
  const double Ri = inner_radius(g), Rp = g.cornea_posterior_radius;
  const double lr = g.lens_diameter / 2;
  const double front_pole = d.apex_y - g.cornea_central_thickness - g.anterior_chamber_depth;
  const double back_pole = front_pole - g.lens_thickness;
  const double fc = front_pole - g.lens_anterior_radius, bc = back_pole + g.lens_posterior_radius;
  const auto front = [&](double r) { return fc + std::sqrt(std::pow(g.lens_anterior_radius, 2) - r * r); };
  const auto back = [&](double r) { return bc - std::sqrt(std::pow(g.lens_posterior_radius, 2) - r * r); };
  const double theta = std::atan2(d.junction_posterior_r, d.junction_posterior_y) + g.ciliary_offset / Ri;
  const double ring_r = Ri * std::sin(theta), ring_y = Ri * std::cos(theta);
  ASSERT_GT(ring_y, 0);
  ASSERT_GT(ring_r, d.junction_posterior_r);
  const auto band = [&](double rim_y, double r) {
    return rim_y + (r - lr) / (ring_r - lr) * (ring_y - rim_y);
  };
  const auto dia_front = [&](double r) { return r <= lr ? front(r) : band(front(lr), r); };
  const auto dia_back = [&](double r) { return r <= lr ? back(r) : band(back(lr), r); };
  const auto wall = [&](double r) {
    return r <= d.junction_posterior_r ? d.posterior_centre_y + std::sqrt(Rp * Rp - r * r)
                                       : std::sqrt(Ri * Ri - r * r);
  };
  // Pieces split at the kinks: lens equator, posterior junction.
  const auto shells = [&](const std::function<double(double)>& height) {
    const auto f = [&](double r) { return 2 * pi * r * height(r); };
    return simpson(f, 0, lr) + simpson(f, lr, d.junction_posterior_r)
           + simpson(f, d.junction_posterior_r, ring_r);
  };
  const double aqueous = shells([&](double r) { return wall(r) - dia_front(r); });
  const double diaphragm = shells([&](double r) { return dia_front(r) - dia_back(r); });
  EXPECT_NEAR(d.aqueous_volume / aqueous, 1, 1e-9);
  EXPECT_NEAR((d.cavity_volume - d.aqueous_volume - d.vitreous_volume) / diaphragm, 1, 1e-9);
  EXPECT_GT(d.vitreous_volume, d.aqueous_volume);
  std::cout << "[ derive   ] internal structures: aqueous " << d.aqueous_volume << ", vitreous "
            << d.vitreous_volume << ", diaphragm " << diaphragm << ", cavity " << d.cavity_volume
            << " mm^3; ring (r, y) = (" << ring_r << ", " << ring_y << ")\n";
}

TEST(EyeDerive, ImpossibleLensNamesTheKey)
{
  Geometry g = internal_geometry();
  g.lens_thickness = 0.3; // the spheres cross before the equator
  expect_rejected(g, "lens_thickness");
  g.internal_structures = false; // not validated when off
  EXPECT_NO_THROW(nct::eye::derive(g));
  g = internal_geometry();
  g.lens_thickness = 14.0; // through the cut plane
  expect_rejected(g, "lens_thickness");
  g = internal_geometry();
  g.lens_anterior_radius = 4.0; // smaller than the lens radius
  expect_rejected(g, "lens_anterior_radius");
  g = internal_geometry();
  g.lens_posterior_radius = 4.7;
  expect_rejected(g, "lens_posterior_radius");
  g = internal_geometry();
  g.anterior_chamber_depth = 0;
  expect_rejected(g, "anterior_chamber_depth");
  g = internal_geometry();
  g.anterior_chamber_depth = 0.5; // the lens periphery pierces the posterior cornea
  g.lens_anterior_radius = 20.0;
  expect_rejected(g, "anterior_chamber_depth");
  g = internal_geometry();
  g.lens_diameter = -1;
  expect_rejected(g, "lens_diameter");
  g = internal_geometry();
  g.lens_nucleus_fraction = 1.2;
  expect_rejected(g, "lens_nucleus_fraction");
  g = internal_geometry();
  g.ciliary_offset = 30.0; // below the cut plane
  expect_rejected(g, "ciliary_offset");
  g = internal_geometry();
  g.ciliary_offset = 0;
  expect_rejected(g, "ciliary_offset");
  g = internal_geometry();
  g.lens_diameter = 10.6; // equator outside the ring
  g.lens_posterior_radius = 10.0;
  g.ciliary_offset = 0.01;
  expect_rejected(g, "ciliary_offset");
}

/// Numbers measured on a mesh with internal structures.
struct InternalReport
{
  std::size_t nodes = 0, tets = 0, ring_nodes = 0;
  double aqueous_error = 0, vitreous_error = 0, min_quality = 0;
};

/// Builds the eye with internal structures, checks it and reports; removes the model.
InternalReport check_internal_mesh(const Geometry& g, const Refinement& r)
{
  nct::eye::build(g, r);
  const MeshData m = read_mesh();
  const Derived d = nct::eye::derive(g);
  InternalReport report;
  report.nodes = m.x.size();

  const std::map<std::pair<int, int>, std::string> expected{
      {{3, 1}, "cornea"},          {{3, 2}, "limbus"},          {{3, 3}, "sclera"},
      {{3, 4}, "lens_cortex"},     {{3, 5}, "lens_nucleus"},    {{3, 6}, "zonule"},
      {{3, 7}, "vitreous_membrane"},
      {{2, 1}, "anterior_cornea"}, {{2, 2}, "anterior_sclera"}, {{2, 4}, "symmetry_x"},
      {{2, 5}, "symmetry_z"},      {{2, 6}, "fixed"},           {{2, 7}, "aqueous_wall"},
      {{2, 8}, "vitreous_wall"}};
  EXPECT_EQ(m.names, expected);

  // Tets: distinct nodes, positive volumes; faces counted.
  using Face = std::array<std::size_t, 3>;
  std::map<Face, int> tet_faces;
  const auto sorted = [](Face f) {
    std::sort(f.begin(), f.end());
    return f;
  };
  std::map<std::size_t, int> node_body; // bit 1 shell, bit 2 diaphragm
  double volume = 0, min_volume = std::numeric_limits<double>::infinity();
  std::size_t repeated = 0;
  for (const auto& [name, nodes] : m.tets) {
    EXPECT_FALSE(nodes.empty()) << name;
    const bool shell = name == "cornea" || name == "limbus" || name == "sclera";
    for (std::size_t i = 0; i < nodes.size(); i += 4) {
      std::array<std::size_t, 4> t{nodes[i], nodes[i + 1], nodes[i + 2], nodes[i + 3]};
      std::array<std::size_t, 4> s = t;
      std::sort(s.begin(), s.end());
      repeated += std::adjacent_find(s.begin(), s.end()) != s.end();
      const Vec3& a = m.x.at(t[0]);
      const double v = dot(sub(m.x.at(t[1]), a), cross(sub(m.x.at(t[2]), a), sub(m.x.at(t[3]), a))) / 6;
      min_volume = std::min(min_volume, v);
      volume += v;
      ++report.tets;
      for (int j = 0; j < 4; ++j) {
        ++tet_faces[sorted({t[(j + 1) % 4], t[(j + 2) % 4], t[(j + 3) % 4]})];
        node_body[t[j]] |= shell ? 1 : 2;
      }
    }
  }
  EXPECT_EQ(repeated, 0u);
  EXPECT_GT(min_volume, 0);
  report.ring_nodes = std::count_if(node_body.begin(), node_body.end(),
                                    [](const auto& n) { return n.second == 3; });
  EXPECT_GT(report.ring_nodes, 2u);

  // Boundary triangles: each in one group, each a face of exactly one tet;
  // interior faces shared by exactly two tets.
  std::map<Face, int> boundary;
  const Vec3 x0{0, g.cut_y, 0};
  double enclosed = 0, aqueous = 0, vitreous = 0;
  for (const auto& [name, nodes] : m.triangles) {
    EXPECT_FALSE(nodes.empty()) << name;
    for (std::size_t i = 0; i < nodes.size(); i += 3) {
      ++boundary[sorted({nodes[i], nodes[i + 1], nodes[i + 2]})];
      const Vec3 &a = m.x.at(nodes[i]), &b = m.x.at(nodes[i + 1]), &c = m.x.at(nodes[i + 2]);
      const Vec3 an = cross(sub(b, a), sub(c, a)); // 2 A n
      const Vec3 centroid{(a[0] + b[0] + c[0]) / 3, (a[1] + b[1] + c[1]) / 3,
                          (a[2] + b[2] + c[2]) / 3};
      enclosed += dot(centroid, an) / 6;
      if (name == "aqueous_wall")
        aqueous -= 4 * dot(sub(centroid, x0), an) / 6;
      if (name == "vitreous_wall")
        vitreous -= 4 * dot(sub(centroid, x0), an) / 6;
    }
  }
  std::size_t bad_interior = 0, bad_boundary = 0, orphan_boundary = 0;
  for (const auto& [face, count] : tet_faces) {
    const auto it = boundary.find(face);
    const int groups = it == boundary.end() ? 0 : it->second;
    if (count == 2)
      bad_interior += groups != 0;
    else
      bad_boundary += !(count == 1 && groups == 1);
  }
  for (const auto& [face, groups] : boundary)
    orphan_boundary += tet_faces.count(face) == 0 || tet_faces.at(face) != 1;
  EXPECT_EQ(bad_interior, 0u);
  EXPECT_EQ(bad_boundary, 0u);
  EXPECT_EQ(orphan_boundary, 0u);
  EXPECT_NEAR(enclosed / volume, 1, 1e-12);

  report.aqueous_error = aqueous / d.aqueous_volume - 1;
  report.vitreous_error = vitreous / d.vitreous_volume - 1;
  EXPECT_LT(std::abs(report.aqueous_error), 0.01);
  EXPECT_LT(std::abs(report.vitreous_error), 0.01);

  report.min_quality = min_quality();
  EXPECT_GT(report.min_quality, 0);
  gmsh::model::remove();
  return report;
}

class EyeInternalMesh : public GmshSuite, public ::testing::WithParamInterface<int>
{
};

TEST_P(EyeInternalMesh, ConformsAndConverges)
{
  const Geometry g = internal_geometry();
  Refinement r = nct::scene::defaults<Refinement>();
  r.layers = GetParam();
  const InternalReport coarse = check_internal_mesh(g, r);
  const InternalReport fine = check_internal_mesh(g, halved(r));
  for (const auto& [label, m] : {std::pair{"sizes", coarse}, std::pair{"sizes / 2", fine}})
    std::cout << "[ internal ] layers " << GetParam() << ", " << label << ": " << m.nodes
              << " nodes, " << m.tets << " tets, " << m.ring_nodes << " shared ring nodes, aqueous error "
              << 100 * m.aqueous_error << " %, vitreous error " << 100 * m.vitreous_error
              << " %, min ICN " << m.min_quality << "\n";
  EXPECT_LT(std::abs(fine.aqueous_error), std::abs(coarse.aqueous_error));
  EXPECT_LT(std::abs(fine.vitreous_error), std::abs(coarse.vitreous_error));
}

INSTANTIATE_TEST_SUITE_P(Layers, EyeInternalMesh, ::testing::Values(3, 5));

TEST_F(EyeMeshDefault, InternalStructuresReport)
{
  const auto start = std::chrono::steady_clock::now();
  nct::eye::build(internal_geometry(), nct::scene::defaults<Refinement>());
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
  std::vector<std::size_t> tets, nodes, tags;
  std::vector<double> xyz, uvw;
  gmsh::model::mesh::getElementsByType(4, tets, nodes);
  gmsh::model::mesh::getNodes(tags, xyz, uvw, -1, -1, false, false);
  const double q = min_quality();
  std::cout << "[ default  ] internal structures: " << tags.size() << " nodes, " << tets.size()
            << " tets, min ICN " << q << ", build() " << 1e3 * seconds << " ms\n";
  EXPECT_GT(q, 0);
  gmsh::model::remove();
}

TEST_F(EyeMeshDefault, RejectsBadLensSize)
{
  Refinement r = nct::scene::defaults<Refinement>();
  r.size_lens = 0;
  EXPECT_NO_THROW(nct::eye::build(nct::scene::defaults<Geometry>(), r)); // unused without internal structures
  gmsh::model::remove();
  try {
    nct::eye::build(internal_geometry(), r);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("mesh.size_lens"), std::string::npos) << e.what();
  }
}

} // namespace
