// A fit's forward runs: each an `nct run` of the base scene at a point of
// the fitted variables, in out/runs/run-NNNN (a jobs::RunCache), found
// again by its overrides: a resumed fit reads the runs it had finished and
// follows those still on a cluster's queue.
#pragma once

#include <filesystem>
#include <map>
#include <string>
#include <vector>

#include "fit/fit.h"
#include "jobs/jobs.h"
#include "jobs/run_cache.h"

namespace nct::fit
{

/// The overrides of a forward run at the fitted variables theta: the
/// fit's, then each parameter's keys.
std::vector<std::string> forward_sets(const Fit& fit, const std::vector<double>& theta);

/// The forward runs of one fit.
class Forward
{
public:
  /// The runs in options.out/runs: the finished ones kept, those in flight
  /// on `launcher`'s cluster followed, the interrupted ones removed.
  Forward(const Fit& fit, const Options& options, jobs::Launcher launcher);

  /// The overrides of a forward run at the fitted variables theta.
  std::vector<std::string> sets(const std::vector<double>& theta) const
  {
    return forward_sets(_fit, theta);
  }

  /// The run folders at these points (run the missing ones, jobs at a
  /// time); an empty path for a run that failed. Throws Interrupted.
  std::vector<std::filesystem::path> runs(const std::vector<std::vector<double>>& points);

  int done() const { return _done; }          ///< runs finished by this process
  int reusable() const { return _reusable; }  ///< runs found on disk at the start
  int total() const { return int(_finished.size()); } ///< runs finished, reused or not

  /// Thrown by runs() when a signal stopped them.
  struct Interrupted
  {
  };

private:
  /// Run the points' overrides not yet run, `jobs` at a time; the names of
  /// those that finished into _finished.
  void run_missing(const std::vector<std::vector<std::string>>& wanted);

  const Fit& _fit;
  const Options& _options;
  jobs::Launcher _launcher;
  jobs::RunCache _runs;
  /// The finished runs by their overrides: their names.
  std::map<std::vector<std::string>, std::string> _finished;
  /// Runs still on a cluster's queue from a driver that was killed.
  std::map<std::vector<std::string>, std::string> _in_flight;
  int _next = 1, _done = 0, _reusable = 0;
};

} // namespace nct::fit
