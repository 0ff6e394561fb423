// The keys of a study or fit file that say how its runs go: ranks, jobs,
// mpiexec, and the launcher (`launcher` and its [slurm] table).
#pragma once

#include <filesystem>
#include <string>

#include <toml++/toml.h>

#include "io/toml_input.h"
#include "jobs/jobs.h"

namespace nct::jobs
{

/// How a study's cases or a fit's forward runs go on this machine.
struct RunKeys
{
  int ranks = 1;       ///< MPI ranks per run
  int jobs = 1;        ///< runs at once
  std::string mpiexec; ///< the MPI launcher of runs on several ranks
};

/// The keys ranks (1 to 4096, default 1), jobs (default: the cores over
/// the ranks) and mpiexec (default "mpiexec --bind-to none") of the table
/// `t` named `section` in `file`. Problems go into `errors`, naming the key.
RunKeys read_run_keys(const toml::table& t, const std::string& section,
                      const std::filesystem::path& file, io::KeyErrors& errors);

/// The launcher of the table `t` named `section` in `file` ("study", "fit"):
///
///     launcher = "local"            # or "slurm"
///     [section.slurm]               # slurm only
///     partition = "..."             # sbatch --partition (default: the cluster's)
///     account = "..."               # --account
///     time_limit = "1:00:00"        # --time per case
///     cores_per_rank = 1            # --cpus-per-task
///     options = ["--qos=short"]     # more sbatch options
///
/// Problems go into `errors`, naming the key.
Launcher read_launcher(const toml::table& t, const std::string& section,
                       const std::filesystem::path& file, io::KeyErrors& errors);

/// The launcher a driver uses: the file's (`section` of `file`), its kind
/// overridden by `kind` ("local", "slurm"; empty: the file's), its folder
/// `folder`. A Slurm launcher is tried first (slurm::check) for jobs of
/// `ranks`: a scene::Error naming the file and the key if Slurm refuses it.
Launcher launcher_for(const Launcher& from_file, const std::string& kind,
                      const std::filesystem::path& folder, int ranks, const std::string& section,
                      const std::filesystem::path& file);

/// The keys read_launcher() takes in the section ("launcher", "slurm").
inline const std::set<std::string>& launcher_keys()
{
  static const std::set<std::string> keys = {"launcher", "slurm"};
  return keys;
}

} // namespace nct::jobs
