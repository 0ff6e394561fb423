// Corvis biomarkers (design.md section 9) from sampled corneal profiles
// and apex time series. Pure functions of the samples: every rank that
// holds the same samples gets the same answer.
#pragma once

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

/// Times [ms] at which f(t) crosses zero, linear between samples; `upward`
/// keeps the crossings from negative to positive, else the other ones.
std::vector<double> crossings(const std::vector<double>& t, const std::vector<double>& f,
                              bool upward);

/// f at time t, linear between samples.
double at_time(const std::vector<double>& t, const std::vector<double>& f, double time);

/// One applanation: when, how long the flat segment, how fast the apex.
struct Applanation
{
  double time = 0;          ///< [ms]
  double length = 0;        ///< flat length [mm]
  double apex_velocity = 0; ///< d u_apex / dt [mm/ms = m/s], + outwards
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
};

/// Biomarkers from a puff's time series: `t` [ms] from the puff's start,
/// the anterior profiles, the apex axial displacement (+ outwards) and the
/// whole-eye motion (mean axial displacement of the anterior surface at
/// +-4 mm). Applanation is where the apex curvature (fitted over
/// |x| <= half_width) changes sign; its length uses `flatness` [mm].
Result analyse(const std::vector<double>& t, const std::vector<Profile>& anterior,
               const std::vector<double>& apex_displacement,
               const std::vector<double>& whole_eye_motion, double half_width,
               double flatness);

} // namespace nct::biomarkers
