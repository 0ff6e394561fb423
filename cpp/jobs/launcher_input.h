// The launcher keys of a study or fit file: `launcher` and its [slurm] table.
#pragma once

#include <filesystem>
#include <string>

#include <toml++/toml.h>

#include "io/toml_input.h"
#include "jobs/jobs.h"

namespace nct::jobs
{

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
