// Child runs of the nct executable: studies' cases and fits' forward
// runs, each an MPI job of its own with its console in a log file.
#pragma once

#include <filesystem>
#include <functional>
#include <string>
#include <vector>

namespace nct::jobs
{

/// One child process: its command line and the file its output goes to.
struct Job
{
  std::vector<std::string> argv;
  std::filesystem::path log;
};

/// From now on SIGINT and SIGTERM set the interrupted() flag instead of
/// killing the process: running jobs are stopped and the caller resumes.
void catch_interrupts();

/// Has SIGINT or SIGTERM arrived since catch_interrupts()?
bool interrupted();

/// Run `jobs`, `at_once` at a time; `done(i, exit code)` after each.
/// Returns false when interrupted: the running jobs are stopped and `done`
/// is called for them too (one may have finished just before the signal).
bool run(const std::vector<Job>& jobs, int at_once,
         const std::function<void(std::size_t, int)>& done);

/// The command line of an nct verb on a scene with overrides:
/// [mpiexec -n ranks] program verb scene --set ... [--out out]. Only `run`
/// starts MPI jobs; `check` runs serially.
std::vector<std::string> nct_command(const std::filesystem::path& program, const std::string& verb,
                                     const std::filesystem::path& scene,
                                     const std::vector<std::string>& sets,
                                     const std::filesystem::path& out, int ranks,
                                     const std::string& mpiexec);

/// The whole text of a file ("" when it cannot be read).
std::string read_text(const std::filesystem::path& file);

/// The last `n` lines of a text, for messages.
std::string tail(const std::string& text, std::size_t n);

} // namespace nct::jobs
