// A study's tables: what each case gave (cases.csv), the analysis of its
// responses (effects.csv, anova.csv, main_effects.csv, correlation.csv; an
// ablation's ablation.csv; analysis.json) and what the console shows of it.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "io/format.h"
#include "study/study.h"

namespace nct::study
{

/// What one case gave.
struct Result
{
  std::string status = "pending"; ///< pending, converged, failed, error
  std::vector<double> responses;  ///< per study response; NaN where the case gave none
  double wall_s = io::nan;
};

/// A pending case's result: no response yet.
Result pending(const Study& s);

/// What the case in run folder `dir` gave (its summary.json).
Result read_result(const Study& s, const std::filesystem::path& dir);

/// The table of the cases: case, status, variant or factors, responses, wall time.
std::string cases_csv(const Study& s, const std::vector<Result>& results);

/// The analysis of the finished cases into the study folder `out` (an
/// ablation: its variants against the baseline; else the effects, ANOVA,
/// main effects and correlations), its rankings or tables on stdout.
void analyse(const Study& s, const std::vector<Result>& results, const std::filesystem::path& out);

/// The closing line: how many cases converged, the tables written in
/// `out` and how to plot them. Returns the exit code: 0 when every case
/// converged, else 3.
int report_outcome(const Study& s, const std::vector<Result>& results,
                   const std::filesystem::path& out);

} // namespace nct::study
