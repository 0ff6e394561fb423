// Usage: compare_summaries A.json B.json RTOL [ATOL]
// Every entry of A's summary.json (numbers, strings, booleans, at any depth:
// the biomarkers, every DCR parameter, the steps, the air's record) must be
// in B and match it: numbers to RTOL relative or ATOL absolute (default
// 1e-14: round-off about zero), the rest exactly; B may hold no entry A
// lacks. Left out, by name at any depth: what measures the run rather than
// the physics (wall times, memory, the solvers' effort, residuals and
// iteration histories, the rank count, the BLAS, a resumed run's
// bookkeeping). Exit 1 on a mismatch.
#include <cmath>
#include <fstream>
#include <iostream>
#include <set>
#include <nlohmann/json.hpp>

namespace
{
int mismatches = 0;
double abs_tol = 1e-14;

/// The run's measures, not its physics.
const std::set<std::string> measures = {
    "wall_s",          "timings_s",       "coupled_timings_s",        "zero_pressure_wall_s",
    "profile",         "memory_peak_rank_mb", "memory_peak_total_mb", "ranks",
    "blas",            "checkpoints",     "resumed",                  "newton_iterations",
    "newton_residuals", "residual_N",     "linear_solves",            "jacobians",
    "factorisations",  "krylov_iterations", "step_cuts",              "zero_pressure_newton_iterations",
    "zero_pressure_history"}; // the fixed point's path: its residuals and relaxation factors

void mismatch(const std::string& path, const std::string& what)
{
  std::cout << path << ": " << what << "\n";
  ++mismatches;
}

void compare(const nlohmann::json& a, const nlohmann::json& b, double rtol,
             const std::string& path)
{
  if (a.is_number() && b.is_number())
  {
    const double x = a.get<double>(), y = b.get<double>();
    const double err = std::abs(x - y) / std::max(std::abs(x), std::abs(y));
    if (err > rtol && std::abs(x - y) > abs_tol)
      mismatch(path, std::to_string(x) + " vs " + std::to_string(y) + " (rel "
                         + std::to_string(err) + ")");
  }
  else if (a.is_array() && b.is_array())
  {
    if (a.size() != b.size())
      return mismatch(path, "sizes " + std::to_string(a.size()) + " vs "
                                + std::to_string(b.size()));
    for (std::size_t i = 0; i < a.size(); ++i)
      compare(a[i], b[i], rtol, path + "/" + std::to_string(i));
  }
  else if (a.is_object() && b.is_object())
  {
    for (auto it = a.begin(); it != a.end(); ++it)
      if (!measures.count(it.key()))
      {
        if (!b.contains(it.key()))
          mismatch(path + "/" + it.key(), "missing in the second");
        else
          compare(it.value(), b.at(it.key()), rtol, path + "/" + it.key());
      }
    for (auto it = b.begin(); it != b.end(); ++it)
      if (!measures.count(it.key()) && !a.contains(it.key()))
        mismatch(path + "/" + it.key(), "missing in the first");
  }
  else if (a != b)
    mismatch(path, a.dump() + " vs " + b.dump());
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
  compare(a, b, rtol, "");
  std::cout << (mismatches ? "MISMATCH" : "agree") << ": " << argv[1] << " vs " << argv[2]
            << " to " << rtol << "\n";
  return mismatches ? 1 : 0;
}
