// nct: the command-line front end (check, run, study, describe).
#include <CLI/CLI.hpp>
#include <cstdlib>
#include <iostream>
#include <sstream>

#include "biomarkers/registry.h"
#include "fit/fit.h"
#include "io/checkpoint.h"
#include "run/run.h"
#include "scene/scene.h"
#include "study/study.h"

namespace
{

/// "-ksp_type cg -ksp_monitor" -> {{ksp_type, cg}, {ksp_monitor, ""}}
std::vector<std::pair<std::string, std::string>> parse_petsc(const std::string& text)
{
  std::vector<std::pair<std::string, std::string>> out;
  std::istringstream in(text);
  std::string word;
  while (in >> word)
  {
    if (word.rfind("-", 0) == 0)
      out.emplace_back(word.substr(1), "");
    else if (!out.empty() && out.back().second.empty())
      out.back().second = word;
    else
      throw nct::scene::Error("--petsc: '" + word + "' is not an option name (-name value)");
  }
  return out;
}

/// A test's hook (tests/fit_check.py, mode fallback): with
/// NCT_TEST_DIVERGE_ABOVE="key=x", a run whose --set gives `key` a value
/// above x gets one Newton iteration per step and no step cut, so that it
/// diverges as a run beyond the model's reach would.
void test_divergence(std::vector<std::string>& sets)
{
  const char* spec = std::getenv("NCT_TEST_DIVERGE_ABOVE");
  if (!spec)
    return;
  const std::string s = spec, key = s.substr(0, s.find('='));
  const double above = std::stod(s.substr(s.find('=') + 1));
  for (const auto& set : std::vector<std::string>(sets))
    if (set.rfind(key + "=", 0) == 0 && std::stod(set.substr(key.size() + 1)) > above)
      sets.insert(sets.end(), {"solver.max_iterations=1", "solver.max_step_cuts=0"});
}

} // namespace

int main(int argc, char* argv[])
{
  CLI::App app{"nct: in-silico non-contact tonometry (Corvis ST air-puff test)"};
  app.require_subcommand(1);
  std::string scene_file, out, petsc;
  std::vector<std::string> sets;
  bool markdown = false;

  auto* check = app.add_subcommand("check", "validate a scene file and exit");
  check->add_option("scene", scene_file, "scene file (TOML)")->required();
  check->add_option("--set", sets, "override a key: section.key=value");

  auto* run = app.add_subcommand("run", "run a scene into a run folder");
  run->add_option("scene", scene_file, "scene file (TOML)")->required();
  run->add_option("--set", sets, "override a key: section.key=value");
  std::string resume;
  auto* out_option = run->add_option("--out", out, "run folder (default: runs/<scene name>)");
  run->add_option("--resume", resume,
                  "continue the run in this folder from its last checkpoint "
                  "(checkpoint.steps; the same scene, --set and --petsc, any rank count)")
      ->excludes(out_option);
  run->add_option("--petsc", petsc, "PETSc options, e.g. \"-ksp_type cg -pc_type gamg\"");

  std::string study_file;
  int jobs = 0;
  bool dry_run = false;
  auto* study = app.add_subcommand("study", "run a study (a design over a scene's keys) and "
                                            "analyse it; resumes an interrupted one");
  study->add_option("study", study_file, "study file (TOML)")->required();
  study->add_option("--out", out, "study folder (default: studies/<study name>)");
  study->add_option("--jobs", jobs, "cases at once (default: the study's)")
      ->check(CLI::Range(1, 4096));
  study->add_flag("--dry-run", dry_run, "check every case and list them; run none");
  std::string launcher;
  study->add_option("--launcher", launcher, "where the cases run (default: the study's)")
      ->check(CLI::IsMember({"local", "slurm"}));

  std::string fit_file;
  auto* fit = app.add_subcommand("fit", "fit scene keys (stiffness, IOP...) to a patient's "
                                        "readings; resumes an interrupted fit");
  fit->add_option("fit", fit_file, "fit file (TOML)")->required();
  fit->add_option("--out", out, "fit folder (default: fits/<fit name>)");
  fit->add_option("--jobs", jobs, "forward runs at once (default: the fit's)")
      ->check(CLI::Range(1, 4096));
  fit->add_flag("--dry-run", dry_run, "check the fit file and the start's scene; run nothing");
  fit->add_option("--launcher", launcher, "where the forward runs go (default: the fit's)")
      ->check(CLI::IsMember({"local", "slurm"}));
  std::string patient;
  fit->add_option("--patient", patient, "a cohort's fit file: fit this patient (a row of "
                                        "its table) only");

  auto* describe = app.add_subcommand("describe", "print every scene key with its documentation");
  describe->add_flag("--markdown", markdown, "as a Markdown table");
  bool biomarkers = false;
  describe->add_flag("--biomarkers", biomarkers,
                     "the biomarker registry instead: every summary.json value studies compare "
                     "and fits read, with its unit and meaning (JSON, or --markdown)");

  try
  {
    app.parse(argc, argv);
  }
  catch (const CLI::ParseError& e)
  {
    if (e.get_exit_code() == 0) // --help
      return app.exit(e);
    // Bad command lines are bad input too: exit code 2.
    std::cerr << "error: " << e.what() << "; 'nct --help' lists the options" << std::endl;
    return 2;
  }

  if (describe->parsed())
  {
    std::cout << (biomarkers ? nct::biomarkers::describe(markdown)
                             : nct::scene::describe(markdown));
    return 0;
  }

  // A study or a fit starts each run as an MPI job of its own: it is no
  // MPI process itself.
  if (study->parsed() || fit->parsed())
  {
    const std::string verb = study->parsed() ? "study" : "fit";
    if (const char* size = std::getenv("OMPI_COMM_WORLD_SIZE"); size && std::atoi(size) > 1)
    {
      std::cerr << "error: nct " << verb << " starts an MPI job per run: run it without mpirun "
                << "(" << verb << ".ranks sets the ranks of each run)" << std::endl;
      return 2;
    }
    try
    {
      const auto program = std::filesystem::read_symlink("/proc/self/exe");
      if (fit->parsed())
      {
        auto f = nct::fit::Fit::load(fit_file, patient);
        nct::fit::Options options;
        options.out = out.empty() ? std::filesystem::path("fits")
                                        / std::filesystem::path(fit_file).stem()
                                        / (patient.empty() ? "" : "patients/" + patient)
                                  : std::filesystem::path(out);
        options.program = program;
        options.jobs = jobs;
        options.dry_run = dry_run;
        options.launcher = launcher;
        return f.cohort ? nct::fit::run_cohort(f, options) : nct::fit::run(f, options);
      }
      auto s = nct::study::Study::load(study_file);
      nct::study::Options options;
      options.out = out.empty() ? std::filesystem::path("studies")
                                      / std::filesystem::path(study_file).stem()
                                : std::filesystem::path(out);
      options.program = program;
      options.jobs = jobs;
      options.dry_run = dry_run;
      options.launcher = launcher;
      return nct::study::run(s, options);
    }
    catch (const nct::scene::Error& e)
    {
      std::cerr << "error: " << e.what() << std::endl;
      return 2;
    }
    catch (const std::exception& e)
    {
      std::cerr << "error: " << e.what() << std::endl;
      return 1;
    }
  }

  nct::Runtime runtime(argv[0]);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);

  int code = 0;
  try
  {
    if (run->parsed())
      test_divergence(sets);
    const nct::Input input = nct::read(MPI_COMM_WORLD, scene_file, sets);
    if (check->parsed())
    {
      if (rank == 0)
        std::cout << scene_file << ": ok\n";
    }
    else
    {
      nct::RunOptions options;
      options.out = out.empty() ? std::filesystem::path("runs")
                                      / std::filesystem::path(scene_file).stem()
                                : std::filesystem::path(out);
      options.petsc = parse_petsc(petsc);
      if (!resume.empty())
        options.out = resume, options.resume = true;
      nct::run(MPI_COMM_WORLD, input, options);
    }
  }
  catch (const nct::scene::Error& e)
  {
    if (rank == 0)
      std::cerr << "error: " << e.what() << std::endl;
    code = 2;
  }
  catch (const nct::io::CheckpointError& e)
  {
    if (rank == 0)
      std::cerr << "error: " << e.what() << std::endl;
    code = 2;
  }
  catch (const nct::Diverged& e)
  {
    if (rank == 0)
      std::cerr << "error: " << e.what() << std::endl;
    code = 3;
  }
  catch (const std::exception& e)
  {
    std::cerr << "error (rank " << rank << "): " << e.what() << std::endl;
    code = 1;
  }
  return code;
}
