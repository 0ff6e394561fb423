// Studies: a base scene run over a design of factor levels (or a list of
// named variants), every case in its own run folder, then one table and
// its statistics.
#pragma once

#include <filesystem>
#include <string>
#include <vector>

#include "jobs/jobs.h"

namespace nct::study
{

/// A factor: one or more scene keys set together to each of its levels.
struct Factor
{
  std::string label;              ///< column name (default: the first key)
  std::vector<std::string> keys;  ///< scene keys, e.g. material.cornea.k1
  std::vector<std::string> levels; ///< TOML literal of each level, as --set takes it
  std::vector<double> values;     ///< each level's number (a string level: its index)
  std::vector<double> range;      ///< table design: {low, high} its values must lie in (or none)
  std::string scale = "linear";   ///< table design: how a design fills the range ("log")
};

/// An ablation variant: named overrides of the base scene.
struct Variant
{
  std::string name;              ///< its row in the tables
  std::string description;       ///< one line for tables and plots (may be empty)
  std::filesystem::path scene;   ///< its scene: study.scene unless it names its own
  std::vector<std::string> sets; ///< its own overrides, after the study's
};

/// One case: the overrides it adds to the base scene.
struct Case
{
  std::vector<int> levels;       ///< per factor, the level's index; -1: the scene's value
                                 ///< (empty in an ablation)
  std::vector<std::string> sets; ///< section.key=value, the study's own first
  int variant = -1;              ///< ablation: the variant's index
  std::filesystem::path scene;   ///< the scene it overrides (the study's, or its variant's)
};

/// A validated study file (docs/manual.md, "Run a study").
struct Study
{
  std::filesystem::path file;  ///< the study file
  std::filesystem::path scene; ///< the base scene (relative to the study file)
  std::string design;          ///< "factorial" (2^k full), "ofat", "ablation" or "table"
  std::filesystem::path cases_file; ///< table: the CSV of its cases (relative to the file)
  std::vector<std::string> sets; ///< overrides of every case
  std::vector<Factor> factors;   ///< factorial, ofat and table (its levels: the values met)
  std::vector<Variant> variants; ///< ablation: the first is the baseline
  std::vector<std::string> responses; ///< summary.json keys
  int ranks; ///< MPI ranks per case
  int jobs;  ///< cases at once
  std::string mpiexec; ///< launcher of cases with ranks > 1 ("-n ranks" is appended)
  jobs::Launcher launcher; ///< where the cases run: this machine or Slurm
  std::vector<Case> cases; ///< factorial: Yates order (the first factor changes fastest);
                           ///< ofat: the base scene, then each factor's levels in turn;
                           ///< ablation: one per variant, in order; table: its rows
  std::vector<double> base_values; ///< ofat: each factor's value in the base scene

  /// Read and validate a study file (and every case's scene keys). Throws
  /// scene::Error naming the file and the key before anything runs.
  static Study load(const std::filesystem::path& file);

  /// Case c's folder: case-001... (as many digits as the cases need, 3 at least).
  std::string case_name(std::size_t c) const;

  /// A case for messages: "C10=0.25, k1=0.005" (an ablation: its variant's name).
  std::string describe(const Case& c) const;

  /// Factor i's value in case c (the base scene's where the case leaves it).
  double factor_value(const Case& c, std::size_t i) const;
};

/// Command-line settings of a study.
struct Options
{
  std::filesystem::path out;     ///< study folder
  std::filesystem::path program; ///< the nct executable that runs the cases
  int jobs = 0;                  ///< overrides the study's when > 0
  bool dry_run = false;          ///< check every case and list them, run none
  /// Overrides the study's launcher kind ("local", "slurm"; empty: the study's).
  std::string launcher;
};

/// Run (or resume) every case of a study in out/cases/case-NNN, then
/// write out/cases.csv and the analysis (out/effects.csv, anova.csv,
/// main_effects.csv, correlation.csv; an ablation: out/ablation.csv; and
/// analysis.json). Cases with a
/// summary.json from the same overrides are kept. Returns the exit code:
/// 0 when every case converged, 3 when some failed (the analysis covers
/// the responses every case gave), 130 when interrupted (run it again to
/// resume).
int run(const Study& study, const Options& options);

} // namespace nct::study
