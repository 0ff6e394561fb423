#include "report/report.h"

#include <cerrno>
#include <cstring>
#include <iostream>
#include <spawn.h>
#include <string>
#include <sys/wait.h>
#include <vector>

extern char** environ;

namespace nct::report
{

int write(const std::filesystem::path& folder, const std::filesystem::path& out)
{
  const std::string python = NCT_PYTHON, package = NCT_PYTHON_DIR;
  if (!std::filesystem::is_directory(std::filesystem::path(package) / "nct" / "report"))
  {
    std::cerr << "report: the package nct.report is not at " << package << "/nct/report "
              << "(the source tree this nct was built from)" << std::endl;
    return 127;
  }
  std::vector<std::string> args = {python, "-m", "nct.report", folder.string()};
  if (!out.empty())
    args.insert(args.end(), {"--out", out.string()});
  // The environment as it is, with python/ first on PYTHONPATH.
  std::vector<std::string> env;
  std::string path = "PYTHONPATH=" + package;
  for (char** e = environ; *e; ++e)
  {
    if (std::strncmp(*e, "PYTHONPATH=", 11) == 0)
      path += std::string(":") + (*e + 11);
    else
      env.emplace_back(*e);
  }
  env.push_back(path);
  std::vector<char*> argv, envp;
  for (auto& a : args)
    argv.push_back(a.data());
  argv.push_back(nullptr);
  for (auto& e : env)
    envp.push_back(e.data());
  envp.push_back(nullptr);

  pid_t pid = 0;
  if (const int error
      = posix_spawn(&pid, python.c_str(), nullptr, nullptr, argv.data(), envp.data()))
  {
    std::cerr << "report: cannot start " << python << ": " << std::strerror(error) << std::endl;
    return 127;
  }
  int status = 0;
  while (waitpid(pid, &status, 0) < 0)
    if (errno != EINTR)
      return 127;
  return WIFEXITED(status) ? WEXITSTATUS(status) : 128 + WTERMSIG(status);
}

void after(const std::filesystem::path& folder)
{
  std::cout.flush();
  if (const int code = write(folder); code != 0)
    std::cerr << "report: no report.html in " << folder.string() << " (exit " << code
              << "); the results are written; `nct report " << folder.string() << "` tries again"
              << std::endl;
}

} // namespace nct::report
