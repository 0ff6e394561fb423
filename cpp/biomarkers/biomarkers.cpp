#include "biomarkers/biomarkers.h"

#include <algorithm>
#include <cmath>
#include <utility>
#include <stdexcept>

namespace nct::biomarkers
{
namespace
{

/// Index i with x[i] <= v < x[i+1], clamped to the ends.
std::size_t interval(const std::vector<double>& x, double v)
{
  auto it = std::upper_bound(x.begin(), x.end(), v);
  std::size_t i = it == x.begin() ? 0 : static_cast<std::size_t>(it - x.begin()) - 1;
  return std::min(i, x.size() - 2);
}

double interpolate(const std::vector<double>& x, const std::vector<double>& y, double v)
{
  if (x.size() < 2 || x.size() != y.size())
    throw std::invalid_argument("biomarkers: need at least two samples of equal count");
  const std::size_t i = interval(x, v);
  const double s = (v - x[i]) / (x[i + 1] - x[i]);
  return (1 - s) * y[i] + s * y[i + 1];
}

/// Vertex (position, value) of the parabola through samples i-1, i, i+1
/// of (x, y); the sample itself at the ends or if the three are collinear.
std::pair<double, double> vertex(const std::vector<double>& x, const std::vector<double>& y,
                                 std::size_t i)
{
  if (i == 0 || i + 1 == x.size())
    return {x[i], y[i]};
  const double x0 = x[i - 1], x1 = x[i], x2 = x[i + 1];
  const double y0 = y[i - 1], y1 = y[i], y2 = y[i + 1];
  const double d = (x0 - x1) * (x0 - x2) * (x1 - x2);
  const double a = (x2 * (y1 - y0) + x1 * (y0 - y2) + x0 * (y2 - y1)) / d;
  const double b = (x2 * x2 * (y0 - y1) + x1 * x1 * (y2 - y0) + x0 * x0 * (y1 - y2)) / d;
  if (a == 0)
    return {x1, y1};
  const double xv = std::clamp(-b / (2 * a), x0, x2);
  const double c = y1 - a * x1 * x1 - b * x1;
  return {xv, a * xv * xv + b * xv + c};
}

/// Position of the maximum of y over the samples with `keep(x)`, refined
/// by the parabola through the best sample and its two neighbours.
double highest(const Profile& p, bool (*keep)(double))
{
  std::size_t best = p.x.size();
  for (std::size_t i = 0; i < p.x.size(); ++i)
    if (keep(p.x[i]) && (best == p.x.size() || p.y[i] > p.y[best]))
      best = i;
  if (best == p.x.size())
    throw std::invalid_argument("biomarkers: the profile has no samples on one side");
  return vertex(p.x, p.y, best).first;
}

/// The profile at `time`: each sample linear in time between the neighbouring frames.
Profile profile_at(const std::vector<double>& t, const std::vector<Profile>& frames, double time)
{
  const std::size_t i = interval(t, time);
  const double s = (time - t[i]) / (t[i + 1] - t[i]);
  Profile p = frames[i];
  for (std::size_t k = 0; k < p.x.size(); ++k)
  {
    p.x[k] = (1 - s) * frames[i].x[k] + s * frames[i + 1].x[k];
    p.y[k] = (1 - s) * frames[i].y[k] + s * frames[i + 1].y[k];
  }
  return p;
}

/// Integral of f over [from, to]: trapezoids over the samples inside,
/// with f at the ends given.
double integral(const std::vector<double>& t, const std::vector<double>& f, double from,
                double f_from, double to, double f_to)
{
  double sum = 0, t0 = from, f0 = f_from;
  for (std::size_t i = 0; i < t.size(); ++i)
    if (t[i] > from && t[i] < to)
    {
      sum += 0.5 * (f0 + f[i]) * (t[i] - t0);
      t0 = t[i], f0 = f[i];
    }
  return sum + 0.5 * (f0 + f_to) * (to - t0);
}

} // namespace

double height(const Profile& p, double x) { return interpolate(p.x, p.y, x); }

double flat_length(const Profile& p, double tolerance)
{
  const double y0 = height(p, 0.0);
  auto flat = [&](std::size_t i) { return std::abs(p.y[i] - y0) <= tolerance; };
  // Walk out from the axis on each side to the first sample off the flat,
  // then interpolate where |y - y0| reaches the tolerance.
  auto end = [&](int direction)
  {
    const std::size_t first = interval(p.x, 0.0) + (direction > 0 ? 1 : 0);
    double inner_x = 0.0, inner_dy = 0.0;
    for (std::size_t i = first; i < p.x.size(); i += direction)
    {
      const double dy = std::abs(p.y[i] - y0);
      if (!flat(i))
        return inner_x + (p.x[i] - inner_x) * (tolerance - inner_dy) / (dy - inner_dy);
      inner_x = p.x[i], inner_dy = dy;
      if (i == 0)
        break;
    }
    return inner_x; // flat to the end of the samples
  };
  return end(+1) - end(-1);
}

double peak_distance(const Profile& p)
{
  const double right = highest(p, [](double x) { return x > 0; });
  const double left = highest(p, [](double x) { return x < 0; });
  // Not concave: the apex is the highest point, the two peaks are one.
  if (height(p, 0.0) >= std::max(height(p, right), height(p, left)))
    return 0.0;
  return right - left;
}

double apex_curvature(const Profile& p, double half_width)
{
  // Least squares for y = a + b s with s = x^2.
  double n = 0, S = 0, SS = 0, Y = 0, SY = 0;
  for (std::size_t i = 0; i < p.x.size(); ++i)
    if (std::abs(p.x[i]) <= half_width)
    {
      const double s = p.x[i] * p.x[i];
      n += 1, S += s, SS += s * s, Y += p.y[i], SY += s * p.y[i];
    }
  const double det = n * SS - S * S;
  if (n < 3 || det <= 0)
    throw std::invalid_argument("biomarkers: fewer than three profile samples within the "
                                "apex window");
  return (n * SY - S * Y) / det;
}

std::optional<double> concave_radius(const Profile& p, double half_width)
{
  const double b = apex_curvature(p, half_width);
  if (b <= 0)
    return std::nullopt;
  return 1 / (2 * b);
}

std::optional<double> concavity_radius(const Profile& p, double depth)
{
  const double right = highest(p, [](double x) { return x > 0; });
  const double left = highest(p, [](double x) { return x < 0; });
  const double y0 = height(p, 0.0);
  if (y0 + depth >= std::min(height(p, right), height(p, left)))
    return std::nullopt;
  // Kasa's fit: x^2 + y^2 = 2 a x + 2 b y + c, linear least squares for
  // (a, b, c); the radius sqrt(c + a^2 + b^2). Centred on the first sample
  // inside, for conditioning.
  double A[3][3] = {}, r[3] = {};
  std::size_t n = 0;
  for (std::size_t i = 0; i < p.x.size(); ++i)
    if (p.x[i] >= left && p.x[i] <= right)
    {
      const double x = p.x[i], y = p.y[i] - y0, row[3] = {2 * x, 2 * y, 1.0};
      for (int j = 0; j < 3; ++j)
      {
        for (int k = 0; k < 3; ++k)
          A[j][k] += row[j] * row[k];
        r[j] += row[j] * (x * x + y * y);
      }
      ++n;
    }
  if (n < 5)
    return std::nullopt;
  // Cramer's rule on the 3x3 normal equations.
  auto det = [](const double M[3][3])
  {
    return M[0][0] * (M[1][1] * M[2][2] - M[1][2] * M[2][1])
           - M[0][1] * (M[1][0] * M[2][2] - M[1][2] * M[2][0])
           + M[0][2] * (M[1][0] * M[2][1] - M[1][1] * M[2][0]);
  };
  const double D = det(A);
  if (D <= 0)
    return std::nullopt;
  double c[3];
  for (int j = 0; j < 3; ++j)
  {
    double M[3][3];
    for (int a = 0; a < 3; ++a)
      for (int b = 0; b < 3; ++b)
        M[a][b] = b == j ? r[a] : A[a][b];
    c[j] = det(M) / D;
  }
  if (c[1] <= 0) // the centre behind the apex: convex
    return std::nullopt;
  return std::sqrt(c[2] + c[0] * c[0] + c[1] * c[1]);
}

std::optional<double> concave_radius(const Profile& p, const Definitions& d)
{
  return d.radius_rule == RadiusRule::concavity ? concavity_radius(p, d.flatness)
                                                : concave_radius(p, d.radius_window);
}

std::optional<double> da_ratio(const Profile& rest, const Profile& p, double d)
{
  auto deformation = [&](double x) { return height(rest, x) - height(p, x); };
  const double flank = 0.5 * (deformation(d) + deformation(-d));
  if (flank <= 0)
    return std::nullopt;
  return deformation(0.0) / flank;
}

std::optional<double> stiffness_parameter_a1(double pressure, double iop, double deflection)
{
  if (deflection <= 0)
    return std::nullopt;
  return (pressure - iop) / deflection;
}

std::vector<double> crossings(const std::vector<double>& t, const std::vector<double>& f,
                              bool upward)
{
  std::vector<double> times;
  for (std::size_t i = 0; i + 1 < t.size(); ++i)
  {
    const bool crosses = upward ? f[i] < 0 && f[i + 1] >= 0 : f[i] > 0 && f[i + 1] <= 0;
    if (crosses)
      times.push_back(t[i] + (t[i + 1] - t[i]) * f[i] / (f[i] - f[i + 1]));
  }
  return times;
}

double at_time(const std::vector<double>& t, const std::vector<double>& f, double time)
{
  return interpolate(t, f, time);
}

Result analyse(const std::vector<double>& t, const std::vector<Profile>& anterior,
               const std::vector<double>& apex_displacement,
               const std::vector<double>& whole_eye_motion, const Definitions& d)
{
  const std::size_t n = t.size();
  if (n < 3 || anterior.size() != n || apex_displacement.size() != n
      || whole_eye_motion.size() != n)
    throw std::invalid_argument("biomarkers: the time series differ in length or are "
                                "shorter than 3 frames");
  Result r;
  // HC: the deepest apex, refined between frames by a parabola.
  const std::size_t hc = static_cast<std::size_t>(
      std::min_element(apex_displacement.begin(), apex_displacement.end())
      - apex_displacement.begin());
  const auto [hc_time, deepest] = vertex(t, apex_displacement, hc);
  r.hc_time = hc_time;
  r.deformation_amplitude = -deepest;
  r.deflection_amplitude = -(deepest - at_time(t, whole_eye_motion, hc_time));
  r.peak_distance = peak_distance(anterior[hc]);
  r.hc_radius = concave_radius(profile_at(t, anterior, hc_time), d);

  // The largest inward whole-eye motion, refined like HC.
  std::vector<double> inward(n);
  for (std::size_t i = 0; i < n; ++i)
    inward[i] = -whole_eye_motion[i];
  const auto [eye_time, eye_depth] = vertex(
      t, inward,
      static_cast<std::size_t>(std::max_element(inward.begin(), inward.end()) - inward.begin()));
  if (eye_depth > 0)
    r.whole_eye_movement_max = eye_depth, r.whole_eye_movement_time = eye_time;

  // Apex velocity by central differences (one-sided at the ends).
  std::vector<double> velocity(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    const std::size_t a = i == 0 ? 0 : i - 1, b = i + 1 == n ? i : i + 1;
    velocity[i] = (apex_displacement[b] - apex_displacement[a]) / (t[b] - t[a]);
  }
  std::vector<double> curvature(n), inverse_radius(n);
  for (std::size_t i = 0; i < n; ++i)
  {
    curvature[i] = apex_curvature(anterior[i], d.apex_window);
    const auto radius = concave_radius(anterior[i], d);
    inverse_radius[i] = radius ? 1 / *radius : 0.0;
  }
  r.max_inverse_radius = *std::max_element(inverse_radius.begin(), inverse_radius.end());
  auto applanation = [&](double time)
  {
    return Applanation{time, flat_length(profile_at(t, anterior, time), d.flatness),
                       at_time(t, velocity, time),
                       -(at_time(t, apex_displacement, time) - at_time(t, whole_eye_motion, time))};
  };
  const auto in = crossings(t, curvature, true), out = crossings(t, curvature, false);
  auto a1 = std::find_if(in.begin(), in.end(), [&](double x) { return x <= r.hc_time; });
  auto a2 = std::find_if(out.begin(), out.end(), [&](double x) { return x >= r.hc_time; });
  r.applanated = a1 != in.end() && a2 != out.end();
  if (!r.applanated)
    return r;
  r.a1 = applanation(*a1);
  r.a2 = applanation(*a2);
  // The area under the inverse radius with time in frames (the device's
  // unit: its integrated radius is in 1/mm): trapezoids over the frames
  // inside, from 0 at A1 and to 0 at A2 (flat: no curvature).
  r.integrated_radius = integral(t, inverse_radius, r.a1.time, 0.0, r.a2.time, 0.0)
                        / d.frame_interval;
  // The concave phase: the DA ratio is ill-conditioned while the flanks barely move.
  for (std::size_t i = 0; i < n; ++i)
    if (t[i] >= r.a1.time && t[i] <= r.a2.time)
      for (auto [d, ratio] : {std::pair{1.0, &r.da_ratio_1mm}, {2.0, &r.da_ratio_2mm}})
        if (auto q = da_ratio(anterior.front(), anterior[i], d); q && (!*ratio || *q > **ratio))
          *ratio = q;
  return r;
}

} // namespace nct::biomarkers
