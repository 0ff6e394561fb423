#include "jobs/slurm.h"

#include <chrono>
#include <cstdio>
#include <fstream>
#include <iostream>
#include <map>
#include <set>
#include <sstream>
#include <stdexcept>
#include <thread>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include "io/format.h"
#include "io/output.h"
#include "io/text.h"

namespace nct::jobs::slurm
{
namespace fs = std::filesystem;
namespace
{

/// A word quoted for the shell.
std::string quote(const std::string& word)
{
  std::string q = "'";
  for (char c : word)
    q += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return q + "'";
}

std::string quote(const std::vector<std::string>& words)
{
  std::string line;
  for (const auto& w : words)
  {
    if (!line.empty())
      line += ' ';
    line += quote(w);
  }
  return line;
}

/// Run a command line; its exit code and its output (stdout and stderr).
std::pair<int, std::string> capture(const std::vector<std::string>& argv)
{
  FILE* pipe = popen((quote(argv) + " 2>&1").c_str(), "r");
  if (!pipe)
    throw std::runtime_error("cannot run " + argv.front());
  std::string out;
  char buffer[4096];
  while (std::size_t n = std::fread(buffer, 1, sizeof buffer, pipe))
    out.append(buffer, n);
  const int status = pclose(pipe);
  while (!out.empty() && (out.back() == '\n' || out.back() == ' '))
    out.pop_back();
  return {WIFEXITED(status) ? WEXITSTATUS(status) : 128, out};
}

/// Is `program` an executable on the PATH?
bool on_path(const std::string& program)
{
  const char* path = std::getenv("PATH");
  std::istringstream dirs(path ? path : "");
  for (std::string dir; std::getline(dirs, dir, ':');)
    if (!dir.empty() && access((fs::path(dir) / program).c_str(), X_OK) == 0)
      return true;
  return false;
}

/// sbatch's options of the launcher for a job of `ranks` ranks.
std::vector<std::string> sbatch_options(const Launcher& l, int ranks)
{
  std::vector<std::string> o = {"--ntasks=" + std::to_string(ranks),
                                "--cpus-per-task=" + std::to_string(l.cores_per_rank)};
  if (!l.partition.empty())
    o.push_back("--partition=" + l.partition);
  if (!l.account.empty())
    o.push_back("--account=" + l.account);
  if (!l.time_limit.empty())
    o.push_back("--time=" + l.time_limit);
  o.insert(o.end(), l.options.begin(), l.options.end());
  return o;
}

/// The states of a task that has not ended.
bool alive(const std::string& state)
{
  static const std::set<std::string> states
      = {"PENDING",  "RUNNING",   "CONFIGURING", "COMPLETING",   "SUSPENDED",    "REQUEUED",
         "RESIZING", "SIGNALING", "STAGE_OUT",   "REQUEUE_HOLD", "REQUEUE_FED",
         "RESV_DEL_HOLD"};
  return states.count(state) > 0;
}

/// Slurm's state of every task of these arrays that squeue still knows,
/// by "<array job>_<task>".
std::map<std::string, std::string> states(const std::set<std::string>& arrays)
{
  std::map<std::string, std::string> out;
  for (const auto& id : arrays)
  {
    // One array at a time: squeue refuses a list with one id it no longer knows.
    const auto [code, text] = capture({"squeue", "-h", "-r", "-t", "all", "-j", id, "-o", "%i %T"});
    if (code != 0)
      continue;
    std::istringstream lines(text);
    for (std::string task, state; lines >> task >> state;)
      out[task] = state;
  }
  return out;
}

/// The array job of a task id "<array job>_<task>".
std::string array_of(const std::string& task) { return task.substr(0, task.find('_')); }

/// The folder's record of submitted jobs: log file -> task id.
struct Record
{
  explicit Record(const fs::path& folder) : file(folder / "slurm" / "submitted.json")
  {
    if (fs::exists(file))
      tasks = nlohmann::json::parse(io::read_text(file)).get<std::map<std::string, std::string>>();
  }
  void save() const
  {
    fs::create_directories(file.parent_path());
    io::write_atomic(file, nlohmann::json(tasks).dump(1) + "\n");
  }
  fs::path file;
  std::map<std::string, std::string> tasks;
};

/// Submit `jobs[indices]` (one number of ranks) as one array, at most
/// `at_once` running; returns the array's job id.
std::string submit(const Launcher& l, const std::vector<Job>& jobs,
                   const std::vector<std::size_t>& indices, int at_once)
{
  const fs::path dir = fs::absolute(l.folder / "slurm");
  fs::create_directories(dir);
  const std::string stamp = std::to_string(
      std::chrono::system_clock::now().time_since_epoch() / std::chrono::milliseconds(1));
  const fs::path list = dir / ("array-" + stamp + ".txt"), script = dir / ("array-" + stamp + ".sh");
  const std::string cwd = fs::current_path().string();
  std::string lines;
  for (std::size_t i : indices)
  {
    const Job& job = jobs[i];
    std::vector<std::string> command;
    if (job.ranks > 1)
      command = {"srun", "--mpi=pmix", "-n", std::to_string(job.ranks)};
    command.insert(command.end(), job.argv.begin(), job.argv.end());
    const std::string log = quote(job.log.string()), exit = quote(job.log.string() + ".exit");
    lines += "cd " + quote(cwd) + " && { " + quote(command) + " > " + log + " 2>&1; echo $? > "
             + exit + ".tmp && mv " + exit + ".tmp " + exit + "; }\n";
  }
  io::write_atomic(list, lines);
  io::write_atomic(script, "#!/bin/sh\n# nct: " + std::to_string(indices.size())
                               + " jobs as one Slurm job array; task k runs line k + 1 of\n# "
                               + list.string() + "\nexec /bin/sh -c \"$(sed -n "
                               "\"$((SLURM_ARRAY_TASK_ID + 1))p\" " + quote(list.string())
                               + ")\"\n");
  std::vector<std::string> argv = {"sbatch", "--parsable", "--job-name=nct",
                                   "--array=0-" + std::to_string(indices.size() - 1) + "%"
                                       + std::to_string(std::max(at_once, 1)),
                                   "--output=" + (dir / "slurm-%A_%a.out").string()};
  const auto options = sbatch_options(l, jobs[indices.front()].ranks);
  argv.insert(argv.end(), options.begin(), options.end());
  argv.push_back(script.string());
  const auto [code, out] = capture(argv);
  if (code != 0)
    throw std::runtime_error("sbatch refused the jobs (exit " + std::to_string(code) + "): " + out);
  return out.substr(0, out.find(';'));
}

/// A job's key in the record: its log's absolute path.
std::string key(const Job& job) { return fs::absolute(job.log).lexically_normal().string(); }

/// The exit code a task left next to its log, or -1.
int exit_code(const Job& job)
{
  std::ifstream in(job.log.string() + ".exit");
  int code = -1;
  return (in >> code) ? code : -1;
}

/// A job's task has ended (Slurm's `state`, empty when Slurm no longer
/// knows it): `done` with its exit code. One that Slurm ended (cancelled,
/// out of time, its node lost...) or that left no exit code counts as
/// failed, with Slurm's state appended to its log.
void finish(const Job& job, const std::string& task, const std::string& state,
            const std::function<void(int)>& done)
{
  int code = exit_code(job);
  if (code < 0 || (!state.empty() && state != "COMPLETED"))
  {
    // Slurm ended it (cancelled, out of time, its node lost...), or no
    // longer knows it (a task cancelled before it started leaves no record).
    std::ofstream log(job.log, std::ios::app);
    log << "slurm: task " << task << " ended "
        << (state.empty() ? std::string("and Slurm no longer knows it") : state);
    if (code < 0)
      log << " without an exit code";
    log << "\n";
    if (code < 0)
      code = state == "CANCELLED" || state.empty() ? 130 : 1;
  }
  done(code);
}

/// The jobs' tasks: those the folder's record shows still queued or
/// running are followed; those that ended well while no driver followed
/// them are done; the rest are submitted, one array per number of ranks
/// (each prepared first). Returns job -> task id of those to follow.
std::map<std::size_t, std::string>
follow_or_submit(const Launcher& l, const std::vector<Job>& jobs, int at_once,
                 const std::function<void(std::size_t, int)>& done)
{
  Record record(l.folder);
  std::set<std::string> arrays;
  for (const auto& [log, task] : record.tasks)
    arrays.insert(array_of(task));
  auto now = states(arrays);
  std::map<std::size_t, std::string> tracked; // job -> task id
  std::map<int, std::vector<std::size_t>> to_submit;
  for (std::size_t i = 0; i < jobs.size(); ++i)
  {
    auto it = record.tasks.find(key(jobs[i]));
    if (it != record.tasks.end() && now.count(it->second) && alive(now[it->second]))
    {
      tracked[i] = it->second;
      std::cout << "slurm: " << jobs[i].log.parent_path().filename().string()
                << " is still in Slurm's queue as task " << it->second << " ("
                << now[it->second] << "): followed, not submitted again" << std::endl;
      continue;
    }
    if (it != record.tasks.end() && exit_code(jobs[i]) == 0)
    {
      done(i, 0); // it ended well while no driver was following it
      continue;
    }
    to_submit[jobs[i].ranks].push_back(i);
  }
  for (const auto& [ranks, indices] : to_submit)
  {
    for (std::size_t i : indices)
    {
      if (jobs[i].prepare)
        jobs[i].prepare();
      fs::remove(jobs[i].log.string() + ".exit");
    }
    const std::string id = submit(l, jobs, indices, at_once);
    std::cout << "slurm: submitted " << indices.size() << " job(s) as array " << id << " ("
              << ranks << " rank(s) each, at most " << at_once << " at once)" << std::endl;
    for (std::size_t k = 0; k < indices.size(); ++k)
    {
      tracked[indices[k]] = id + "_" + std::to_string(k);
      record.tasks[key(jobs[indices[k]])] = tracked[indices[k]];
    }
    record.save();
  }
  return tracked;
}

/// Interrupted: what ended before the signal counts; the rest of the
/// `tracked` tasks are cancelled (scancel), waited for, and done as Slurm
/// ended them.
void cancel(const std::vector<Job>& jobs, std::map<std::size_t, std::string>& tracked,
            const std::function<void(std::size_t, int)>& done)
{
  std::set<std::string> unfinished;
  for (const auto& [i, task] : tracked)
    unfinished.insert(array_of(task));
  auto now = states(unfinished);
  for (auto it = tracked.begin(); it != tracked.end();)
    if (now.count(it->second) && alive(now[it->second]))
      ++it;
    else
    {
      finish(jobs[it->first], it->second, now.count(it->second) ? now[it->second] : "",
             [&, i = it->first](int code) { done(i, code); });
      it = tracked.erase(it);
    }
  unfinished.clear();
  for (const auto& [i, task] : tracked)
    unfinished.insert(array_of(task));
  std::vector<std::string> argv = {"scancel"};
  for (const auto& [i, task] : tracked)
    argv.push_back(task);
  if (!tracked.empty())
    capture(argv);
  std::string ids;
  for (const auto& id : unfinished)
    ids += (ids.empty() ? "" : ", ") + id;
  std::cerr << "slurm: interrupted: cancelled " << tracked.size() << " unfinished job(s)"
            << (ids.empty() ? "" : " of array(s) " + ids) << " (scancel)" << std::endl;
  // A task may have ended just before: wait for Slurm to end them all.
  for (int wait = 0; wait < 300; ++wait)
  {
    now = states(unfinished);
    bool any = false;
    for (const auto& [i, task] : tracked)
      any = any || (now.count(task) && alive(now[task]));
    if (!any)
      break;
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  for (const auto& [i, task] : tracked)
    finish(jobs[i], task, now.count(task) ? now[task] : "CANCELLED",
           [&, i = i](int code) { done(i, code); });
}

} // namespace

void check(const Launcher& l, int ranks, const std::string& prefix)
{
  auto refuse = [&](const std::string& key, const std::string& why)
  { throw std::runtime_error("key '" + prefix + key + "': " + why); };
  if (!on_path("sbatch") || !on_path("squeue") || !on_path("scancel"))
    refuse("launcher", "\"slurm\" needs Slurm's sbatch, squeue and scancel on the PATH; they "
                       "are not all there");
  if (!l.partition.empty())
  {
    const auto [code, known] = capture({"sinfo", "-h", "-p", l.partition, "-o", "%P"});
    if (code != 0 || known.empty())
    {
      const auto all = capture({"sinfo", "-h", "-o", "%P"}).second;
      refuse("slurm.partition", "Slurm knows no partition '" + l.partition + "'"
                                    + (all.empty() ? std::string() : " (it has: " + all + ")"));
    }
  }
  std::vector<std::string> argv = {"sbatch", "--test-only"};
  const auto options = sbatch_options(l, ranks);
  argv.insert(argv.end(), options.begin(), options.end());
  argv.push_back("--wrap=true");
  const auto [code, out] = capture(argv);
  if (code == 0)
    return;
  // Which key Slurm refused, from its message.
  std::string lower = out;
  for (char& c : lower)
    c = static_cast<char>(std::tolower(c));
  const std::string key = lower.find("time") != std::string::npos      ? "slurm.time_limit"
                          : lower.find("account") != std::string::npos ? "slurm.account"
                          : lower.find("partition") != std::string::npos
                              ? "slurm.partition"
                          : lower.find("cpu") != std::string::npos ? "slurm.cores_per_rank"
                                                                   : "slurm.options";
  refuse(key, "Slurm refuses a job of " + std::to_string(ranks) + " rank(s) with "
                  + quote(options) + ": " + out);
}

std::set<std::string> in_flight(const Launcher& l)
{
  std::set<std::string> logs;
  if (l.kind != Launcher::Kind::slurm)
    return logs;
  Record record(l.folder);
  std::set<std::string> arrays;
  for (const auto& [log, task] : record.tasks)
    arrays.insert(array_of(task));
  const auto now = states(arrays);
  for (const auto& [log, task] : record.tasks)
    if (auto it = now.find(task); it != now.end() && alive(it->second))
      logs.insert(log);
  return logs;
}

bool run(const Launcher& l, const std::vector<Job>& jobs, int at_once,
         const std::function<void(std::size_t, int)>& done)
{
  if (interrupted())
    return false; // as the local launcher: nothing new starts after a signal
  std::map<std::size_t, std::string> tracked = follow_or_submit(l, jobs, at_once, done);
  // Follow them until each has ended.
  while (!tracked.empty())
  {
    if (interrupted())
    {
      cancel(jobs, tracked, done);
      return false;
    }
    std::set<std::string> arrays;
    for (const auto& [i, task] : tracked)
      arrays.insert(array_of(task));
    const auto now = states(arrays);
    for (auto it = tracked.begin(); it != tracked.end();)
    {
      const auto state = now.find(it->second);
      if (state != now.end() && alive(state->second))
      {
        ++it;
        continue;
      }
      finish(jobs[it->first], it->second, state == now.end() ? "" : state->second,
             [&, i = it->first](int code) { done(i, code); });
      it = tracked.erase(it);
    }
    if (!tracked.empty())
      std::this_thread::sleep_for(std::chrono::milliseconds(500));
  }
  return true;
}

} // namespace nct::jobs::slurm
