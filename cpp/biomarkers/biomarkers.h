// Corvis biomarkers (docs/physics.md section 9) from sampled corneal profiles
// and apex time series. Pure functions of the samples: every rank that
// holds the same samples gets the same answer. The dynamic corneal
// response (DCR) parameters follow the device's published definitions
// (docs/physics.md, "The device's definitions": Vinciguerra et al., J
// Refract Surg 2016;32(8):550-561 and 32(12):803-810 for the DA ratio and
// the integrated radius; Roberts et al., J Refract Surg 2017;33(4):266-273
// for SP-A1); where the device's rule is not published, Definitions holds
// the choice.
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

/// Radius [mm] of the circle fitted by least squares (Kasa's algebraic
/// fit) to the samples between the highest points on either side of the
/// axis: the whole concavity, wherever its rim lies. None unless the
/// profile is concave there: the apex more than `depth` [mm] below both
/// peaks (a shallower concavity is flat to the camera), the circle's
/// centre on the outer side, at least five samples.
std::optional<double> concavity_radius(const Profile& p, double depth = 0.0);

/// How the concave radius of a profile is read: the circle over the whole
/// concavity (concavity_radius), or the parabola over a fixed window
/// (concave_radius). The device publishes neither.
enum class RadiusRule
{
  concavity,
  window
};

/// The choices the device does not publish (docs/physics.md section 9).
struct Definitions
{
  double apex_window = 1.0;   ///< [mm] applanation: the apex curvature's fit, |x| <= this
  RadiusRule radius_rule = RadiusRule::concavity; ///< the HC and inverse concave radius
  double radius_window = 1.5; ///< [mm] the window of RadiusRule::window
  double flatness = 0.014;    ///< [mm] applanation length: flat within this of the apex
  double frame_interval = 1 / 4.33; ///< [ms] between the device's frames (4330/s)
};

/// The concave radius [mm] of a profile by `d`'s rule; none unless concave
/// (the concavity's circle: deeper than d.flatness).
std::optional<double> concave_radius(const Profile& p, const Definitions& d);

/// Corvis' DA ratio at d [mm]: the deformation on the axis over the mean
/// deformation at x = +d and -d, the deformation being rest(x) - p(x) at
/// the fixed image column x (linear between samples); none unless that
/// mean is positive.
std::optional<double> da_ratio(const Profile& rest, const Profile& p, double d);

/// Stiffness parameter at A1 [mmHg/mm] (Roberts et al. 2017): the device's
/// air pressure at A1 less the IOP (the device: its bIOP) [mmHg], over the
/// deflection at A1 [mm]; none unless the deflection is positive.
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
  /// [1/mm] the integrated radius: the area under the inverse concave
  /// radius from A1 to A2 with time counted in frames (when applanated)
  std::optional<double> integrated_radius;
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
/// |x| <= d.apex_window) changes sign; its length uses d.flatness. The HC
/// radius (the profile linear in time at HC) and each frame's inverse
/// concave radius follow d.radius_rule; the integrated radius counts time
/// in d.frame_interval; the DA ratio's deformations are from the first
/// frame.
Result analyse(const std::vector<double>& t, const std::vector<Profile>& anterior,
               const std::vector<double>& apex_displacement,
               const std::vector<double>& whole_eye_motion, const Definitions& d);

} // namespace nct::biomarkers
