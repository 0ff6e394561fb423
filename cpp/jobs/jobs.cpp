#include "jobs/jobs.h"

#include "jobs/slurm.h"

#include <cerrno>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <iomanip>
#include <map>
#include <spawn.h>
#include <sstream>
#include <stdexcept>
#include <sys/wait.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "io/output.h"
#include "io/text.h"

extern char** environ;

namespace nct::jobs
{
namespace fs = std::filesystem;
namespace
{

volatile std::sig_atomic_t stop = 0;
void on_signal(int) { stop = 1; }

/// The environment without an enclosing MPI job's variables, so that each
/// job starts an MPI job of its own.
std::vector<std::string> clean_environment()
{
  std::vector<std::string> env;
  for (char** e = environ; *e; ++e)
  {
    std::string v = *e;
    if (v.rfind("OMPI_COMM_WORLD", 0) == 0 || v.rfind("OMPI_MCA_orte_", 0) == 0
        || v.rfind("OMPI_MCA_ess", 0) == 0 || v.rfind("OMPI_MCA_pmix", 0) == 0
        || v.rfind("PMIX_", 0) == 0 || v.rfind("PMI_", 0) == 0)
      continue;
    env.push_back(v);
  }
  return env;
}

/// Start `argv` with stdout and stderr into `log`; returns its pid.
pid_t spawn(const std::vector<std::string>& argv, const fs::path& log)
{
  posix_spawn_file_actions_t actions;
  posix_spawn_file_actions_init(&actions);
  posix_spawn_file_actions_addopen(&actions, 1, log.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
  posix_spawn_file_actions_adddup2(&actions, 1, 2);
  std::vector<char*> args;
  for (auto& a : argv)
    args.push_back(const_cast<char*>(a.c_str()));
  args.push_back(nullptr);
  static const std::vector<std::string> env_strings = clean_environment();
  std::vector<char*> env;
  for (auto& e : env_strings)
    env.push_back(const_cast<char*>(e.c_str()));
  env.push_back(nullptr);
  pid_t pid = 0;
  int err = posix_spawnp(&pid, args[0], &actions, nullptr, args.data(), env.data());
  posix_spawn_file_actions_destroy(&actions);
  if (err != 0)
    throw std::runtime_error("cannot start " + argv[0] + ": " + std::strerror(err));
  return pid;
}

std::vector<std::string> split_words(const std::string& text)
{
  std::istringstream in(text);
  std::vector<std::string> out;
  std::string w;
  while (in >> w)
    out.push_back(w);
  return out;
}

} // namespace

void catch_interrupts()
{
  struct sigaction action = {};
  action.sa_handler = on_signal;
  sigaction(SIGINT, &action, nullptr);
  sigaction(SIGTERM, &action, nullptr);
}

bool interrupted() { return stop != 0; }

std::string name(Launcher::Kind kind) { return kind == Launcher::Kind::slurm ? "slurm" : "local"; }

std::vector<std::string> local_command(const Job& job)
{
  std::vector<std::string> argv;
  if (job.ranks > 1)
  {
    argv = split_words(job.mpiexec);
    argv.push_back("-n");
    argv.push_back(std::to_string(job.ranks));
  }
  argv.insert(argv.end(), job.argv.begin(), job.argv.end());
  return argv;
}

bool run(const Launcher& launcher, const std::vector<Job>& jobs, int at_once,
         const std::function<void(std::size_t, int)>& done)
{
  if (launcher.kind == Launcher::Kind::slurm)
    return slurm::run(launcher, jobs, at_once, done);
  return run(jobs, at_once, done);
}

bool run(const std::vector<Job>& jobs, int at_once,
         const std::function<void(std::size_t, int)>& done)
{
  std::map<pid_t, std::size_t> running;
  std::size_t next = 0;
  while (next < jobs.size() || !running.empty())
  {
    while (!stop && next < jobs.size() && int(running.size()) < at_once)
    {
      if (jobs[next].prepare)
        jobs[next].prepare();
      running[spawn(local_command(jobs[next]), jobs[next].log)] = next;
      ++next;
    }
    if (stop)
    {
      for (auto& [pid, i] : running)
        kill(pid, SIGTERM);
      // A job may have finished just before the signal: keep it.
      for (auto& [pid, i] : running)
      {
        int status = 0;
        waitpid(pid, &status, 0);
        done(i, WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status));
      }
      return false;
    }
    int status = 0;
    pid_t pid = waitpid(-1, &status, 0);
    if (pid < 0)
    {
      if (errno == EINTR)
        continue;
      throw std::runtime_error(std::string("waitpid: ") + std::strerror(errno));
    }
    auto it = running.find(pid);
    if (it == running.end())
      continue;
    const std::size_t i = it->second;
    running.erase(it);
    done(i, WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status));
  }
  return true;
}

std::vector<std::string> nct_command(const fs::path& program, const std::string& verb,
                                     const fs::path& scene, const std::vector<std::string>& sets,
                                     const fs::path& out)
{
  std::vector<std::string> argv;
  argv.push_back(program.string());
  argv.push_back(verb);
  argv.push_back(fs::absolute(scene).string());
  for (auto& set : sets)
  {
    argv.push_back("--set");
    argv.push_back(set);
  }
  if (verb == "run") // a case or a forward run: the study's or fit's page covers it
    argv.insert(argv.end(), {"--out", out.string(), "--no-report"});
  return argv;
}

std::vector<std::pair<std::size_t, std::string>>
check_scenes(const fs::path& program, const std::vector<SceneCase>& cases, const fs::path& dir)
{
  if (cases.empty())
    return {};
  fs::create_directories(dir);
  const fs::path list = dir / "check.jsonl", log = dir / "check.log";
  std::string lines;
  for (const auto& c : cases)
    lines += nlohmann::json{{"scene", fs::absolute(c.scene).string()}, {"sets", c.sets}}.dump()
             + "\n";
  io::write_atomic(list, lines);
  int code = -1;
  const Job job{{program.string(), "check", "--cases", list.string()}, log, 1, "", nullptr};
  if (!run({job}, 1, [&](std::size_t, int c) { code = c; }))
    throw std::runtime_error("interrupted while checking the cases");
  // Each refused case: a line "case I:", then what nct check says of it.
  std::vector<std::pair<std::size_t, std::string>> refused;
  std::istringstream text(io::read_text(log));
  for (std::string line; std::getline(text, line);)
    if (line.rfind("case ", 0) == 0 && !line.empty() && line.back() == ':')
      refused.push_back({std::stoul(line.substr(5)), ""});
    else if (!refused.empty() && line.rfind("note: ", 0) != 0)
      refused.back().second += (refused.back().second.empty() ? "" : "\n") + line;
  if (code != 0 && refused.empty())
    throw std::runtime_error("nct check --cases failed (exit " + std::to_string(code)
                             + "): " + tail(io::read_text(log), 3));
  fs::remove(list);
  fs::remove(log);
  return refused;
}

std::string progress(std::size_t done, std::size_t total, std::size_t run_now, double elapsed)
{
  std::ostringstream line;
  line << "[" << done << "/" << total << "]  " << std::fixed << std::setprecision(0) << elapsed
       << " s elapsed";
  if (run_now > 0 && done < total)
    line << ", about " << elapsed / double(run_now) * double(total - done) << " s to go";
  return line.str();
}

std::string tail(const std::string& text, std::size_t n)
{
  std::vector<std::string> lines;
  std::istringstream in(text);
  for (std::string line; std::getline(in, line);)
    lines.push_back(line);
  std::string out;
  for (std::size_t i = lines.size() > n ? lines.size() - n : 0; i < lines.size(); ++i)
    out += lines[i] + "\n";
  return out;
}

} // namespace nct::jobs
