// The idealised eye: derived shape, fibres and the layered quarter-eye mesh.
#include "eye/geometry.h"

#include <gmsh.h>

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <cstdint>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

namespace nct::eye
{
namespace
{

using Vec3 = std::array<double, 3>;

/// A point (r, y) of the meridian half-plane.
struct Meridian
{
  double r;
  double y;
};

/// Throws std::invalid_argument naming `key`, its value and what is accepted.
[[noreturn]] void reject(const std::string& key, double value,
                         const std::string& accepted)
{
  std::ostringstream message;
  message << key << " = " << value << " is impossible: " << accepted;
  throw std::invalid_argument(message.str());
}

/// A meridian profile parametrised by arc length s from the apex: an arc
/// about (0, cap_centre_y) down to the junction, then an arc about the
/// origin down to the cut plane.
class Profile
{
public:
  Profile(double cap_centre_y, double cap_radius, Meridian junction,
          double sclera_radius, double cut_y)
    : cap_centre_y_(cap_centre_y), cap_radius_(cap_radius),
      sclera_radius_(sclera_radius), cut_y_(cut_y),
      junction_angle_(std::atan2(junction.r, junction.y)),
      junction_s_(cap_radius * std::atan2(junction.r, junction.y - cap_centre_y)),
      length_(junction_s_ + sclera_radius * (std::acos(cut_y / sclera_radius)
                                             - junction_angle_))
  {
  }

  /// Arc length from the apex to the junction.
  double junction_s() const { return junction_s_; }

  /// Arc length from the apex to the cut plane.
  double length() const { return length_; }

  /// The point at arc length s; exactly on the cut plane for s >= length().
  Meridian at(double s) const
  {
    if (s <= junction_s_) {
      const double a = s / cap_radius_;
      return {cap_radius_ * std::sin(a), cap_centre_y_ + cap_radius_ * std::cos(a)};
    }
    if (s >= length_)
      return {std::sqrt(sclera_radius_ * sclera_radius_ - cut_y_ * cut_y_), cut_y_};
    const double theta = junction_angle_ + (s - junction_s_) / sclera_radius_;
    return {sclera_radius_ * std::sin(theta), sclera_radius_ * std::cos(theta)};
  }

  /// The unit tangent (dr/ds, dy/ds) at arc length s.
  Meridian tangent(double s) const
  {
    const double a = s <= junction_s_ ? s / cap_radius_
                                      : junction_angle_ + (s - junction_s_) / sclera_radius_;
    return {std::cos(a), -std::sin(a)};
  }

private:
  double cap_centre_y_, cap_radius_, sclera_radius_, cut_y_;
  double junction_angle_, junction_s_, length_;
};

/// The validated shape: derived numbers, both profiles and the part bounds.
struct Layout
{
  Derived derived;
  Profile anterior;
  Profile posterior;
  double limbus_begin; ///< s where the cornea ends
  double limbus_end;   ///< s where the sclera begins

  /// The posterior arc length matched to the anterior arc length s.
  double matched(double s) const
  {
    const double sl = anterior.junction_s(), S = anterior.length();
    const double psl = posterior.junction_s(), pS = posterior.length();
    if (s >= S)
      return pS;
    if (s <= sl)
      return s / sl * psl;
    return psl + (s - sl) / (S - sl) * (pS - psl);
  }

  /// The slope ds'/ds of the matching at s.
  double matched_rate(double s) const
  {
    const double sl = anterior.junction_s(), psl = posterior.junction_s();
    return s <= sl ? psl / sl : (posterior.length() - psl) / (anterior.length() - sl);
  }
};

/// Whole-revolution volume between the planes y0 < y1 inside the sphere of
/// radius R centred at (0, c, 0): integral of pi (R^2 - (y - c)^2) dy.
double zone_volume(double R, double c, double y0, double y1)
{
  const auto F = [&](double y) { return R * R * y - std::pow(y - c, 3) / 3.0; };
  return std::numbers::pi * (F(y1) - F(y0));
}

/// The y of the anterior corneal sphere's centre (unvalidated).
double anterior_centre_y(const Geometry& g)
{
  const double rl = g.limbus_diameter / 2, Rs = g.sclera_outer_radius;
  const double Ra = g.cornea_anterior_radius;
  return std::sqrt(Rs * Rs - rl * rl) - std::sqrt(Ra * Ra - rl * rl);
}

/// Validates the geometry and derives the layout of the eye.
Layout layout(const Geometry& g)
{
  const double Rs = g.sclera_outer_radius, ts = g.sclera_thickness;
  const double Ra = g.cornea_anterior_radius, Rp = g.cornea_posterior_radius;
  const double tc = g.cornea_central_thickness, rl = g.limbus_diameter / 2;
  if (!(Rs > 0))
    reject("geometry.sclera_outer_radius", Rs, "must be > 0");
  if (!(ts > 0 && ts < Rs))
    reject("geometry.sclera_thickness", ts, "must be in (0, sclera_outer_radius)");
  if (!(Ra > 0))
    reject("geometry.cornea_anterior_radius", Ra, "must be > 0");
  if (!(Rp > 0))
    reject("geometry.cornea_posterior_radius", Rp, "must be > 0");
  if (!(tc > 0))
    reject("geometry.cornea_central_thickness", tc, "must be > 0");
  if (!(rl > 0 && rl < Rs && rl < Ra))
    reject("geometry.limbus_diameter", g.limbus_diameter,
           "must be in (0, 2 min(cornea_anterior_radius, sclera_outer_radius))");

  Derived d{};
  const double Ri = Rs - ts;
  d.junction_anterior_r = rl;
  d.junction_anterior_y = std::sqrt(Rs * Rs - rl * rl);
  d.anterior_centre_y = anterior_centre_y(g);
  d.apex_y = d.anterior_centre_y + Ra;
  const double cp = d.apex_y - tc - Rp;
  d.posterior_centre_y = cp;

  // Posterior junction: r^2 + y^2 = Ri^2 and r^2 + (y - cp)^2 = Rp^2.
  const double yp = (Ri * Ri - Rp * Rp + cp * cp) / (2 * cp);
  const double rp2 = Ri * Ri - yp * yp;
  if (!(std::abs(cp) > 0 && rp2 > 0))
    reject("geometry.cornea_posterior_radius", Rp,
           "the posterior corneal sphere must meet the inner scleral sphere "
           "(radius sclera_outer_radius - sclera_thickness)");
  d.junction_posterior_r = std::sqrt(rp2);
  d.junction_posterior_y = yp;
  if (std::hypot(d.junction_posterior_r, yp - d.anterior_centre_y) >= Ra)
    reject("geometry.cornea_posterior_radius", Rp,
           "the posterior cornea must meet the sclera inside the anterior corneal sphere");

  // Peripheral thickness: first hit of the posterior sphere along the
  // inward anterior normal n from the anterior junction J (J outside it).
  const double nr = rl / Ra, ny = (d.junction_anterior_y - d.anterior_centre_y) / Ra;
  const double dr = rl, dy = d.junction_anterior_y - cp;
  const double dn = dr * nr + dy * ny, dd = dr * dr + dy * dy;
  const double disc = dn * dn - dd + Rp * Rp;
  if (!(dd > Rp * Rp && disc >= 0 && dn - std::sqrt(disc) > 0))
    reject("geometry.cornea_posterior_radius", Rp,
           "the posterior corneal sphere must lie under the anterior junction "
           "(positive peripheral thickness)");
  d.peripheral_thickness = dn - std::sqrt(disc);

  const double top_cut = std::min(d.junction_anterior_y, d.junction_posterior_y);
  if (!(g.cut_y > -Ri && g.cut_y < top_cut)) {
    std::ostringstream range;
    range << "must be in (-(sclera_outer_radius - sclera_thickness), lower junction y) = ("
          << -Ri << ", " << top_cut << ")";
    reject("geometry.cut_y", g.cut_y, range.str());
  }

  d.cavity_volume = zone_volume(Ri, 0, g.cut_y, yp) + zone_volume(Rp, cp, yp, d.apex_y - tc);

  const Profile anterior(d.anterior_centre_y, Ra, {rl, d.junction_anterior_y}, Rs, g.cut_y);
  const Profile posterior(cp, Rp, {d.junction_posterior_r, yp}, Ri, g.cut_y);
  const double sl = anterior.junction_s(), w = g.limbus_width;
  if (!(w > 0 && w / 2 < sl && sl + w / 2 < anterior.length())) {
    std::ostringstream range;
    range << "must be in (0, " << 2 * std::min(sl, anterior.length() - sl)
          << ") so that cornea and sclera keep some anterior arc length";
    reject("geometry.limbus_width", w, range.str());
  }
  const Layout e{d, anterior, posterior, sl - w / 2, sl + w / 2};

  // The sweep X(s, t) = A + t (P - A) must not fold. Its meridian Jacobian
  // dX/ds x (P - A) is linear in t and -tc < 0 at the apex, so it must be
  // negative on both profiles; sampled at the midpoints of each arc piece.
  const int samples = 64;
  for (const auto& [s0, s1] : {std::pair{0.0, sl}, std::pair{sl, anterior.length()}})
    for (int i = 0; i < samples; ++i) {
      const double s = s0 + (i + 0.5) / samples * (s1 - s0), ps = e.matched(s);
      const Meridian a = anterior.at(s), p = posterior.at(ps);
      const Meridian da = anterior.tangent(s), dp = posterior.tangent(ps);
      const double sr = p.r - a.r, sy = p.y - a.y, rate = e.matched_rate(s);
      if (!(da.r * sy - da.y * sr < 0 && rate * (dp.r * sy - dp.y * sr) < 0)) {
        std::ostringstream message;
        message << "geometry: the layers between the anterior and posterior surfaces fold near "
                   "(r, y) = ("
                << a.r << ", " << a.y << "); geometry.cornea_central_thickness and "
                << "geometry.sclera_thickness are too large for the radii";
        throw std::invalid_argument(message.str());
      }
    }
  return e;
}

/// Sets gmsh numeric options, restoring the previous values on destruction.
class OptionGuard
{
public:
  OptionGuard() = default;
  OptionGuard(const OptionGuard&) = delete;
  OptionGuard& operator=(const OptionGuard&) = delete;
  ~OptionGuard()
  {
    for (auto it = saved_.rbegin(); it != saved_.rend(); ++it)
      gmsh::option::setNumber(it->first, it->second);
  }

  void set(const std::string& name, double value)
  {
    double old = 0;
    gmsh::option::getNumber(name, old);
    saved_.emplace_back(name, old);
    gmsh::option::setNumber(name, value);
  }

private:
  std::vector<std::pair<std::string, double>> saved_;
};

/// Boundary groups; the values are the physical tags.
enum class Group { anterior_cornea = 1, anterior_sclera, cavity_wall, symmetry_x, symmetry_z, fixed };

/// The meshed chart: per node the arc length s and (cos, sin) of phi; per
/// triangle its sorted node indices, chart orientation and part.
struct Chart
{
  std::vector<double> s, cos_phi, sin_phi;
  std::vector<std::array<std::size_t, 3>> triangles;
  std::vector<int> orientation; ///< +1 if the sorted triangle is counter-clockwise
  std::vector<Part> part;
  std::unordered_map<std::uint64_t, Group> side_edges; ///< boundary edge key -> group
};

/// Key of the undirected chart edge (a, b).
std::uint64_t edge_key(std::size_t a, std::size_t b)
{
  return (std::uint64_t(std::min(a, b)) << 32) | std::uint64_t(std::max(a, b));
}

/// Meshes the quarter-disc chart of radius S in a temporary gmsh model,
/// with rings at the part bounds and the junction, and reads it back.
Chart mesh_chart(const Layout& e, const Refinement& ref)
{
  namespace geo = gmsh::model::geo;
  const std::array<double, 4> radii{e.limbus_begin, e.anterior.junction_s(),
                                    e.limbus_end, e.anterior.length()};
  const std::array<Part, 4> ring_part{Part::cornea, Part::limbus, Part::limbus, Part::sclera};

  // Size: the least over the parts of the part's size plus `gradation`
  // times the distance to the part, so sizes change smoothly (at most
  // 0.3 mm per mm) and never exceed the part's own size inside it.
  const double gradation = 0.3;
  const std::array<double, 3> size{ref.size_cornea, ref.size_limbus, ref.size_sclera};
  const std::array<double, 4> bounds{0, e.limbus_begin, e.limbus_end, e.anterior.length()};
  const auto size_at = [=](int, int, double x, double y, double) {
    const double s = std::hypot(x, y);
    double h = size[0] + gradation * std::max(0.0, s - bounds[1]);
    for (std::size_t p = 1; p < 3; ++p)
      h = std::min(h, size[p] + gradation * std::max({0.0, bounds[p] - s, s - bounds[p + 1]}));
    return h;
  };

  const std::string name = "eye_chart";
  gmsh::model::add(name);
  // Removes the chart model and its size callback however we leave.
  struct Cleanup
  {
    const std::string& name;
    ~Cleanup()
    {
      gmsh::model::setCurrent(name);
      gmsh::model::mesh::removeSizeCallback();
      gmsh::model::remove();
    }
  } cleanup{name};

  const int origin = geo::addPoint(0, 0, 0);
  std::array<int, 4> along_x{}, along_z{}, arcs{}, rings{};
  int last_x = origin, last_z = origin;
  for (std::size_t i = 0; i < radii.size(); ++i) {
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
  for (std::size_t i = 0; i < arcs.size(); ++i) {
    gmsh::model::mesh::getNodes(tags, xyz, uvw, 1, arcs[i], true, false);
    for (std::size_t t : tags)
      chart.s[index.at(t)] = radii[i];
  }

  for (std::size_t i = 0; i < rings.size(); ++i) {
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
      chart.part.push_back(ring_part[i]);
    }
  }

  const auto add_side = [&](int curve, Group group) {
    std::vector<std::size_t> element_tags, node_tags;
    gmsh::model::mesh::getElementsByType(1, element_tags, node_tags, curve);
    for (std::size_t t = 0; t < element_tags.size(); ++t)
      chart.side_edges[edge_key(index.at(node_tags[2 * t]), index.at(node_tags[2 * t + 1]))] = group;
  };
  for (std::size_t i = 0; i < radii.size(); ++i) {
    add_side(along_x[i], Group::symmetry_z);
    add_side(along_z[i], Group::symmetry_x);
  }
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

/// Sweeps the chart through the shell and writes the mesh into a new
/// gmsh model "eye" as discrete entities with physical groups.
void write_eye(const Layout& e, const Chart& chart, int layers)
{
  const std::size_t nc = chart.s.size(), nl = static_cast<std::size_t>(layers);

  // Nodes: tag k nc + v + 1 for chart node v on layer k.
  std::vector<Vec3> x(nc * (nl + 1));
  for (std::size_t v = 0; v < nc; ++v) {
    const Meridian a = e.anterior.at(chart.s[v]);
    const Meridian p = e.posterior.at(e.matched(chart.s[v]));
    for (std::size_t k = 0; k <= nl; ++k) {
      const double t = double(k) / double(nl);
      const double r = a.r + t * (p.r - a.r), y = a.y + t * (p.y - a.y);
      x[k * nc + v] = {r * chart.cos_phi[v], y, r * chart.sin_phi[v]};
    }
  }
  const auto at = [&](std::size_t tag) -> const Vec3& { return x[tag - 1]; };

  // The prism rule's tets (b0,b1,b2,t2), (b0,b1,t1,t2), (b0,t0,t1,t2), the
  // second with t1, t2 swapped so that all three have the orientation of the
  // chart triangle, made positive by swapping the last two nodes of
  // clockwise ones. Each tet's faces are listed outwards (face j opposite
  // node j); those on the boundary go to their group. Each node is put on
  // the lowest-numbered part's volume that uses it (owner).
  std::array<std::vector<std::size_t>, 3> tets;
  std::array<std::vector<std::size_t>, 6> faces;
  std::vector<int> owner(x.size(), 4);
  const std::array<std::array<int, 3>, 4> outward{{{1, 2, 3}, {0, 3, 2}, {0, 1, 3}, {0, 2, 1}}};
  for (std::size_t i = 0; i < chart.triangles.size(); ++i) {
    const auto& v = chart.triangles[i];
    const int part = static_cast<int>(chart.part[i]);
    for (std::size_t k = 0; k < nl; ++k) {
      const auto b = [&](int j) { return k * nc + v[j] + 1; };
      const auto t = [&](int j) { return (k + 1) * nc + v[j] + 1; };
      std::array<Tet, 3> prism{{{b(0), b(1), b(2), t(2)}, {b(0), b(1), t(2), t(1)},
                                {b(0), t(0), t(1), t(2)}}};
      for (Tet& tet : prism) {
        if (chart.orientation[i] < 0)
          std::swap(tet[2], tet[3]);
        if (!(signed_volume(at(tet[0]), at(tet[1]), at(tet[2]), at(tet[3])) > 0)) {
          const Vec3& c = at(tet[0]);
          std::ostringstream message;
          message << "nct::eye::build: inverted tetrahedron near (" << c[0] << ", " << c[1]
                  << ", " << c[2] << "); the sweep folds for this geometry and refinement";
          throw std::runtime_error(message.str());
        }
        tets[part - 1].insert(tets[part - 1].end(), tet.begin(), tet.end());
        for (std::size_t n : tet)
          owner[n - 1] = std::min(owner[n - 1], part);

        for (const auto& f : outward) {
          const std::array<std::size_t, 3> face{tet[f[0]], tet[f[1]], tet[f[2]]};
          std::array<std::size_t, 3> layer{}, node{};
          for (int j = 0; j < 3; ++j) {
            layer[j] = (face[j] - 1) / nc;
            node[j] = (face[j] - 1) % nc;
          }
          Group group;
          if (layer[0] == 0 && layer[1] == 0 && layer[2] == 0)
            group = chart.part[i] == Part::cornea ? Group::anterior_cornea : Group::anterior_sclera;
          else if (layer[0] == nl && layer[1] == nl && layer[2] == nl)
            group = Group::cavity_wall;
          else {
            // A side face spans one chart edge: exactly two distinct chart nodes.
            const std::size_t e0 = node[0], e1 = node[1] != e0 ? node[1] : node[2];
            if (e0 == e1 || (node[2] != e0 && node[2] != e1))
              continue;
            const auto side = chart.side_edges.find(edge_key(e0, e1));
            if (side == chart.side_edges.end())
              continue;
            group = side->second;
          }
          auto& list = faces[static_cast<int>(group) - 1];
          list.insert(list.end(), face.begin(), face.end());
        }
      }
    }
  }

  gmsh::model::add("eye");
  const std::array<std::string, 3> part_names{"cornea", "limbus", "sclera"};
  const std::array<std::string, 6> group_names{"anterior_cornea", "anterior_sclera", "cavity_wall",
                                               "symmetry_x", "symmetry_z", "fixed"};
  for (int p = 1; p <= 3; ++p) {
    gmsh::model::addDiscreteEntity(3, p);
    std::vector<std::size_t> tags;
    std::vector<double> coords;
    for (std::size_t n = 0; n < x.size(); ++n)
      if (owner[n] == p) {
        tags.push_back(n + 1);
        coords.insert(coords.end(), x[n].begin(), x[n].end());
      }
    gmsh::model::mesh::addNodes(3, p, tags, coords);
  }
  std::size_t next = 1;
  const auto add_elements = [&](int entity, int type, const std::vector<std::size_t>& nodes,
                                std::size_t per_element) {
    std::vector<std::size_t> tags(nodes.size() / per_element);
    for (auto& tag : tags)
      tag = next++;
    gmsh::model::mesh::addElementsByType(entity, type, tags, nodes);
  };
  for (int p = 1; p <= 3; ++p) {
    add_elements(p, 4, tets[p - 1], 4);
    gmsh::model::addPhysicalGroup(3, {p}, p);
    gmsh::model::setPhysicalName(3, p, part_names[p - 1]);
  }
  for (int s = 1; s <= 6; ++s) {
    gmsh::model::addDiscreteEntity(2, s);
    add_elements(s, 2, faces[s - 1], 3);
    gmsh::model::addPhysicalGroup(2, {s}, s);
    gmsh::model::setPhysicalName(2, s, group_names[s - 1]);
  }
}

} // namespace

Derived derive(const Geometry& g)
{
  return layout(g).derived;
}

std::array<std::array<double, 3>, 2> fibres(const Geometry& g, Part part,
                                            const std::array<double, 3>& X)
{
  // Projects e onto the plane normal to n and normalises (zero if e || n).
  const auto tangent = [](Vec3 e, const Vec3& n) {
    const double en = e[0] * n[0] + e[1] * n[1] + e[2] * n[2];
    for (int i = 0; i < 3; ++i)
      e[i] -= en * n[i];
    const double len = std::sqrt(e[0] * e[0] + e[1] * e[1] + e[2] * e[2]);
    return len > 1e-12 ? Vec3{e[0] / len, e[1] / len, e[2] / len} : Vec3{0, 0, 0};
  };
  switch (part) {
  case Part::cornea: {
    const double cy = anterior_centre_y(g);
    Vec3 n{X[0], X[1] - cy, X[2]};
    const double len = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    n = len > 0 ? Vec3{n[0] / len, n[1] / len, n[2] / len} : Vec3{0, 1, 0};
    return {tangent({1, 0, 0}, n), tangent({0, 0, 1}, n)};
  }
  case Part::limbus: {
    // e_phi = (-sin phi, 0, cos phi); on the axis take phi = 0, i.e. e_z.
    const double r = std::hypot(X[0], X[2]);
    const Vec3 e_phi = r > 0 ? Vec3{-X[2] / r, 0, X[0] / r} : Vec3{0, 0, 1};
    return {e_phi, Vec3{0, 0, 0}};
  }
  case Part::sclera:
    break;
  }
  return {Vec3{0, 0, 0}, Vec3{0, 0, 0}};
}

void build(const Geometry& g, const Refinement& r)
{
  if (r.layers < 1)
    reject("mesh.layers", r.layers, "must be >= 1");
  if (!(r.size_cornea > 0))
    reject("mesh.size_cornea", r.size_cornea, "must be > 0");
  if (!(r.size_limbus > 0))
    reject("mesh.size_limbus", r.size_limbus, "must be > 0");
  if (!(r.size_sclera > 0))
    reject("mesh.size_sclera", r.size_sclera, "must be > 0");
  const Layout e = layout(g);
  try {
    OptionGuard quiet;
    quiet.set("General.Terminal", 0);
    const Chart chart = mesh_chart(e, r);
    write_eye(e, chart, r.layers);
  } catch (const std::string& message) { // gmsh 4.8 throws its last error as a string
    throw std::runtime_error("nct::eye::build: gmsh failed: " + message);
  }
}

} // namespace nct::eye
