// The puff: [puff], the device's pulse, the prescribed load, the frames.
#include "settings/settings.h"

namespace nct
{
namespace
{
constexpr double inf = std::numeric_limits<double>::infinity();
} // namespace

void visit(scene::Visitor& v, PuffSettings& s)
{
  using L = PuffSettings::Load;
  v.choice({"puff.load", "none", "", -inf, inf,
            "none skips the phase; gaussian = peak exp(-(t - peak_time)^2 / (2 width_t^2)) "
            "exp(-r^2 / (2 width_r^2)); pulse = peak s(t) f(r), s the measured pulse's shape "
            "(rise_rate, fall_rate, pulse_duration) and f the radial profile of a CFD run "
            "(profile); table = a CSV file (t_ms, r_mm, p_mmHg) such as a CFD run writes; air = "
            "the air itself, computed from the nozzle (air.*, inlet.*) on a rigid eye or on "
            "none, writing such a table; fsi = the air and the eye two-way coupled in one Newton "
            "system (air.*, inlet.*, mesh_motion.*, fsi.*)"},
           s.load,
           {{"none", L::none},
            {"gaussian", L::gaussian},
            {"pulse", L::pulse},
            {"table", L::table},
            {"air", L::air},
            {"fsi", L::fsi}});
  const std::string frames = "puff.load=gaussian|pulse|table|fsi";
  v.real({"puff.duration", "20.0", "ms", 1e-3, 1e7, "time followed from the start of the puff",
          "puff.load=gaussian|pulse|table|air|fsi"},
         s.duration);
  v.real({"puff.peak", "65.0", "mmHg", -1e4, 1e4,
          "peak air pressure at the apex (with inlet.history = \"pulse\": the target the "
          "pulse's edges are relative to)",
          "puff.load=gaussian|pulse|air|fsi"},
         s.peak);
  v.real({"puff.rise_rate", "8.94", "mmHg/ms", 1e-3, 1e5,
          "the pulse's mean rate of rise: the peak over the rising edge's length (a raised "
          "cosine, cpp/puff/load.h)",
          "puff.load=pulse|air|fsi"},
         s.rise_rate);
  v.real({"puff.fall_rate", "11.18", "mmHg/ms", 1e-3, 1e5,
          "the mean rate of fall (magnitude): the peak over the falling edge's length",
          "puff.load=pulse|air|fsi"},
         s.fall_rate);
  v.real({"puff.pulse_duration", "21.48", "ms", 1e-3, 1e4,
          "the pulse's length from onset (t = 0) to end; what the edges leave of it is a hold "
          "at the peak (must not be negative)",
          "puff.load=pulse|air|fsi"},
         s.pulse_duration);
  v.path({"puff.profile", "", "", -inf, inf,
          "CSV file with the header r_mm,p_mmHg from r = 0 (e.g. a CFD run's corneal pressure "
          "at its peak), relative to the scene file; the pulse is scaled by p(r) / p(0)",
          "puff.load=pulse"},
         s.profile);
  v.real({"puff.peak_time", "10.0", "ms", 0, 1e3, "time of the peak from the start of the puff",
          "puff.load=gaussian|air|fsi"},
         s.peak_time);
  v.real({"puff.width_t", "3.0", "ms", 1e-3, 1e3, "standard deviation in time",
          "puff.load=gaussian|air|fsi"},
         s.width_t);
  v.real({"puff.width_r", "1.5", "mm", 1e-3, 1e3,
          "standard deviation in the distance r from the eye's axis", "puff.load=gaussian"},
         s.width_r);
  v.path({"puff.table", "", "", -inf, inf,
          "CSV file with the header t_ms,r_mm,p_mmHg, relative to the scene file (zero before "
          "its first and after its last time)",
          "puff.load=table"},
         s.table);
  v.real({"puff.frame_rate", "4330.0", "1/s", 100, 1e5,
          "rate at which the corneal profiles are sampled (Corvis ST: 4330 frames/s)", frames},
         s.frame_rate);
  // The device's unpublished choices (docs/physics.md section 9).
  biomarkers::Definitions& d = s.definitions;
  v.real({"puff.apex_window", "1.0", "mm", 0.05, 5,
          "applanation: the apex curvature is fitted over |x| <= this", frames},
         d.apex_window);
  using R = biomarkers::RadiusRule;
  v.choice({"puff.radius_rule", "concavity", "", -inf, inf,
            "the HC radius and each frame's inverse concave radius: concavity = the circle "
            "fitted to the profile between its two highest points (the whole concavity); "
            "window = the parabola fitted over |x| <= puff.radius_window (the device publishes "
            "neither)",
            frames},
           d.radius_rule, {{"concavity", R::concavity}, {"window", R::window}});
  v.real({"puff.radius_window", "1.5", "mm", 0.1, 5,
          "the parabola's half-width for puff.radius_rule = \"window\"",
          "puff.load=gaussian|pulse|table|fsi,puff.radius_rule=window"},
         d.radius_window);
  v.real({"puff.flatness", "0.014", "mm", 1e-6, 1,
          "applanation length: the profile is flat where it stays within this of its height on "
          "the axis (0.014 mm: one pixel of the device's 576-pixel, 8 mm wide image)",
          frames},
         d.flatness);
}

} // namespace nct
