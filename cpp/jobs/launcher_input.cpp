#include "jobs/launcher_input.h"

#include <algorithm>
#include <stdexcept>
#include <thread>

#include "jobs/slurm.h"

namespace nct::jobs
{

RunKeys read_run_keys(const toml::table& t, const std::string& section,
                      const std::filesystem::path& file, io::KeyErrors& errors)
{
  RunKeys keys;
  auto integer = [&](const char* key, long def, long lo, long hi)
  { return io::integer(t, section, key, def, lo, hi, file); };
  errors.attempt([&] { keys.ranks = integer("ranks", 1, 1, 4096); });
  errors.attempt([&] {
    const long cores = std::max(1u, std::thread::hardware_concurrency());
    keys.jobs = integer("jobs", std::max(1L, cores / keys.ranks), 1, 4096);
  });
  errors.attempt([&] {
    keys.mpiexec = t["mpiexec"].value_or<std::string>("mpiexec --bind-to none");
    if (keys.mpiexec.find_first_not_of(" \t") == std::string::npos)
      throw io::key_error(file, section + ".mpiexec",
                          "empty: the MPI launcher, e.g. \"mpiexec --bind-to none\"");
  });
  return keys;
}

Launcher read_launcher(const toml::table& t, const std::string& section,
                       const std::filesystem::path& file, io::KeyErrors& errors)
{
  Launcher l;
  const std::string key = section + ".launcher", slurm = section + ".slurm";
  errors.attempt([&] {
    const std::string kind = t["launcher"].value_or(std::string("local"));
    if (kind != "local" && kind != "slurm")
      throw io::key_error(file, key, "\"local\" (this machine) or \"slurm\" (job arrays on a "
                                     "Slurm cluster), got \"" + kind + "\"");
    l.kind = kind == "slurm" ? Launcher::Kind::slurm : Launcher::Kind::local;
  });
  const toml::table* st = t["slurm"].as_table();
  if (!st)
    return l;
  io::refuse_unknown_keys(*st, {"partition", "account", "time_limit", "cores_per_rank", "options"},
                          file, slurm + ".", "[" + slurm + "]", errors);
  auto text = [&](const char* name, std::string& into)
  {
    errors.attempt([&] {
      if (auto* v = (*st)[name].node())
      {
        if (!v->is_string() || v->as_string()->get().empty())
          throw io::key_error(file, slurm + "." + name, "a non-empty string");
        into = v->as_string()->get();
      }
    });
  };
  text("partition", l.partition);
  text("account", l.account);
  text("time_limit", l.time_limit);
  errors.attempt([&] { l.cores_per_rank = io::integer(*st, slurm, "cores_per_rank", 1, 1, 4096, file); });
  errors.attempt([&] {
    if (auto* v = (*st)["options"].node())
      l.options = io::string_list(*v, file, slurm + ".options", false);
  });
  if (l.kind != Launcher::Kind::slurm)
    errors.attempt([&] {
      throw io::key_error(file, slurm, "Slurm's options, but " + key + " is \"local\"; set it "
                                       "to \"slurm\" or remove the table");
    });
  return l;
}

Launcher launcher_for(const Launcher& from_file, const std::string& kind,
                      const std::filesystem::path& folder, int ranks, const std::string& section,
                      const std::filesystem::path& file)
{
  Launcher l = from_file;
  if (!kind.empty())
    l.kind = kind == "slurm" ? Launcher::Kind::slurm : Launcher::Kind::local;
  l.folder = folder;
  if (l.kind == Launcher::Kind::slurm)
    try
    {
      slurm::check(l, ranks, section + ".");
    }
    catch (const std::runtime_error& e)
    {
      throw scene::Error(file.string() + ": " + e.what());
    }
  return l;
}

} // namespace nct::jobs
