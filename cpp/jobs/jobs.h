// Child runs of the nct executable: studies' cases and fits' forward
// runs, each an MPI job of its own with its console in a log file, on
// this machine or as a Slurm cluster's job arrays (jobs/slurm.h).
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <utility>
#include <vector>

namespace nct::jobs
{

/// One child run: its nct command line (no MPI launcher), the file its
/// output goes to, and its MPI ranks.
struct Job
{
  std::vector<std::string> argv;
  std::filesystem::path log;
  int ranks = 1;       ///< MPI ranks (`nct run` only)
  std::string mpiexec; ///< this machine's MPI launcher when ranks > 1 ("-n ranks" is appended)
  /// Called just before the job starts (not for one a resumed driver finds
  /// still running on a cluster), e.g. to clear its run folder.
  std::function<void()> prepare;
};

/// Where jobs run: this machine (processes) or a Slurm cluster (job arrays).
struct Launcher
{
  enum class Kind
  {
    local,
    slurm,
  };
  Kind kind = Kind::local;
  // Slurm only: sbatch's options; empty ones are left to the cluster.
  std::string partition;  ///< --partition
  std::string account;    ///< --account
  std::string time_limit; ///< --time, per job (Slurm's formats, e.g. "30", "1:00:00")
  int cores_per_rank = 1; ///< --cpus-per-task
  std::vector<std::string> options; ///< more sbatch options, each one word ("--qos=short")
  /// Where the driver keeps its submissions (scripts, job ids): the
  /// study's or fit's folder.
  std::filesystem::path folder;
};

/// The name of a launcher kind ("local", "slurm").
std::string name(Launcher::Kind kind);

/// The command a job runs on this machine: [mpiexec -n ranks] argv.
std::vector<std::string> local_command(const Job& job);

/// From now on SIGINT and SIGTERM set the interrupted() flag instead of
/// killing the process: running jobs are stopped and the caller resumes.
void catch_interrupts();

/// Has SIGINT or SIGTERM arrived since catch_interrupts()?
bool interrupted();

/// Run `jobs` on this machine, `at_once` at a time; `done(i, exit code)`
/// after each. Returns false when interrupted: the running jobs are
/// stopped and `done` is called for them too (one may have finished just
/// before the signal).
bool run(const std::vector<Job>& jobs, int at_once,
         const std::function<void(std::size_t, int)>& done);

/// The same with `launcher`: on this machine, or submitted to Slurm with at
/// most `at_once` in flight (jobs/slurm.h).
bool run(const Launcher& launcher, const std::vector<Job>& jobs, int at_once,
         const std::function<void(std::size_t, int)>& done);

/// The command line of an nct verb on a scene with overrides:
/// program verb scene --set ... [--out out --no-report] (`run` only).
std::vector<std::string> nct_command(const std::filesystem::path& program, const std::string& verb,
                                     const std::filesystem::path& scene,
                                     const std::vector<std::string>& sets,
                                     const std::filesystem::path& out);

/// A scene with its overrides, as `nct check` takes it.
struct SceneCase
{
  std::filesystem::path scene;
  std::vector<std::string> sets;
};

/// Checks every case by one `nct check --cases FILE` (FILE, in `dir`, a
/// JSON line per case): what `nct check` says of each refused case, by its
/// index (empty: all check out). Throws std::runtime_error when
/// interrupted or when the check itself fails without naming a case.
std::vector<std::pair<std::size_t, std::string>>
check_scenes(const std::filesystem::path& program, const std::vector<SceneCase>& cases,
             const std::filesystem::path& dir);


/// The last `n` lines of a text, for messages.
std::string tail(const std::string& text, std::size_t n);

/// A progress line's tail for work done in pieces: "[done/total]  t s
/// elapsed, about T s to go", T at the pace of the `run_now` pieces this
/// process finished in `elapsed` seconds (none kept from before).
std::string progress(std::size_t done, std::size_t total, std::size_t run_now, double elapsed);

} // namespace nct::jobs
