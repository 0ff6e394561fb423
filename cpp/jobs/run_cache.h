// Resumable child runs: each in a run folder of its own that records what
// the run was made with (an `nct run`: its scene and --set options) and
// holds its result once it has finished. A driver started again reuses the
// finished runs whose record agrees with what it wants, follows those still
// in flight on a cluster, and starts the others afresh.
#pragma once

#include <filesystem>
#include <set>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "jobs/jobs.h"

namespace nct::jobs
{

/// The record of an `nct run` of `scene` with `sets`:
/// {"scene": the scene's absolute path, "sets": [...]}.
nlohmann::json run_record(const std::filesystem::path& scene,
                          const std::vector<std::string>& sets);

/// A driver's run folders: a study's cases/case-NNN, a fit's runs/run-NNNN,
/// a cohort's patients/NAME.
class RunCache
{
public:
  /// How a run that did not finish starts again.
  enum class Restart
  {
    afresh, ///< its folder cleared
    resume, ///< its folder kept but for its result: the child resumes from it (a cohort's
            ///< patient, whose fit keeps its forward runs)
  };

  /// The runs in `folder` (made if missing), each recording itself in its
  /// file `record` (case.json, run.json, patient.json) and finished once it
  /// holds its file `result` (summary.json, fit.json).
  RunCache(std::filesystem::path folder, std::string record, std::string result);

  /// Run `name`'s folder.
  std::filesystem::path path(const std::string& name) const { return _folder / name; }

  /// The names of the runs in the folder, sorted.
  std::vector<std::string> names() const;

  /// Run `name`'s record; null when it has none.
  nlohmann::json recorded(const std::string& name) const;

  /// Has run `name` finished: its record and its result are there.
  bool finished(const std::string& name) const;

  /// Does run `name`'s record agree with `wanted`: every key both hold has
  /// the same value (a record an older nct wrote may lack a key, e.g. a
  /// study's case.json its scene). A run without a record agrees.
  bool agrees(const std::string& name, const nlohmann::json& wanted) const;

  /// Is run `name` finished with a record that agrees with `wanted`?
  bool reusable(const std::string& name, const nlohmann::json& wanted) const
  {
    return finished(name) && agrees(name, wanted);
  }

  /// Make `job` start run `name` again: just before it starts (not when a
  /// resumed driver finds it still in flight on a cluster), the folder is
  /// made ready as `restart` says and `record` written in it.
  void prepare(Job& job, const std::string& name, const nlohmann::json& record,
               Restart restart = Restart::afresh) const;

  /// The job of an `nct run` of `scene` with `sets` into run `name`, its
  /// console in the folder's console.log, prepared (afresh) with the run
  /// record and the keys of `more` (a study's case name).
  Job nct_run(const std::string& name, const std::filesystem::path& program,
              const std::filesystem::path& scene, const std::vector<std::string>& sets,
              int ranks, const std::string& mpiexec,
              const nlohmann::json& more = nlohmann::json::object()) const;

  /// Remove the runs that will not be reused as they are: those without a
  /// record, and those unfinished that `launcher`'s cluster no longer runs
  /// (interrupted: they run again when wanted). Returns the names of the
  /// unfinished runs still in flight, to be followed.
  std::set<std::string> clean(const Launcher& launcher) const;

private:
  std::filesystem::path _folder;
  std::string _record, _result;
};

} // namespace nct::jobs
