#include "biomarkers/registry.h"

#include <algorithm>
#include <array>
#include <stdexcept>

namespace nct::biomarkers
{

const std::vector<Entry>& registry()
{
  // Times from the puff's start; displacements and velocities + outwards
  // (+y), the amplitudes and the whole-eye movement + inwards.
  static const std::vector<Entry> entries = {
      {"deflection_amplitude_mm", "mm", "the deformation amplitude less the whole eye's "
                                        "retraction", true},
      {"deformation_amplitude_mm", "mm", "the apex's inward displacement at HC, from the eye at "
                                         "rest", true},
      {"whole_eye_motion_hc_mm", "mm", "the anterior surface's axial displacement 4 mm from the "
                                       "axis at HC, + outwards (deflection - deformation)", true},
      {"peak_distance_mm", "mm", "between the two highest points of the anterior profile at HC",
       true},
      {"hc_time_ms", "ms", "highest concavity: the deepest apex (a parabola through the deepest "
                           "frame and its neighbours)", true},
      {"a1_time_ms", "ms", "first applanation: the apex curvature (over |x| <= "
                           "puff.apex_window) changes sign inwards", true},
      {"a1_length_mm", "mm", "the flat length at A1: where the profile stays within "
                             "puff.flatness of its apex height", true},
      {"a1_velocity_m_s", "m/s", "the apex's velocity at A1, + outwards", true},
      {"a2_time_ms", "ms", "second applanation, outwards", true},
      {"a2_length_mm", "mm", "the flat length at A2", true},
      {"a2_velocity_m_s", "m/s", "the apex's velocity at A2, + outwards", true},
      {"apex_pressure_hc_mmHg", "mmHg", "the air pressure at the apex at HC", true},
      {"apex_pressure_max_mmHg", "mmHg", "the largest air pressure at the apex", true},
      {"iop_max_mmHg", "mmHg", "the largest IOP under the puff (the first cavity: the aqueous "
                               "one with the internal structures)", true},
      {"iop_hc_mmHg", "mmHg", "the IOP at HC", true},
      {"hc_radius_mm", "mm", "the concave radius at HC by puff.radius_rule: the circle over "
                             "the concavity between the two peaks (or the parabola over |x| <= "
                             "puff.radius_window); when concave", true},
      {"max_inverse_radius_per_mm", "1/mm", "the largest inverse concave radius over the "
                                            "frames", true},
      {"integrated_radius_per_mm", "1/mm", "the integrated radius: the area under the inverse "
                                           "concave radius from A1 to A2, time counted in "
                                           "frames (the device's unit)", true},
      {"whole_eye_movement_max_mm", "mm", "the largest inward whole-eye motion (0 if it never "
                                          "moves in)", true},
      {"whole_eye_movement_time_ms", "ms", "the time of the largest inward whole-eye motion",
       true},
      {"da_ratio_1mm", "", "the largest ratio, from A1 to A2, of the apex's deformation to the "
                           "mean deformation at x = +-1 mm", true},
      {"da_ratio_2mm", "", "the same at x = +-2 mm", true},
      {"a1_a2_interval_ms", "ms", "from A1 to A2", true},
      {"a1_hc_interval_ms", "ms", "from A1 to HC", true},
      {"a1_deflection_mm", "mm", "the apex's deflection at A1", true},
      {"a2_deflection_mm", "mm", "the apex's deflection at A2", true},
      {"sp_a1_mmHg_per_mm", "mmHg/mm", "stiffness parameter at A1: (the device's pressure at "
                                       "A1 - the IOP at t = 0) / the deflection at A1; the "
                                       "device's pressure is the prescribed apex pressure, or "
                                       "the pulse the inlet was calibrated to", true},
      {"<cavity>_pressure_max_mmHg", "mmHg", "a cavity's largest pressure over the steps "
                                             "(cavity; aqueous, vitreous)", true},
      {"humor_pressure_range_max_mmHg", "mmHg", "with the humor's flow: the largest range of "
                                                "its pressure over the humor (max - min)",
       false},
      {"humor_bernoulli_max_mmHg", "mmHg", "with the humor's flow: the largest Bernoulli term "
                                           "rho |w|^2 / 2 its linearisation leaves out (w from "
                                           "Euler's equation)", false},
      {"humor_speed_max_m_s", "m/s", "with the humor as Navier-Stokes: its largest speed",
       false},
      {"newton_iterations", "", "Newton iterations, all phases", false},
      {"step_cuts", "", "increments halved after a failed step", false},
      {"step_rejections", "", "adaptive time steps (dynamics.tolerance) taken again shorter "
                              "for their local error", false},
      {"wall_s", "s", "wall time of the whole run", false}};
  return entries;
}

const Entry* find(std::string_view key)
{
  static const std::array<std::string_view, 3> cavities = {"cavity", "aqueous", "vitreous"};
  constexpr std::string_view pattern = "<cavity>";
  for (const Entry& e : registry())
  {
    if (e.key == key)
      return &e;
    if (e.key.rfind(pattern, 0) != 0)
      continue;
    const std::string_view rest = std::string_view(e.key).substr(pattern.size());
    for (auto cavity : cavities)
      if (key.size() == cavity.size() + rest.size() && key.substr(0, cavity.size()) == cavity
          && key.substr(cavity.size()) == rest)
        return &e;
  }
  return nullptr;
}

void put(nlohmann::json& summary, std::string_view key, double value)
{
  if (!find(key))
    throw std::logic_error("summary key '" + std::string(key)
                           + "' is not in the biomarker registry (cpp/biomarkers/registry.cpp)");
  summary[std::string(key)] = value;
}

std::string describe(bool markdown)
{
  if (!markdown)
  {
    nlohmann::json list = nlohmann::json::array();
    for (const Entry& e : registry())
      list.push_back({{"key", e.key}, {"unit", e.unit}, {"meaning", e.meaning},
                      {"reading", e.reading}});
    return list.dump(2) + "\n";
  }
  std::string text = "| key | unit | meaning |\n|---|---|---|\n";
  for (const Entry& e : registry())
  {
    std::string meaning = e.meaning;
    for (std::size_t i = meaning.find('|'); i != std::string::npos; i = meaning.find('|', i + 2))
      meaning.replace(i, 1, "\\|");
    text += "| `" + e.key + "` | " + e.unit + " | " + meaning + " |\n";
  }
  return text;
}

} // namespace nct::biomarkers
