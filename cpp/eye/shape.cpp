// The idealised eye's analytic shape: the derived numbers, the validated
// shape the meshers use and the fibres.
#include "eye/shape.h"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <sstream>
#include <stdexcept>
#include <string>
#include <utility>

namespace nct::eye
{
namespace detail
{

void reject(const std::string& key, double value, const std::string& accepted)
{
  std::ostringstream message;
  message << key << " = " << value << " is impossible: " << accepted;
  throw std::invalid_argument(message.str());
}

namespace
{

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

/// Throws for the first key of the internal structures that is impossible
/// on its own.
void check_diaphragm_keys(const Geometry& g)
{
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
}

/// The lens and the zonule ring of g in the shell `shape`; throws if the
/// lens rim has no thickness or the ring lies below the cut plane or
/// inside the lens equator.
Diaphragm place_diaphragm(const Geometry& g, const Shape& shape)
{
  const double cavity_top = shape.derived.apex_y - g.cornea_central_thickness;
  const double lr = g.lens_diameter / 2;
  Diaphragm dia;
  dia.on = true;
  dia.lens_radius = lr;
  dia.front_pole = cavity_top - g.anterior_chamber_depth;
  dia.back_pole = dia.front_pole - g.lens_thickness;
  dia.front_radius = g.lens_anterior_radius;
  dia.front_centre_y = dia.front_pole - dia.front_radius;
  dia.back_radius = g.lens_posterior_radius;
  dia.back_centre_y = dia.back_pole + dia.back_radius;
  dia.rim_front
      = {lr, dia.front_centre_y + std::sqrt(dia.front_radius * dia.front_radius - lr * lr)};
  dia.rim_back = {lr, dia.back_centre_y - std::sqrt(dia.back_radius * dia.back_radius - lr * lr)};
  if (!(dia.rim_front.y > dia.rim_back.y)) {
    std::ostringstream accepted;
    accepted << "the lens rim at r = geometry.lens_diameter / 2 must have a positive thickness "
                "(it is "
             << dia.rim_front.y - dia.rim_back.y
             << "): increase lens_thickness or the lens radii, or decrease lens_diameter";
    reject("geometry.lens_thickness", g.lens_thickness, accepted.str());
  }

  // The ring point: ciliary_offset along the inner sphere behind the
  // posterior junction; the posterior profile is parametrised by arc length.
  const Profile &anterior = shape.anterior, &posterior = shape.posterior;
  const double ring_ps = posterior.junction_s() + g.ciliary_offset;
  if (!(ring_ps < posterior.length())) {
    std::ostringstream accepted;
    accepted << "the zonule ring must lie above the cut plane: ciliary_offset < "
             << posterior.length() - posterior.junction_s();
    reject("geometry.ciliary_offset", g.ciliary_offset, accepted.str());
  }
  dia.ring = posterior.at(ring_ps);
  if (!(dia.ring.r > lr))
    reject("geometry.ciliary_offset", g.ciliary_offset,
           "the zonule ring must lie outside the lens equator (ring radius > lens_diameter / 2)");
  // Invert the matching s -> s' (linear beyond the junction).
  const double sl = anterior.junction_s(), S = anterior.length();
  const double psl = posterior.junction_s(), pS = posterior.length();
  dia.ring_s = sl + g.ciliary_offset * (S - sl) / (pS - psl);
  dia.rho_nucleus = g.lens_nucleus_fraction * lr;
  const Meridian mid{lr, (dia.rim_front.y + dia.rim_back.y) / 2};
  dia.rho_ring = lr + std::hypot(dia.ring.r - mid.r, dia.ring.y - mid.y);
  return dia;
}

/// Throws if the lens or the zonule band leaves the cavity: they must lie
/// strictly inside it (the band ends on its wall at the ring point).
void check_diaphragm_in_cavity(const Geometry& g, const Derived& d, const Diaphragm& dia)
{
  const double Ri = g.sclera_outer_radius - g.sclera_thickness, Rp = g.cornea_posterior_radius;
  const double cp = d.posterior_centre_y, yp = d.junction_posterior_y;
  const double cavity_top = d.apex_y - g.cornea_central_thickness;
  const double lr = dia.lens_radius;
  const auto inside = [&](Meridian p) {
    if (!(p.y > g.cut_y && p.y < cavity_top))
      return false;
    const double w2 = p.y >= yp ? Rp * Rp - (p.y - cp) * (p.y - cp) : Ri * Ri - p.y * p.y;
    return p.r * p.r < w2;
  };
  const int samples = 256;
  for (int i = 0; i <= samples; ++i) {
    const double rho = lr * i / samples;
    if (!inside(dia.anterior(rho)))
      reject("geometry.anterior_chamber_depth", g.anterior_chamber_depth,
             "the anterior lens surface must lie inside the cavity, behind the posterior cornea");
    if (!inside(dia.posterior(rho)))
      reject("geometry.lens_thickness", g.lens_thickness,
             "the posterior lens surface must lie inside the cavity, above the cut plane");
  }
  for (int i = 0; i < samples; ++i) {
    const double rho = lr + (dia.rho_ring - lr) * i / samples;
    if (!inside(dia.anterior(rho)) || !inside(dia.posterior(rho)))
      reject("geometry.ciliary_offset", g.ciliary_offset,
             "the zonule band from the lens equator to the ring must not cross the cornea "
             "or the sclera");
  }
}

/// Validates the internal structures of g and derives them into `shape`
/// (its diaphragm, the aqueous and vitreous volumes).
void derive_diaphragm(const Geometry& g, Shape& shape)
{
  check_diaphragm_keys(g);
  const Diaphragm dia = place_diaphragm(g, shape);
  check_diaphragm_in_cavity(g, shape.derived, dia);
  shape.diaphragm = dia;

  // Chamber volumes: pi r^2 dy along their counter-clockwise meridian
  // boundaries (r right, y up); the axis and the cut plane add nothing.
  Derived& d = shape.derived;
  const double Ri = g.sclera_outer_radius - g.sclera_thickness, Rp = g.cornea_posterior_radius;
  const double cp = d.posterior_centre_y, yp = d.junction_posterior_y;
  const double cavity_top = d.apex_y - g.cornea_central_thickness;
  d.aqueous_volume
      = zone_volume(dia.front_radius, dia.front_centre_y, dia.front_pole, dia.rim_front.y)
        + segment_volume(dia.rim_front, dia.ring) + zone_volume(Ri, 0, dia.ring.y, yp)
        + zone_volume(Rp, cp, yp, cavity_top);
  d.vitreous_volume
      = zone_volume(Ri, 0, g.cut_y, dia.ring.y) + segment_volume(dia.ring, dia.rim_back)
        + zone_volume(dia.back_radius, dia.back_centre_y, dia.rim_back.y, dia.back_pole);
}

/// The y of the anterior corneal sphere's centre (unvalidated).
double anterior_centre_y(const Geometry& g)
{
  const double rl = g.limbus_diameter / 2, Rs = g.sclera_outer_radius;
  const double Ra = g.cornea_anterior_radius;
  return std::sqrt(Rs * Rs - rl * rl) - std::sqrt(Ra * Ra - rl * rl);
}

/// Throws for the first key of the shell (sclera, cornea, limbus) that is
/// impossible on its own.
void check_shell_keys(const Geometry& g)
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
}

/// The shell's derived points, its peripheral thickness and the cavity's
/// volume (no internal structures); throws if the posterior cornea misses
/// the inner sclera or the anterior junction, or the cut plane the eye.
Derived derive_shell(const Geometry& g)
{
  const double Rs = g.sclera_outer_radius, ts = g.sclera_thickness;
  const double Ra = g.cornea_anterior_radius, Rp = g.cornea_posterior_radius;
  const double tc = g.cornea_central_thickness, rl = g.limbus_diameter / 2;
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
  return d;
}

/// Throws if the sweep X(s, t) = A + t (P - A) between the profiles folds.
/// Its meridian Jacobian dX/ds x (P - A) is linear in t and -tc < 0 at the
/// apex, so it must be negative on both profiles; sampled at the midpoints
/// of each arc piece.
void check_layers_do_not_fold(const Shape& shape)
{
  const Profile &anterior = shape.anterior, &posterior = shape.posterior;
  const double sl = anterior.junction_s();
  const int samples = 64;
  for (const auto& [s0, s1] : {std::pair{0.0, sl}, std::pair{sl, anterior.length()}})
    for (int i = 0; i < samples; ++i) {
      const double s = s0 + (i + 0.5) / samples * (s1 - s0), ps = shape.posterior_s(s);
      const Meridian a = anterior.at(s), p = posterior.at(ps);
      const Meridian da = anterior.tangent(s), dp = posterior.tangent(ps);
      const double sr = p.r - a.r, sy = p.y - a.y, rate = shape.posterior_s_rate(s);
      if (!(da.r * sy - da.y * sr < 0 && rate * (dp.r * sy - dp.y * sr) < 0)) {
        std::ostringstream message;
        message << "geometry: the layers between the anterior and posterior surfaces fold near "
                   "(r, y) = ("
                << a.r << ", " << a.y << "); geometry.cornea_central_thickness and "
                << "geometry.sclera_thickness are too large for the radii";
        throw std::invalid_argument(message.str());
      }
    }
}

} // namespace

Shape derive_shape(const Geometry& g)
{
  check_shell_keys(g);
  const Derived d = derive_shell(g);
  const double Rs = g.sclera_outer_radius, Ri = Rs - g.sclera_thickness;
  const Profile anterior(d.anterior_centre_y, g.cornea_anterior_radius,
                         {d.junction_anterior_r, d.junction_anterior_y}, Rs, g.cut_y);
  const Profile posterior(d.posterior_centre_y, g.cornea_posterior_radius,
                          {d.junction_posterior_r, d.junction_posterior_y}, Ri, g.cut_y);
  // The limbus: a band of limbus_width centred on the anterior junction.
  const double sl = anterior.junction_s(), w = g.limbus_width;
  if (!(w > 0 && w / 2 < sl && sl + w / 2 < anterior.length())) {
    std::ostringstream range;
    range << "must be in (0, " << 2 * std::min(sl, anterior.length() - sl)
          << ") so that cornea and sclera keep some anterior arc length";
    reject("geometry.limbus_width", w, range.str());
  }
  Shape shape{d, anterior, posterior, sl - w / 2, sl + w / 2};
  check_layers_do_not_fold(shape);
  if (g.internal_structures)
    derive_diaphragm(g, shape);
  return shape;
}

} // namespace detail

using detail::Vec3;

Derived derive(const Geometry& g)
{
  return detail::derive_shape(g).derived;
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
    const double cy = detail::anterior_centre_y(g);
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

} // namespace nct::eye
