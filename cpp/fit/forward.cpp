// A fit's forward runs (cpp/fit/forward.h).
#include "fit/forward.h"

#include <algorithm>
#include <chrono>
#include <iostream>
#include <set>

#include <nlohmann/json.hpp>

#include "io/format.h"
#include "io/text.h"
#include "io/toml_input.h"

namespace nct::fit
{
namespace fs = std::filesystem;
using io::format;

Forward::Forward(const Fit& fit, const Options& options, jobs::Launcher launcher)
    : _fit(fit), _options(options), _launcher(std::move(launcher)),
      _runs(options.out / "runs", "run.json", "summary.json")
{
  // A run a driver killed before it left on a cluster's queue is followed;
  // an interrupted one runs again when needed.
  const std::set<std::string> followed = _runs.clean(_launcher);
  for (const std::string& name : _runs.names())
  {
    const auto sets = _runs.recorded(name).at("sets").get<std::vector<std::string>>();
    (followed.count(name) ? _in_flight : _finished)[sets] = name;
    _next = std::max(_next, std::stoi(name.substr(4)) + 1);
  }
  _reusable = int(_finished.size());
}

std::vector<std::string> forward_sets(const Fit& fit, const std::vector<double>& theta)
{
  std::vector<std::string> out = {"output.fields=false"};
  out.insert(out.end(), fit.sets.begin(), fit.sets.end());
  for (std::size_t i = 0; i < theta.size(); ++i)
    for (auto& k : fit.parameters[i].keys)
      out.push_back(k + "=" + io::literal(fit.parameters[i].value(theta[i])));
  return out;
}

void Forward::run_missing(const std::vector<std::vector<std::string>>& wanted)
{
  std::vector<std::vector<std::string>> todo_sets;
  std::vector<std::string> todo_names;
  std::vector<jobs::Job> todo;
  for (auto& s : wanted)
  {
    if (_finished.count(s) || std::count(todo_sets.begin(), todo_sets.end(), s))
      continue;
    auto in_flight = _in_flight.find(s);
    const std::string name
        = in_flight != _in_flight.end() ? in_flight->second : format("run-%04d", _next++);
    if (in_flight != _in_flight.end())
      _in_flight.erase(in_flight);
    todo_sets.push_back(s);
    todo_names.push_back(name);
    todo.push_back(_runs.nct_run(name, _options.program, _fit.scene, s, _fit.ranks, _fit.mpiexec));
  }
  const int at_once = _options.jobs > 0 ? _options.jobs : _fit.jobs;
  // A line per forward run: [done/this step's runs], the time to go.
  const auto start = std::chrono::steady_clock::now();
  std::size_t finished = 0;
  auto done = [&](std::size_t i, int code)
  {
    const double elapsed
        = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
    ++finished;
    std::cout << "  forward " << todo_names[i]
              << (code == 0 ? std::string(" done") : format(" failed (exit %d)", code)) << "  "
              << jobs::progress(finished, todo.size(), finished, elapsed) << std::endl;
  };
  if (!jobs::run(_launcher, todo, at_once, done))
    throw Interrupted();
  for (std::size_t i = 0; i < todo.size(); ++i)
    if (_runs.finished(todo_names[i]))
    {
      _finished[todo_sets[i]] = todo_names[i];
      ++_done;
    }
    else
    {
      const fs::path console = _runs.path(todo_names[i]) / "console.log";
      std::cerr << "fit: forward run " << todo_names[i] << " stopped without a summary; "
                << console.string() << " ends:\n"
                << jobs::tail(io::read_text(console), 4);
    }
}

std::vector<fs::path> Forward::runs(const std::vector<std::vector<double>>& points)
{
  std::vector<std::vector<std::string>> wanted;
  for (auto& p : points)
    wanted.push_back(sets(p));
  run_missing(wanted);
  std::vector<fs::path> out;
  for (auto& s : wanted)
  {
    auto it = _finished.find(s);
    const bool converged
        = it != _finished.end()
          && nlohmann::json::parse(io::read_text(_runs.path(it->second) / "summary.json"))
                     .value("status", "")
                 == "converged";
    out.push_back(converged ? _runs.path(it->second) : fs::path());
  }
  return out;
}

} // namespace nct::fit
