// What a fit file says (docs/manual.md, "Fit a patient" and "Fit a
// cohort"): the fitted parameters, the observations with their SDs, the
// forward model (forward runs, or an emulator with its discrepancy), the
// posterior's method and a cohort's table; read and validated by
// Fit::load (fit_file.cpp) before anything runs.
#pragma once

#include <cmath>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>
#include <vector>

#include "emulator/emulator.h"
#include "jobs/jobs.h"

namespace nct::fit
{

/// A fitted parameter: one or more scene keys set together.
struct Parameter
{
  std::string label;             ///< its column (default: the first key's last part)
  std::vector<std::string> keys; ///< scene keys, e.g. material.cornea.c10
  double start;                  ///< the first guess
  double lower, upper;           ///< bounds (lower < start < upper)
  bool log;                      ///< fitted as log(value) (lower > 0)
  bool prior = false;            ///< a measured value with its SD (e.g. IOP by tonometry)
  double prior_mean = 0, prior_sd = 0;

  /// The value at the fitted variable theta, and back: on a log scale the
  /// variable is log(value / start), so that the start's value is exact
  /// (0.05, not 0.05000000000000001); else the value itself.
  double value(double theta) const { return log ? start * std::exp(theta) : theta; }
  double variable(double value) const { return log ? std::log(value / start) : value; }
};

/// What an observation compares.
enum class Kind
{
  biomarker, ///< a summary.json value
  curve,     ///< a frames.csv column against time (default: the apex displacement)
  profile    ///< the corneal profile (profiles.csv) at given times and x
};

/// One observation: one or more measured points with their SDs.
struct Observation
{
  std::string label;
  Kind kind;
  std::string quantity;      ///< biomarker key, frames.csv column, or profile surface
  std::filesystem::path file; ///< the CSV of a curve or profile
  bool relative = true;      ///< profile: y is the displacement from the t = 0 profile
  std::vector<double> t, x, value, sd; ///< per point (a biomarker: one, t and x unused)
};

/// One patient of a cohort: a row of its table (docs/manual.md, "Fit a cohort").
struct Patient
{
  std::string id;                ///< the `patient` column: its folder's name in the output
  std::size_t row = 0;           ///< its data row in the table (1: the line after the header)
  std::filesystem::path folder;  ///< its readings: the observations' files are read there
  std::vector<std::string> sets; ///< its scene keys (geometry, measured IOP...) as overrides
  /// Per parameter label: a measured value with its SD (replaces the fit file's prior).
  std::map<std::string, std::pair<double, double>> priors;
  std::map<std::string, double> truths; ///< per parameter label: the truth (synthetic cohorts)
  std::vector<std::pair<std::string, std::string>> covariates; ///< column, cell (age...)
};

/// A table of patients fitted one by one with the same fit file.
struct Cohort
{
  std::filesystem::path table;        ///< the CSV, one row per patient
  std::vector<std::string> covariates; ///< columns carried into the results (age...)
  int at_once = 0;                    ///< patients fitted at once (0: from the jobs)
  std::vector<Patient> patients;
};

/// A validated fit file (docs/manual.md, "Fit a patient").
struct Fit
{
  std::filesystem::path file;
  std::filesystem::path scene;   ///< the base scene
  std::vector<std::string> sets; ///< overrides of every forward run
  std::vector<Parameter> parameters;
  std::vector<Observation> observations;
  int ranks = 1, jobs = 1;
  std::string mpiexec;
  jobs::Launcher launcher; ///< where the forward runs go: this machine or Slurm
  int max_iterations = 20;
  double step = 0.01;            ///< finite-difference step in the fitted variable (relative)
  bool central = false;          ///< central differences (2 runs per parameter)
  double tolerance = 1e-4;       ///< stop when the cost or the parameters change less

  /// An emulator standing in for the forward runs ([fit] emulator); null:
  /// every evaluation is a forward run.
  std::shared_ptr<const emulator::Emulator> emulator;
  std::filesystem::path emulator_file;
  /// A model discrepancy measured against a more faithful model ([fit]
  /// discrepancy; empty: none): its mean is added to the emulator's, its
  /// covariance to the likelihood's.
  std::filesystem::path discrepancy_file;
  /// Per emulator input: the parameter it is (its index), or -1 and its value.
  std::vector<std::pair<int, double>> emulator_inputs;
  std::string posterior = "auto"; ///< "auto" (MCMC when a |correlation| > 0.9), "mcmc", "laplace"
  int walkers = 32;               ///< the MCMC's ensemble
  int steps = 1500;               ///< its steps, the first third burn-in
  int seed = 1;                   ///< its generator's seed
  bool confirm = true;            ///< an emulator fit's confirming forward run
  int corrected_iterations = 5;   ///< the corrected fit's iterations where it disagrees

  /// A fit file with a [cohort] table: its patients (the fit is each one's).
  std::optional<Cohort> cohort;
  /// The patient this fit is for (a cohort's row), if any.
  std::optional<Patient> patient;

  /// Read and validate a fit file: its keys, the parameters' keys and
  /// bounds against the scene, the observations' files and whether the
  /// scene can produce them. Throws scene::Error before anything runs.
  /// A cohort's file: with `patient` empty every row is checked so (each
  /// error naming its row) and `cohort` is set; else the fit of that
  /// patient.
  static Fit load(const std::filesystem::path& file, const std::string& patient = "");

  /// Weighted residuals: observation points, then priors.
  std::size_t residuals() const;
};

} // namespace nct::fit
