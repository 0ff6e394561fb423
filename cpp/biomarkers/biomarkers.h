// Corvis biomarkers (docs/physics.md section 9) from sampled corneal profiles
// and apex time series. Pure functions of the samples: every rank that
// holds the same samples gets the same answer. The dynamic corneal
// response (DCR) parameters follow Vinciguerra et al., J Refract Surg
// 2016;32(8):550-561 (DA ratio, integrated inverse radius) and Roberts et
// al., J Refract Surg 2017;33(4):266-273 (SP-A1).
#pragma once

#include <optional>
#include <vector>

namespace nct::biomarkers
{

/// A corneal profile in the horizontal section: heights y [mm] along the
/// axis at positions x [mm] (strictly increasing, spanning x = 0).
struct Profile
{
  std::vector<double> x, y;
};

/// y at x, linear between samples.
double height(const Profile& p, double x);

/// Length [mm] of the flat segment around the axis: the interval around
/// x = 0 on which |y(x) - y(0)| <= tolerance, its ends found by linear
/// interpolation between samples. Corvis' applanation length.
double flat_length(const Profile& p, double tolerance);

/// Distance [mm] between the highest points on either side of the axis
/// (each refined by a parabola through the highest sample and its
/// neighbours). Corvis' peak distance, taken at highest concavity; 0 when
/// the profile is not concave there (the apex is its highest point: a
/// stiff cornea that only flattens), the limit of two peaks merging.
double peak_distance(const Profile& p);

/// Curvature coefficient b of the least-squares fit y = a + b x^2 over
/// |x| <= half_width [1/mm]: negative while the cornea bulges outwards
/// (+y), positive once it is pushed concave.
double apex_curvature(const Profile& p, double half_width);

/// Radius [mm] of the concavity at the apex, 1 / (2 b) with b from
/// apex_curvature over |x| <= half_width; none unless b > 0 (concave).
std::optional<double> concave_radius(const Profile& p, double half_width);

/// Corvis' DA ratio at d [mm]: the deformation on the axis over the mean
/// deformation at x = +d and -d, the deformation being rest(x) - p(x) at
/// the fixed image column x (linear between samples); none unless that
/// mean is positive.
std::optional<double> da_ratio(const Profile& rest, const Profile& p, double d);

/// Stiffness parameter at A1 [mmHg/mm] (Roberts et al. 2017): the apex air
/// pressure at A1 less the IOP at rest [mmHg], over the deflection at A1
/// [mm]; none unless the deflection is positive.
std::optional<double> stiffness_parameter_a1(double pressure, double iop, double deflection);

/// Times [ms] at which f(t) crosses zero, linear between samples; `upward`
/// keeps the crossings from negative to positive, else the other ones.
std::vector<double> crossings(const std::vector<double>& t, const std::vector<double>& f,
                              bool upward);

/// f at time t, linear between samples.
double at_time(const std::vector<double>& t, const std::vector<double>& f, double time);

/// One applanation: when, how long the flat segment, how fast and how far the apex.
struct Applanation
{
  double time = 0;          ///< [ms]
  double length = 0;        ///< flat length [mm]
  double apex_velocity = 0; ///< d u_apex / dt [mm/ms = m/s], + outwards
  double deflection = 0;    ///< [mm] apex inward displacement less the whole eye's
};

/// The biomarkers of one puff.
struct Result
{
  double hc_time = 0;               ///< [ms] deepest apex (parabola between frames)
  double deformation_amplitude = 0; ///< [mm] apex inward displacement at HC
  double deflection_amplitude = 0;  ///< [mm] the same less the whole-eye motion
  double peak_distance = 0;         ///< [mm] in the frame nearest HC
  Applanation a1, a2;              ///< inward and outward applanation
  bool applanated = false;         ///< both A1 and A2 were found
  std::optional<double> hc_radius; ///< [mm] concave radius at HC; none if not concave
  double max_inverse_radius = 0;   ///< [1/mm] largest inverse concave radius of the frames
  /// [ms/mm] the inverse concave radius integrated from A1 to A2 (when applanated)
  std::optional<double> integrated_inverse_radius;
  double whole_eye_movement_max = 0; ///< [mm] largest inward whole-eye motion, 0 if none
  std::optional<double> whole_eye_movement_time; ///< [ms] its time; none if never inward
  /// Largest DA ratios at 1 and 2 mm of the frames from A1 to A2 (when applanated)
  std::optional<double> da_ratio_1mm, da_ratio_2mm;

  /// [ms] from A1 to A2 (when applanated)
  double a1_a2_interval() const { return a2.time - a1.time; }
  /// [ms] from A1 to HC (when applanated)
  double a1_hc_interval() const { return hc_time - a1.time; }
};

/// Biomarkers from a puff's time series: `t` [ms] from the puff's start,
/// the anterior profiles, the apex axial displacement (+ outwards) and the
/// whole-eye motion (mean axial displacement of the anterior surface at
/// +-4 mm). Applanation is where the apex curvature (fitted over
/// |x| <= half_width) changes sign; its length uses `flatness` [mm]. The
/// HC radius (the profile linear in time at HC) and the inverse concave
/// radius are fitted over |x| <= radius_window [mm]; the DA ratio's
/// deformations are from the first frame.
Result analyse(const std::vector<double>& t, const std::vector<Profile>& anterior,
               const std::vector<double>& apex_displacement,
               const std::vector<double>& whole_eye_motion, double half_width,
               double radius_window, double flatness);

} // namespace nct::biomarkers
