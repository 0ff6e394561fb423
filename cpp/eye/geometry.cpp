// The idealised eye: derived shape, fibres and the layered quarter-eye mesh.
#include "eye/geometry.h"
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

/// The internal structures in the meridian plane, parametrised by the
/// diaphragm's chart radius rho: rho = r in the lens, then linear in the
/// distance along the zonule band to the ring point at rho_max.
struct Diaphragm
{
  bool on = false;
  double lens_r = 0;                  ///< lens radius (equator)
  double front_c = 0, front_R = 0;    ///< anterior lens sphere: centre y, radius
  double back_c = 0, back_R = 0;      ///< posterior lens sphere: centre y, radius
  double front_pole = 0, back_pole = 0; ///< y of the lens poles
  Meridian rim_front{}, rim_back{};   ///< lens equator rim on the two spheres
  Meridian ring{};                    ///< zonule ring point R on the inner sclera
  double ring_s = 0;                  ///< shell chart radius (anterior arc length) of the ring
  double rho_nucleus = 0;             ///< chart radius bounding the nucleus
  double rho_max = 0;                 ///< chart radius of the ring

  /// The anterior (front) profile point at chart radius rho.
  Meridian anterior(double rho) const
  {
    if (rho <= lens_r)
      return {rho, front_c + std::sqrt(front_R * front_R - rho * rho)};
    return toward_ring(rim_front, rho);
  }

  /// The posterior (back) profile point at chart radius rho.
  Meridian posterior(double rho) const
  {
    if (rho <= lens_r)
      return {rho, back_c - std::sqrt(back_R * back_R - rho * rho)};
    return toward_ring(rim_back, rho);
  }

private:
  Meridian toward_ring(Meridian rim, double rho) const
  {
    if (rho >= rho_max)
      return ring;
    const double u = (rho - lens_r) / (rho_max - lens_r);
    return {rim.r + u * (ring.r - rim.r), rim.y + u * (ring.y - rim.y)};
  }
};

/// The validated shape: derived numbers, both profiles and the part bounds.
struct Layout
{
  Derived derived;
  Profile anterior;
  Profile posterior;
  double limbus_begin; ///< s where the cornea ends
  double limbus_end;   ///< s where the sclera begins
  Diaphragm diaphragm{}; ///< internal structures (diaphragm.on) or nothing

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

/// Integral of pi r^2 dy along the straight meridian segment a -> b (signed).
double segment_volume(Meridian a, Meridian b)
{
  return std::numbers::pi * (b.y - a.y) * (a.r * a.r + a.r * b.r + b.r * b.r) / 3;
}

/// Validates the internal structures of g and derives them into e
/// (diaphragm, aqueous and vitreous volumes).
void add_diaphragm(const Geometry& g, Layout& e)
{
  Derived& d = e.derived;
  const double Ri = g.sclera_outer_radius - g.sclera_thickness, Rp = g.cornea_posterior_radius;
  const double cp = d.posterior_centre_y, yp = d.junction_posterior_y;
  const double cavity_top = d.apex_y - g.cornea_central_thickness;
  const double lr = g.lens_diameter / 2;
  if (!(g.anterior_chamber_depth > 0))
    reject("geometry.anterior_chamber_depth", g.anterior_chamber_depth, "must be > 0");
  if (!(g.lens_thickness > 0))
    reject("geometry.lens_thickness", g.lens_thickness, "must be > 0");
  if (!(lr > 0))
    reject("geometry.lens_diameter", g.lens_diameter, "must be > 0");
  if (!(g.lens_anterior_radius > lr))
    reject("geometry.lens_anterior_radius", g.lens_anterior_radius,
           "must exceed lens_diameter / 2 (the sphere must reach the lens equator)");
  if (!(g.lens_posterior_radius > lr))
    reject("geometry.lens_posterior_radius", g.lens_posterior_radius,
           "must exceed lens_diameter / 2 (the sphere must reach the lens equator)");
  if (!(g.lens_nucleus_fraction > 0 && g.lens_nucleus_fraction < 1))
    reject("geometry.lens_nucleus_fraction", g.lens_nucleus_fraction, "must be in (0, 1)");
  if (!(g.ciliary_offset > 0))
    reject("geometry.ciliary_offset", g.ciliary_offset, "must be > 0");

  Diaphragm m;
  m.on = true;
  m.lens_r = lr;
  m.front_pole = cavity_top - g.anterior_chamber_depth;
  m.back_pole = m.front_pole - g.lens_thickness;
  m.front_R = g.lens_anterior_radius;
  m.front_c = m.front_pole - m.front_R;
  m.back_R = g.lens_posterior_radius;
  m.back_c = m.back_pole + m.back_R;
  m.rim_front = {lr, m.front_c + std::sqrt(m.front_R * m.front_R - lr * lr)};
  m.rim_back = {lr, m.back_c - std::sqrt(m.back_R * m.back_R - lr * lr)};
  if (!(m.rim_front.y > m.rim_back.y)) {
    std::ostringstream accepted;
    accepted << "the lens rim at r = geometry.lens_diameter / 2 must have a positive thickness "
                "(it is "
             << m.rim_front.y - m.rim_back.y
             << "): increase lens_thickness or the lens radii, or decrease lens_diameter";
    reject("geometry.lens_thickness", g.lens_thickness, accepted.str());
  }

  // The ring point: ciliary_offset along the inner sphere behind the
  // posterior junction; the posterior profile is parametrised by arc length.
  const double ring_ps = e.posterior.junction_s() + g.ciliary_offset;
  if (!(ring_ps < e.posterior.length())) {
    std::ostringstream accepted;
    accepted << "the zonule ring must lie above the cut plane: ciliary_offset < "
             << e.posterior.length() - e.posterior.junction_s();
    reject("geometry.ciliary_offset", g.ciliary_offset, accepted.str());
  }
  m.ring = e.posterior.at(ring_ps);
  if (!(m.ring.r > lr))
    reject("geometry.ciliary_offset", g.ciliary_offset,
           "the zonule ring must lie outside the lens equator (ring radius > lens_diameter / 2)");
  // Invert the matching s -> s' (linear beyond the junction).
  const double sl = e.anterior.junction_s(), S = e.anterior.length();
  const double psl = e.posterior.junction_s(), pS = e.posterior.length();
  m.ring_s = sl + g.ciliary_offset * (S - sl) / (pS - psl);
  m.rho_nucleus = g.lens_nucleus_fraction * lr;
  const Meridian mid{lr, (m.rim_front.y + m.rim_back.y) / 2};
  m.rho_max = lr + std::hypot(m.ring.r - mid.r, m.ring.y - mid.y);

  // The lens and the band must lie strictly inside the cavity (the band
  // ends on its wall at the ring point).
  const auto inside = [&](Meridian p) {
    if (!(p.y > g.cut_y && p.y < cavity_top))
      return false;
    const double w2 = p.y >= yp ? Rp * Rp - (p.y - cp) * (p.y - cp) : Ri * Ri - p.y * p.y;
    return p.r * p.r < w2;
  };
  const int samples = 256;
  for (int i = 0; i <= samples; ++i) {
    const double rho = lr * i / samples;
    if (!inside(m.anterior(rho)))
      reject("geometry.anterior_chamber_depth", g.anterior_chamber_depth,
             "the anterior lens surface must lie inside the cavity, behind the posterior cornea");
    if (!inside(m.posterior(rho)))
      reject("geometry.lens_thickness", g.lens_thickness,
             "the posterior lens surface must lie inside the cavity, above the cut plane");
  }
  for (int i = 0; i < samples; ++i) {
    const double rho = lr + (m.rho_max - lr) * i / samples;
    if (!inside(m.anterior(rho)) || !inside(m.posterior(rho)))
      reject("geometry.ciliary_offset", g.ciliary_offset,
             "the zonule band from the lens equator to the ring must not cross the cornea "
             "or the sclera");
  }
  e.diaphragm = m;

  // Chamber volumes: pi r^2 dy along their counter-clockwise meridian
  // boundaries (r right, y up); the axis and the cut plane add nothing.
  d.aqueous_volume = zone_volume(m.front_R, m.front_c, m.front_pole, m.rim_front.y)
                     + segment_volume(m.rim_front, m.ring) + zone_volume(Ri, 0, m.ring.y, yp)
                     + zone_volume(Rp, cp, yp, cavity_top);
  d.vitreous_volume = zone_volume(Ri, 0, g.cut_y, m.ring.y) + segment_volume(m.ring, m.rim_back)
                      + zone_volume(m.back_R, m.back_c, m.rim_back.y, m.back_pole);
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
  Layout e{d, anterior, posterior, sl - w / 2, sl + w / 2};

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
  if (g.internal_structures)
    add_diaphragm(g, e);
  return e;
}

using meshio::OptionGuard;

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
const std::array<std::string, part_count> part_names{
    "cornea", "limbus", "sclera", "lens_cortex", "lens_nucleus", "zonule", "vitreous_membrane"};

/// Adds elements of one gmsh type to an entity of the current model,
/// tagged consecutively from `next` on.
void add_elements(std::size_t& next, int entity, int type, const std::vector<std::size_t>& nodes,
                  std::size_t per_element)
{
  std::vector<std::size_t> tags(nodes.size() / per_element);
  for (auto& tag : tags)
    tag = next++;
  gmsh::model::mesh::addElementsByType(entity, type, tags, nodes);
}

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
void build_eye(const Layout& e, const Refinement& ref)
{
  const Diaphragm& dia = e.diaphragm;
  const std::size_t nl = static_cast<std::size_t>(ref.layers);

  // Shell chart: rings at the part bounds, the junction and the zonule ring.
  // Size: the least over the parts of the part's size plus `gradation`
  // times the distance to the part, so sizes change smoothly (at most
  // 0.3 mm per mm) and never exceed the part's own size inside it.
  const double gradation = 0.3;
  const std::array<double, 3> size{ref.size_cornea, ref.size_limbus, ref.size_sclera};
  const std::array<double, 4> bounds{0, e.limbus_begin, e.limbus_end, e.anterior.length()};
  ChartSpec shell_spec;
  shell_spec.size = [=](double s) {
    double h = size[0] + gradation * std::max(0.0, s - bounds[1]);
    for (std::size_t p = 1; p < 3; ++p)
      h = std::min(h, size[p] + gradation * std::max({0.0, bounds[p] - s, s - bounds[p + 1]}));
    return h;
  };
  shell_spec.radii = {e.limbus_begin, e.anterior.junction_s(), e.limbus_end, e.anterior.length()};
  shell_spec.fixed_outer = true;
  if (dia.on) {
    // The ring arc, merged with an existing one it (nearly) coincides with.
    auto& radii = shell_spec.radii;
    const double tol = 1e-9 * e.anterior.length();
    auto it = std::find_if(radii.begin(), radii.end(),
                           [&](double r) { return std::abs(r - dia.ring_s) < tol; });
    if (it == radii.end())
      it = radii.insert(std::upper_bound(radii.begin(), radii.end(), dia.ring_s), dia.ring_s);
    shell_spec.ring_arc = static_cast<int>(it - radii.begin());
    const double chart_arc = std::numbers::pi / 2 * dia.ring_s;
    shell_spec.ring_points =
        1 + std::max(2, static_cast<int>(std::ceil(chart_arc / shell_spec.size(dia.ring_s))));
  }
  const Chart shell = mesh_chart(shell_spec);
  std::vector<Part> shell_part;
  for (std::size_t i = 0; i < shell_spec.radii.size(); ++i) {
    const double lo = i > 0 ? shell_spec.radii[i - 1] : 0, mid = (lo + shell_spec.radii[i]) / 2;
    shell_part.push_back(mid < e.limbus_begin ? Part::cornea
                         : mid < e.limbus_end ? Part::limbus
                                              : Part::sclera);
  }

  // Shell nodes: tag k nc + v + 1 for chart node v on layer k.
  const std::size_t nc = shell.s.size();
  Assembly mesh;
  mesh.x.resize(nc * (nl + 1));
  for (std::size_t v = 0; v < nc; ++v) {
    const Meridian a = e.anterior.at(shell.s[v]);
    const Meridian p = e.posterior.at(e.matched(shell.s[v]));
    for (std::size_t k = 0; k <= nl; ++k) {
      const double t = double(k) / double(nl);
      mesh.x[k * nc + v] = place({a.r + t * (p.r - a.r), a.y + t * (p.y - a.y)},
                                 shell.cos_phi[v], shell.sin_phi[v]);
    }
  }
  mesh.owner.assign(mesh.x.size(), part_count + 1);
  sweep(mesh, Body{shell, nl, [nc](std::size_t k, std::size_t v) { return k * nc + v + 1; },
                   [](std::size_t) { return false; },
                   [&](std::size_t i, std::size_t) { return shell_part[shell.annulus[i]]; },
                   [&](std::size_t i, bool posterior) {
                     if (!posterior)
                       return shell_part[shell.annulus[i]] == Part::cornea ? Group::anterior_cornea
                                                                           : Group::anterior_sclera;
                     if (!dia.on)
                       return Group::cavity_wall;
                     return shell.annulus[i] <= shell_spec.ring_arc ? Group::aqueous_wall
                                                                    : Group::vitreous_wall;
                   }});

  if (dia.on) {
    // Diaphragm chart: rings at the nucleus bound, the lens equator and the
    // ring, whose arc has the shell ring's points; the size grades linearly
    // along the band from size_lens to the ring's node spacing.
    const int m = shell_spec.ring_points;
    const double ring_h = std::numbers::pi / 2 * dia.rho_max / (m - 1);
    ChartSpec spec;
    spec.radii = {dia.rho_nucleus, dia.lens_r, dia.rho_max};
    spec.ring_arc = 2;
    spec.ring_points = m;
    const double lens_h = ref.size_lens, lr = dia.lens_r, band = dia.rho_max - dia.lens_r;
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
        mesh.x[base + k * nf + free_index[v]] = place(
            {a.r + t * (p.r - a.r), a.y + t * (p.y - a.y)}, chart.cos_phi[v], chart.sin_phi[v]);
      }
    }
    const std::size_t quarter = nl / 4;
    sweep(mesh,
          Body{chart, nl,
               [&](std::size_t k, std::size_t v) {
                 return ring_of[v] != std::size_t(-1) ? nl * nc + ring_of[v] + 1
                                                      : base + k * nf + free_index[v] + 1;
               },
               [&](std::size_t v) { return ring_of[v] != std::size_t(-1); },
               [&](std::size_t i, std::size_t k) {
                 const int annulus = chart.annulus[i];
                 if (annulus == 2)
                   return nl > 1 && k + 1 == nl ? Part::vitreous_membrane : Part::zonule;
                 if (annulus == 0 && k >= quarter && k < nl - quarter)
                   return Part::lens_nucleus;
                 return Part::lens_cortex;
               },
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

/// Writes the eye's section into a new gmsh model "eye": the nodes, the
/// triangles by part (3 parts, or all with the internal structures) and
/// the boundary segments by group.
void write_section(const std::vector<std::size_t>& tags, const std::vector<double>& coords,
                   const std::array<std::vector<std::size_t>, part_count>& triangles,
                   const std::array<std::vector<std::size_t>, group_count>& segments,
                   bool internal_structures)
{
  gmsh::model::add("eye");
  gmsh::model::addDiscreteEntity(2, 1);
  gmsh::model::mesh::addNodes(2, 1, tags, coords);
  std::size_t next = 1;
  for (int p = 1; p <= (internal_structures ? part_count : 3); ++p) {
    if (p > 1)
      gmsh::model::addDiscreteEntity(2, p);
    add_elements(next, p, 2, triangles[p - 1], 3);
    gmsh::model::addPhysicalGroup(2, {p}, p);
    gmsh::model::setPhysicalName(2, p, part_names[p - 1]);
  }
  std::vector<std::pair<Group, const char*>> groups{
      {Group::anterior_cornea, "anterior_cornea"}, {Group::anterior_sclera, "anterior_sclera"},
      {Group::symmetry_x, "axis"}, {Group::fixed, "fixed"}};
  if (internal_structures)
    groups.insert(groups.end(), {{Group::aqueous_wall, "aqueous_wall"},
                                 {Group::vitreous_wall, "vitreous_wall"}});
  else
    groups.emplace_back(Group::cavity_wall, "cavity_wall");
  for (auto [group, name] : groups) {
    const int g = static_cast<int>(group);
    gmsh::model::addDiscreteEntity(1, g);
    add_elements(next, g, 1, segments[g - 1], 2);
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
void build_eye_section(const Layout& e, const Refinement& ref)
{
  const Diaphragm& dia = e.diaphragm;
  const std::size_t nl = static_cast<std::size_t>(ref.layers);
  // The chart: nodes in s, uniform within each piece between the part
  // bounds, the junction and the zonule ring, at the piece's part's size.
  std::vector<double> bounds{0, e.limbus_begin, e.anterior.junction_s(), e.limbus_end,
                             e.anterior.length()};
  if (dia.on) {
    const double tol = 1e-9 * e.anterior.length();
    if (std::none_of(bounds.begin(), bounds.end(),
                     [&](double b) { return std::abs(b - dia.ring_s) < tol; }))
      bounds.insert(std::upper_bound(bounds.begin(), bounds.end(), dia.ring_s), dia.ring_s);
  }
  const auto part_at = [&](double s) {
    return s < e.limbus_begin ? Part::cornea : s < e.limbus_end ? Part::limbus : Part::sclera;
  };
  const auto size_of = [&](Part p) {
    return p == Part::cornea ? ref.size_cornea : p == Part::limbus ? ref.size_limbus
                                                                   : ref.size_sclera;
  };
  const std::vector<double> chart
      = chart_nodes(bounds, [&](double a, double b) { return size_of(part_at((a + b) / 2)); });
  const std::size_t nc = chart.size();
  std::size_t ring = nc;
  if (dia.on)
    ring = static_cast<std::size_t>(
        std::min_element(chart.begin(), chart.end(),
                         [&](double a, double b) {
                           return std::abs(a - dia.ring_s) < std::abs(b - dia.ring_s);
                         })
        - chart.begin());

  // Nodes: tag k nc + j + 1 for chart node j on layer k (k = 0 anterior).
  std::vector<double> coords;
  std::vector<std::size_t> tags;
  for (std::size_t k = 0; k <= nl; ++k)
    for (std::size_t j = 0; j < nc; ++j) {
      const Meridian a = e.anterior.at(chart[j]), p = e.posterior.at(e.matched(chart[j]));
      const double t = double(k) / double(nl);
      // The axis exactly: r = 0 at the apex on every layer.
      coords.insert(coords.end(), {j == 0 ? 0.0 : a.r + t * (p.r - a.r), a.y + t * (p.y - a.y),
                                   0.0});
      tags.push_back(k * nc + j + 1);
    }
  const auto node = [nc](std::size_t k, std::size_t j) { return k * nc + j + 1; };

  // Triangles by part, counter-clockwise in (r, y); boundary segments by
  // group, in the solid's counter-clockwise sense. s (and rho) run
  // outwards along the profile (clockwise in (r, y)), t inwards.
  std::array<std::vector<std::size_t>, part_count> triangles;
  std::array<std::vector<std::size_t>, group_count> segments;
  const auto add_segment = [&](Group g, std::size_t a, std::size_t b) {
    auto& list = segments[static_cast<int>(g) - 1];
    list.insert(list.end(), {a, b});
  };
  // The quadrilateral (a, b, c, d) of a sweep: a, b on layer k; d, c on k + 1.
  const auto add_cell = [&](Part part, std::size_t a, std::size_t b, std::size_t c,
                            std::size_t d) {
    auto& cells = triangles[static_cast<int>(part) - 1];
    cells.insert(cells.end(), {a, d, b});
    if (b != c)
      cells.insert(cells.end(), {b, d, c});
  };
  for (std::size_t j = 0; j + 1 < nc; ++j) {
    const Part part = part_at((chart[j] + chart[j + 1]) / 2);
    for (std::size_t k = 0; k < nl; ++k)
      add_cell(part, node(k, j), node(k, j + 1), node(k + 1, j + 1), node(k + 1, j));
    add_segment(part == Part::cornea ? Group::anterior_cornea : Group::anterior_sclera,
                node(0, j + 1), node(0, j));
    add_segment(!dia.on ? Group::cavity_wall
                : j < ring ? Group::aqueous_wall
                           : Group::vitreous_wall,
                node(nl, j), node(nl, j + 1));
  }
  for (std::size_t k = 0; k < nl; ++k) {
    add_segment(Group::symmetry_x, node(k, 0), node(k + 1, 0));
    add_segment(Group::fixed, node(k + 1, nc - 1), node(k, nc - 1));
  }

  if (dia.on) {
    // The diaphragm's chart in rho: the nucleus' bound, the lens equator,
    // the ring; size_lens in the lens, along the band the mean of it and
    // the shell's spacing at the ring. Its last node is the ring: the
    // shell's posterior node there, on every layer.
    const double ring_h = std::max(chart[ring] - chart[ring - 1],
                                   ring + 1 < nc ? chart[ring + 1] - chart[ring] : 0.0);
    const std::vector<double> rho = chart_nodes(
        {0, dia.rho_nucleus, dia.lens_r, dia.rho_max},
        [&](double a, double) { return a < dia.lens_r ? ref.size_lens : (ref.size_lens + ring_h) / 2; });
    const std::size_t nd = rho.size(), base = (nl + 1) * nc;
    const auto dnode = [&](std::size_t k, std::size_t v) {
      return v + 1 == nd ? node(nl, ring) : base + k * (nd - 1) + v + 1;
    };
    for (std::size_t k = 0; k <= nl; ++k)
      for (std::size_t v = 0; v + 1 < nd; ++v) {
        const Meridian a = dia.anterior(rho[v]), p = dia.posterior(rho[v]);
        const double t = double(k) / double(nl);
        coords.insert(coords.end(), {v == 0 ? 0.0 : a.r + t * (p.r - a.r), a.y + t * (p.y - a.y),
                                     0.0});
        tags.push_back(dnode(k, v));
      }
    const std::size_t quarter = nl / 4;
    for (std::size_t v = 0; v + 1 < nd; ++v) {
      const double mid = (rho[v] + rho[v + 1]) / 2;
      for (std::size_t k = 0; k < nl; ++k) {
        const Part part = mid < dia.rho_nucleus && k >= quarter && k < nl - quarter
                              ? Part::lens_nucleus
                          : mid < dia.lens_r              ? Part::lens_cortex
                          : nl > 1 && k + 1 == nl ? Part::vitreous_membrane
                                                  : Part::zonule;
        add_cell(part, dnode(k, v), dnode(k, v + 1), dnode(k + 1, v + 1), dnode(k + 1, v));
      }
      add_segment(Group::aqueous_wall, dnode(0, v + 1), dnode(0, v));
      add_segment(Group::vitreous_wall, dnode(nl, v), dnode(nl, v + 1));
    }
    for (std::size_t k = 0; k < nl; ++k)
      add_segment(Group::symmetry_x, dnode(k, 0), dnode(k + 1, 0));
  }

  write_section(tags, coords, triangles, segments, dia.on);
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
  case Part::lens_cortex:
  case Part::lens_nucleus:
  case Part::zonule:
  case Part::vitreous_membrane:
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
  if (g.internal_structures && !(r.size_lens > 0))
    reject("mesh.size_lens", r.size_lens, "must be > 0");
  const Layout e = layout(g);
  try {
    OptionGuard quiet;
    quiet.set("General.Terminal", 0);
    build_eye(e, r);
  } catch (const std::string& message) { // gmsh 4.8 throws its last error as a string
    throw std::runtime_error("nct::eye::build: gmsh failed: " + message);
  }
}

void build_section(const Geometry& g, const Refinement& r)
{
  if (r.layers < 1)
    reject("mesh.layers", r.layers, "must be >= 1");
  for (auto [key, h] : {std::pair{"mesh.size_cornea", r.size_cornea},
                        {"mesh.size_limbus", r.size_limbus}, {"mesh.size_sclera", r.size_sclera}})
    if (!(h > 0))
      reject(key, h, "must be > 0");
  if (g.internal_structures && !(r.size_lens > 0))
    reject("mesh.size_lens", r.size_lens, "must be > 0");
  const Layout e = layout(g);
  try {
    build_eye_section(e, r);
  } catch (const std::string& message) { // gmsh 4.8 throws its last error as a string
    throw std::runtime_error("nct::eye::build_section: gmsh failed: " + message);
  }
}

} // namespace nct::eye
