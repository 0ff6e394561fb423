// Usage: compare_summaries A.json B.json RTOL [ATOL]
// Every number in A's "steps" (and its top-level results) must match B's
// to RTOL relative, or to ATOL absolute (default 1e-14: round-off about
// zero); exit 1 otherwise.
#include <cmath>
#include <fstream>
#include <iostream>
#include <nlohmann/json.hpp>

namespace
{
int mismatches = 0;
double abs_tol = 1e-14;

void compare(const nlohmann::json& a, const nlohmann::json& b, double rtol,
             const std::string& path)
{
  if (a.is_number())
  {
    const double x = a.get<double>(), y = b.get<double>();
    const double err = std::abs(x - y) / std::max(std::abs(x), std::abs(y));
    if (err > rtol && std::abs(x - y) > abs_tol)
    {
      std::cout << path << ": " << x << " vs " << y << " (rel " << err << ")\n";
      ++mismatches;
    }
  }
  else if (a.is_array() || a.is_object())
  {
    if (a.size() != b.size())
    {
      std::cout << path << ": sizes " << a.size() << " vs " << b.size() << "\n";
      ++mismatches;
      return;
    }
    for (auto it = a.begin(); it != a.end(); ++it)
    {
      const std::string key = a.is_array() ? std::to_string(it - a.begin()) : it.key();
      if (key == "residual_N" || key == "newton_iterations"
          || key == "newton_residuals") // solver, not physics
        continue;
      compare(it.value(), a.is_array() ? b[std::stoul(key)] : b.at(key), rtol,
              path + "/" + key);
    }
  }
}
} // namespace

int main(int argc, char* argv[])
{
  if (argc != 4 && argc != 5)
  {
    std::cerr << "usage: compare_summaries A.json B.json RTOL [ATOL]\n";
    return 2;
  }
  nlohmann::json a = nlohmann::json::parse(std::ifstream(argv[1]));
  nlohmann::json b = nlohmann::json::parse(std::ifstream(argv[2]));
  const double rtol = std::stod(argv[3]);
  if (argc == 5)
    abs_tol = std::stod(argv[4]);
  for (const char* key :
       {"steps", "apex_displacement_mm", "cavity_volume_mm3", "cavity_volume_reference_mm3",
        "dofs", "cells", "probe_reference_mm", "zero_pressure_iterations", "frames",
        "deformation_amplitude_mm", "deflection_amplitude_mm", "whole_eye_motion_hc_mm",
        "peak_distance_mm", "hc_time_ms", "a1_time_ms", "a2_time_ms", "a1_length_mm",
        "a2_length_mm", "a1_velocity_m_s", "a2_velocity_m_s", "iop_max_mmHg",
        "apex_pressure_hc_mmHg", "apex_pressure_max_mmHg", "rest_drift_mm",
        "apex_pressure_max_time_ms", "centreline_peak_m_s", "max_velocity_m_s", "air",
        "air_mesh_jacobian_min", "interface_power_max_mW"})
    if (a.contains(key))
      compare(a[key], b.at(key), rtol, key);
  std::cout << (mismatches ? "MISMATCH" : "agree") << ": " << argv[1] << " vs " << argv[2]
            << " to " << rtol << "\n";
  return mismatches ? 1 : 0;
}
