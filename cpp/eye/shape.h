// The idealised eye's analytic shape as its meshers use it: the meridian
// profiles, the internal structures' diaphragm and the validated shape
// (cpp/eye/shape.cpp).
#pragma once

#include "eye/geometry.h"

#include <array>
#include <cmath>
#include <string>

namespace nct::eye::detail
{

using Vec3 = std::array<double, 3>;

/// A point (r, y) of the meridian half-plane.
struct Meridian
{
  double r;
  double y;
};

/// The point a fraction t of the way from a to b: the layered sweep
/// X(s, t) = A + t (P - A) between an anterior point A and its posterior P.
inline Meridian between(Meridian a, Meridian b, double t)
{
  return {a.r + t * (b.r - a.r), a.y + t * (b.y - a.y)};
}

/// Throws std::invalid_argument naming `key`, its value and what is accepted.
[[noreturn]] void reject(const std::string& key, double value, const std::string& accepted);

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
/// distance along the zonule band to the ring point at rho_ring.
struct Diaphragm
{
  bool on = false;
  double lens_radius = 0;             ///< lens radius (equator)
  double front_centre_y = 0, front_radius = 0; ///< anterior lens sphere: centre y, radius
  double back_centre_y = 0, back_radius = 0;   ///< posterior lens sphere: centre y, radius
  double front_pole = 0, back_pole = 0; ///< y of the lens poles
  Meridian rim_front{}, rim_back{};   ///< lens equator rim on the two spheres
  Meridian ring{};                    ///< zonule ring point R on the inner sclera
  double ring_s = 0;                  ///< shell chart radius (anterior arc length) of the ring
  double rho_nucleus = 0;             ///< chart radius bounding the nucleus
  double rho_ring = 0;                ///< chart radius of the ring

  /// The anterior (front) profile point at chart radius rho.
  Meridian anterior(double rho) const
  {
    if (rho <= lens_radius)
      return {rho, front_centre_y + std::sqrt(front_radius * front_radius - rho * rho)};
    return toward_ring(rim_front, rho);
  }

  /// The posterior (back) profile point at chart radius rho.
  Meridian posterior(double rho) const
  {
    if (rho <= lens_radius)
      return {rho, back_centre_y - std::sqrt(back_radius * back_radius - rho * rho)};
    return toward_ring(rim_back, rho);
  }

private:
  Meridian toward_ring(Meridian rim, double rho) const
  {
    if (rho >= rho_ring)
      return ring;
    const double u = (rho - lens_radius) / (rho_ring - lens_radius);
    return {rim.r + u * (ring.r - rim.r), rim.y + u * (ring.y - rim.y)};
  }
};

/// The validated shape: derived numbers, both profiles and the part bounds.
struct Shape
{
  Derived derived;
  Profile anterior;
  Profile posterior;
  double limbus_begin; ///< s where the cornea ends
  double limbus_end;   ///< s where the sclera begins
  Diaphragm diaphragm{}; ///< internal structures (diaphragm.on) or nothing

  /// The shell's part at the anterior arc length s.
  Part part_at(double s) const
  {
    return s < limbus_begin ? Part::cornea : s < limbus_end ? Part::limbus : Part::sclera;
  }

  /// The posterior arc length matched to the anterior arc length s.
  double posterior_s(double s) const
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
  double posterior_s_rate(double s) const
  {
    const double sl = anterior.junction_s(), psl = posterior.junction_s();
    return s <= sl ? psl / sl : (posterior.length() - psl) / (anterior.length() - sl);
  }
};

/// Validates the geometry and derives its shape; throws
/// std::invalid_argument naming the key of an impossible shape (derive()).
Shape derive_shape(const Geometry& g);

} // namespace nct::eye::detail
