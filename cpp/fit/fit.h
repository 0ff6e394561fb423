// Inverse identification: the scene keys (stiffness, IOP...) whose puff
// best explains a patient's Corvis readings, with their uncertainty.
// Levenberg-Marquardt with bounds (Ceres) on the weighted residuals of a
// forward model (fit/model.h): forward runs, each a child nct run as a
// study's case, cached so that an interrupted fit resumes, with
// sensitivities by finite differences; or an emulator of them.
#pragma once

#include <filesystem>
#include <string>

#include "fit/fit_file.h"

namespace nct::fit
{

/// Command-line settings of a fit (or of a cohort's fits).
struct Options
{
  std::filesystem::path out;     ///< fit folder
  std::filesystem::path program; ///< the nct executable that runs the forward runs
  int jobs = 0;                  ///< overrides the fit's when > 0
  bool dry_run = false;          ///< check the fit and the start's scene; run nothing
  /// Overrides the fit's launcher kind ("local", "slurm"; empty: the fit's).
  std::string launcher;
};

/// Run (or resume) a fit into out: fit.json, iterations.csv,
/// observations.csv and the forward runs in out/runs. Returns 0 when the
/// fit converged, 3 when it stopped otherwise (results written, status
/// says why), 130 when interrupted (the same command resumes it).
int run(const Fit& fit, const Options& options);

/// Fit every patient of a cohort (fit.cohort), each an `nct fit --patient`
/// of its own in out/patients/<id>, `at_once` at a time sharing the jobs;
/// then cohort.csv and cohort.json in out. A patient already fitted is
/// kept; an interrupted cohort resumes. Returns 0 when every fit
/// converged, 3 otherwise, 130 when interrupted.
int run_cohort(const Fit& fit, const Options& options);

} // namespace nct::fit
