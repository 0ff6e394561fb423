#include "jobs/run_cache.h"

#include <algorithm>

#include "io/output.h"
#include "io/text.h"
#include "jobs/slurm.h"

namespace nct::jobs
{
namespace fs = std::filesystem;

nlohmann::json run_record(const fs::path& scene, const std::vector<std::string>& sets)
{
  return {{"scene", fs::absolute(scene).string()}, {"sets", sets}};
}

RunCache::RunCache(fs::path folder, std::string record, std::string result)
    : _folder(std::move(folder)), _record(std::move(record)), _result(std::move(result))
{
  fs::create_directories(_folder);
}

std::vector<std::string> RunCache::names() const
{
  std::vector<std::string> out;
  for (const auto& entry : fs::directory_iterator(_folder))
    out.push_back(entry.path().filename().string());
  std::sort(out.begin(), out.end());
  return out;
}

nlohmann::json RunCache::recorded(const std::string& name) const
{
  const fs::path file = path(name) / _record;
  return fs::exists(file) ? nlohmann::json::parse(io::read_text(file)) : nlohmann::json();
}

bool RunCache::finished(const std::string& name) const
{
  return fs::exists(path(name) / _record) && fs::exists(path(name) / _result);
}

bool RunCache::agrees(const std::string& name, const nlohmann::json& wanted) const
{
  const nlohmann::json record = recorded(name);
  for (const auto& [key, value] : record.items())
    if (wanted.contains(key) && wanted[key] != value)
      return false;
  return true;
}

void RunCache::prepare(Job& job, const std::string& name, const nlohmann::json& record,
                       Restart restart) const
{
  job.prepare = [dir = path(name), file = _record, result = _result,
                 text = record.dump(2) + "\n", restart]
  {
    if (restart == Restart::afresh)
      fs::remove_all(dir);
    fs::create_directories(dir);
    fs::remove(dir / result);
    io::write_atomic(dir / file, text);
  };
}

Job RunCache::nct_run(const std::string& name, const fs::path& program, const fs::path& scene,
                      const std::vector<std::string>& sets, int ranks, const std::string& mpiexec,
                      const nlohmann::json& more) const
{
  const fs::path dir = path(name);
  Job job{nct_command(program, "run", scene, sets, dir), fs::absolute(dir / "console.log"), ranks,
          mpiexec, nullptr};
  nlohmann::json record = run_record(scene, sets);
  record.update(more);
  prepare(job, name, record);
  return job;
}

std::set<std::string> RunCache::clean(const Launcher& launcher) const
{
  const std::set<std::string> queued = slurm::in_flight(launcher);
  std::set<std::string> followed;
  for (const std::string& name : names())
  {
    const bool recorded = fs::exists(path(name) / _record);
    const bool in_flight
        = queued.count(fs::absolute(path(name) / "console.log").lexically_normal().string());
    if (recorded && !finished(name) && in_flight)
      followed.insert(name);
    else if (!recorded || !finished(name))
      fs::remove_all(path(name));
  }
  return followed;
}

} // namespace nct::jobs
