// Running a study (cpp/study/study.h): every case checked, then run (or
// found finished) in its own run folder, then its tables (study/tables.h).
#include "study/study.h"

#include <algorithm>
#include <chrono>
#include <iostream>

#include <nlohmann/json.hpp>

#include "io/format.h"
#include "io/output.h"
#include "io/text.h"
#include "jobs/jobs.h"
#include "jobs/launcher_input.h"
#include "jobs/run_cache.h"
#include "scene/scene.h"
#include "study/tables.h"

namespace nct::study
{
using io::format;
using io::read_text;
using jobs::tail;
using scene::Error;
namespace fs = std::filesystem;

namespace
{

/// What case c's folder records: its name, scene and overrides.
nlohmann::json case_record(const Study& s, std::size_t c)
{
  nlohmann::json record = jobs::run_record(s.cases[c].scene, s.cases[c].sets);
  record["case"] = s.case_name(c);
  return record;
}

/// The cases still to run; the finished ones' results into `results`. A
/// folder run with other overrides means another study: refuse to mix.
std::vector<std::size_t> cases_to_run(const Study& s, const Options& o,
                                      const jobs::RunCache& cases, std::vector<Result>& results)
{
  std::vector<std::size_t> todo;
  for (std::size_t c = 0; c < s.cases.size(); ++c)
  {
    const std::string name = s.case_name(c);
    if (!cases.agrees(name, case_record(s, c)))
      throw Error(s.file.string() + ": " + o.out.string() + " holds another study (" + name
                  + " was run with other keys); give a new --out or remove it");
    if (cases.finished(name))
      results[c] = read_result(s, cases.path(name));
    else
      todo.push_back(c);
  }
  return todo;
}

/// The study's first line: its design, cases and where they run.
void print_plan(const Study& s, const Options& o, const jobs::Launcher& launcher, int at_once,
                std::size_t done)
{
  std::cout << "study " << s.file.string() << ": " << s.design << ", "
            << (s.variants.empty() ? format("%zu factor(s)", s.factors.size())
                                   : format("%zu variants", s.variants.size()))
            << ", " << s.cases.size() << " cases (" << done << " already done), " << at_once
            << " at once on " << s.ranks << " rank(s) each"
            << (launcher.kind == jobs::Launcher::Kind::slurm ? " through Slurm" : "") << " -> "
            << o.out.string() << std::endl;
}

/// Every case to run must pass `nct check` (the eye's geometry, the
/// puff...) before any runs: a scene::Error naming the first that does
/// not. False when interrupted.
bool check_cases(const Study& s, const Options& o, const std::vector<std::size_t>& todo)
{
  std::vector<jobs::SceneCase> cases;
  for (std::size_t c : todo)
    cases.push_back({s.cases[c].scene, s.cases[c].sets});
  std::vector<std::pair<std::size_t, std::string>> refused;
  try
  {
    refused = jobs::check_scenes(o.program, cases, o.out / "cases");
  }
  catch (const std::runtime_error& e)
  {
    if (!jobs::interrupted())
      throw;
    std::cerr << "study: interrupted while checking the cases" << std::endl;
    return false;
  }
  if (!refused.empty())
  {
    const std::size_t c = todo[refused[0].first];
    std::string why = tail(refused[0].second, 3);
    if (why.rfind("error: ", 0) == 0)
      why.erase(0, 7);
    while (!why.empty() && why.back() == '\n')
      why.pop_back();
    throw Error(s.file.string() + ": " + s.case_name(c) + " (" + s.describe(s.cases[c]) + "): " + why);
  }
  return true;
}

/// --dry-run: every case with what it sets, those done marked.
void list_cases(const Study& s, const std::vector<std::size_t>& todo)
{
  for (std::size_t c = 0; c < s.cases.size(); ++c)
  {
    std::string sets; // an ablation: what the variant sets
    for (std::size_t i = 0; s.cases[c].variant >= 0 && i < s.cases[c].sets.size(); ++i)
      sets += (i ? " " : " (") + s.cases[c].sets[i] + (i + 1 < s.cases[c].sets.size() ? "" : ")");
    std::cout << "  " << s.case_name(c) << ": " << s.describe(s.cases[c]) << sets
              << (std::find(todo.begin(), todo.end(), c) == todo.end() ? "  (done)" : "")
              << "\n";
  }
  std::cout << "study: every case checks out; nothing run (--dry-run)" << std::endl;
}

/// A finished case's progress line: its result, its first responses and
/// the time left at this pace (`run_now` cases run by this process).
std::string progress_line(const Study& s, std::size_t c, const Result& r, std::size_t finished,
                          std::size_t run_now, double elapsed)
{
  const std::size_t n = s.cases.size();
  std::string line = format("%s %s (%s)", s.case_name(c).c_str(), r.status.c_str(),
                            s.describe(s.cases[c]).c_str());
  for (std::size_t j = 0; j < std::min<std::size_t>(s.responses.size(), 4); ++j)
    line += " " + s.responses[j] + "=" + format("%.4g", r.responses[j]);
  return line + "  " + jobs::progress(finished, n, run_now, elapsed);
}

/// Run the cases `todo` (an interrupted one afresh; one still running on
/// a cluster is followed), `at_once` at a time, each one's result into
/// `results` and cases.csv as it ends. False when interrupted.
bool run_cases(const Study& s, const Options& o, const jobs::RunCache& cases,
               const jobs::Launcher& launcher, int at_once, const std::vector<std::size_t>& todo,
               std::vector<Result>& results)
{
  const std::size_t n = s.cases.size();
  std::vector<jobs::Job> runs;
  for (std::size_t c : todo)
    runs.push_back(cases.nct_run(s.case_name(c), o.program, s.cases[c].scene, s.cases[c].sets,
                                 s.ranks, s.mpiexec, {{"case", s.case_name(c)}}));
  const auto start = std::chrono::steady_clock::now();
  std::size_t finished = n - todo.size();
  io::write_atomic(o.out / "cases.csv", cases_csv(s, results));
  const bool complete = jobs::run(
      launcher, runs, at_once,
      [&](std::size_t i, int code)
      {
        const std::size_t c = todo[i];
        const fs::path dir = cases.path(s.case_name(c));
        if (fs::exists(dir / "summary.json"))
          results[c] = read_result(s, dir);
        else if (jobs::interrupted())
          return; // stopped: it stays pending
        else
        {
          results[c].status = "error";
          std::cerr << s.case_name(c) << ": nct run exited with " << code << " and no summary; "
                    << (dir / "console.log").string() << " ends:\n"
                    << tail(read_text(dir / "console.log"), 5);
        }
        ++finished;
        const double elapsed
            = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::cout << progress_line(s, c, results[c], finished, finished - (n - todo.size()),
                                   elapsed)
                  << std::endl;
        io::write_atomic(o.out / "cases.csv", cases_csv(s, results));
      });
  if (!complete)
    std::cerr << "study: interrupted with " << finished << " of " << n
              << " cases done; the same command resumes it" << std::endl;
  return complete;
}

} // namespace

int run(const Study& s, const Options& o)
{
  const int at_once = o.jobs > 0 ? o.jobs : s.jobs;
  // Slurm must take the options before anything runs or is submitted.
  const jobs::Launcher launcher
      = jobs::launcher_for(s.launcher, o.launcher, o.out, s.ranks, "study", s.file);
  std::error_code ec;
  fs::create_directories(o.out / "cases", ec);
  if (ec)
    throw std::runtime_error("cannot create the study folder " + o.out.string() + ": "
                             + ec.message());

  const jobs::RunCache cases(o.out / "cases", "case.json", "summary.json");
  std::vector<Result> results(s.cases.size(), pending(s));
  const std::vector<std::size_t> todo = cases_to_run(s, o, cases, results);
  print_plan(s, o, launcher, at_once, s.cases.size() - todo.size());
  jobs::catch_interrupts();
  if (!check_cases(s, o, todo))
    return 130;
  if (o.dry_run)
  {
    list_cases(s, todo);
    return 0;
  }
  io::write_atomic(o.out / "study.toml", read_text(s.file));
  if (!run_cases(s, o, cases, launcher, at_once, todo, results))
    return 130;
  io::write_atomic(o.out / "cases.csv", cases_csv(s, results));
  analyse(s, results, o.out);
  return report_outcome(s, results, o.out);
}

} // namespace nct::study
