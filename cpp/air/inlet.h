// The velocity on a fluid inlet: a profile across the section times a
// ramp in time.
#pragma once

#include <array>
#include <filesystem>
#include <string>
#include <vector>

namespace nct::air
{

/// The inlet's velocity profile u(x) = speed f(x) e, with e the flow's
/// direction and f = 1 at the profile's centre:
/// - uniform: f = 1;
/// - parabolic over a rectangle: f = prod_i (1 - (s_i / a_i)^2)_+, s_i =
///   (x - c) . e_i along two directions across the section (a_i infinite:
///   no variation that way: a plane channel, or a slab between symmetry
///   planes, is Poiseuille's profile);
/// - parabolic over a circle: f = (1 - (r / R)^2)_+, r the distance from
///   the axis through c along e (a pipe's Poiseuille profile);
/// - a table of speeds at points (e.g. measured): speed f is their inverse
///   distance weighted mean (Shepard's, power 2: each point's own value
///   there, between them a smooth blend), speed = 1.
struct Inlet
{
  enum class Profile
  {
    uniform,
    rectangle,
    circle,
    table
  };
  Profile profile = Profile::uniform;
  std::array<double, 3> direction{1, 0, 0}; ///< unit
  std::array<double, 3> center{0, 0, 0};    ///< [mm]
  std::array<std::array<double, 3>, 2> axes{{{0, 1, 0}, {0, 0, 1}}}; ///< unit
  std::array<double, 2> half_widths{1, 1};  ///< [mm], may be infinite
  double radius = 1;                        ///< [mm]
  double speed = 1;                         ///< the largest speed [mm/ms]
  double ramp_time = 0;                     ///< [ms]
  std::vector<std::array<double, 4>> points; ///< table: x, y, z [mm], speed [mm/ms]

  /// The points of a CSV table with the header x_mm,y_mm,z_mm,u_m_s (the
  /// speed along the direction); throws std::invalid_argument naming the
  /// file and the line.
  static std::vector<std::array<double, 4>> read_table(const std::filesystem::path& file);

  /// The velocity at x once ramped [mm/ms].
  std::array<double, 3> velocity(const std::array<double, 3>& x) const;
  /// The ramp in time: (1 - cos(pi t / T)) / 2 for t < T, then 1 (and 1
  /// at once for T = 0; 0 before t = 0).
  double ramp(double t) const;
  /// The mean of f over the rectangle or the circle (uniform, table: 1):
  /// the mean speed over the section is speed times this (2/3 per bounded
  /// direction of the rectangle, 1/2 for the circle).
  double mean_factor() const;
};

} // namespace nct::air
