// nct: the command-line front end (check, run, study, fit, report, describe).
#include <CLI/CLI.hpp>
#include <chrono>
#include <cstdlib>
#include <fstream>
#include <iostream>
#include <sstream>
#include <thread>

#include <nlohmann/json.hpp>

#include "biomarkers/registry.h"
#include "fit/fit.h"
#include "io/checkpoint.h"
#include "report/report.h"
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

/// The command line of `nct check` and `nct run`.
struct SceneArgs
{
  std::string scene_file, out, resume, petsc, cases;
  std::vector<std::string> sets;
  bool no_report = false;
};

/// The command line of `nct study` and `nct fit`.
struct DriverArgs
{
  std::string file, out, launcher, patient;
  int jobs = 0;
  bool dry_run = false, no_report = false;
};

/// The command line of `nct report`.
struct ReportArgs
{
  std::string folder, out;
};

/// The option that turns a run's, study's or fit's page off.
void add_no_report(CLI::App* verb, bool& flag)
{
  verb->add_flag("--no-report", flag,
                 "write no report.html at the end (nct report DIR writes it later)");
}

/// The command line of `nct describe`.
struct DescribeArgs
{
  bool markdown = false, biomarkers = false;
};

CLI::App* add_check(CLI::App& app, SceneArgs& a)
{
  auto* check = app.add_subcommand("check", "validate a scene file and exit");
  auto* scene = check->add_option("scene", a.scene_file, "scene file (TOML)");
  check->add_option("--set", a.sets, "override a key: section.key=value");
  check->add_option("--cases", a.cases,
                    "check many scenes in one process: a file of JSON lines "
                    "{\"scene\": FILE, \"sets\": [...]}; each refused one is said as "
                    "'case I:' and its error (exit 2)")
      ->excludes(scene)
      ->check(CLI::ExistingFile);
  return check;
}

CLI::App* add_run(CLI::App& app, SceneArgs& a)
{
  auto* run = app.add_subcommand("run", "run a scene into a run folder");
  run->add_option("scene", a.scene_file, "scene file (TOML)")->required();
  run->add_option("--set", a.sets, "override a key: section.key=value");
  auto* out_option = run->add_option("--out", a.out, "run folder (default: runs/<scene name>)");
  run->add_option("--resume", a.resume,
                  "continue the run in this folder from its last checkpoint "
                  "(checkpoint.steps; the same scene, --set and --petsc, any rank count)")
      ->excludes(out_option);
  run->add_option("--petsc", a.petsc, "PETSc options, e.g. \"-ksp_type cg -pc_type gamg\"");
  add_no_report(run, a.no_report);
  return run;
}

CLI::App* add_study(CLI::App& app, DriverArgs& a)
{
  auto* study = app.add_subcommand("study", "run a study (a design over a scene's keys) and "
                                            "analyse it; resumes an interrupted one");
  study->add_option("study", a.file, "study file (TOML)")->required();
  study->add_option("--out", a.out, "study folder (default: studies/<study name>)");
  study->add_option("--jobs", a.jobs, "cases at once (default: the study's)")
      ->check(CLI::Range(1, 4096));
  study->add_flag("--dry-run", a.dry_run, "check every case and list them; run none");
  study->add_option("--launcher", a.launcher, "where the cases run (default: the study's)")
      ->check(CLI::IsMember({"local", "slurm"}));
  add_no_report(study, a.no_report);
  return study;
}

CLI::App* add_fit(CLI::App& app, DriverArgs& a)
{
  auto* fit = app.add_subcommand("fit", "fit scene keys (stiffness, IOP...) to a patient's "
                                        "readings; resumes an interrupted fit");
  fit->add_option("fit", a.file, "fit file (TOML)")->required();
  fit->add_option("--out", a.out, "fit folder (default: fits/<fit name>)");
  fit->add_option("--jobs", a.jobs, "forward runs at once (default: the fit's)")
      ->check(CLI::Range(1, 4096));
  fit->add_flag("--dry-run", a.dry_run, "check the fit file and the start's scene; run nothing");
  fit->add_option("--launcher", a.launcher, "where the forward runs go (default: the fit's)")
      ->check(CLI::IsMember({"local", "slurm"}));
  fit->add_option("--patient", a.patient, "a cohort's fit file: fit this patient (a row of "
                                          "its table) only");
  add_no_report(fit, a.no_report);
  return fit;
}

CLI::App* add_report(CLI::App& app, ReportArgs& a)
{
  auto* report = app.add_subcommand("report", "write the web page of a run, study, fit or "
                                              "cohort folder: DIR/report.html, self-contained");
  report->add_option("folder", a.folder, "a folder nct run, study or fit wrote")->required();
  report->add_option("--out", a.out, "the page (default: DIR/report.html)");
  return report;
}

CLI::App* add_describe(CLI::App& app, DescribeArgs& a)
{
  auto* describe = app.add_subcommand("describe", "print every scene key with its documentation");
  describe->add_flag("--markdown", a.markdown, "as a Markdown table");
  describe->add_flag("--biomarkers", a.biomarkers,
                     "the biomarker registry instead: every summary.json value studies compare "
                     "and fits read, with its unit and meaning (JSON, or --markdown)");
  return describe;
}

/// nct study: the study file's cases run (or resumed) into its folder
/// (`out`).
int run_study(const DriverArgs& a, const std::filesystem::path& program,
              std::filesystem::path& out)
{
  auto s = nct::study::Study::load(a.file);
  nct::study::Options options;
  options.out = a.out.empty() ? std::filesystem::path("studies")
                                    / std::filesystem::path(a.file).stem()
                              : std::filesystem::path(a.out);
  options.program = program;
  options.jobs = a.jobs;
  options.dry_run = a.dry_run;
  options.launcher = a.launcher;
  out = options.out;
  return nct::study::run(s, options);
}

/// nct fit: the fit (or a cohort's fits, or one patient's) run or resumed
/// into its folder (`out`).
int run_fit(const DriverArgs& a, const std::filesystem::path& program, std::filesystem::path& out)
{
  auto f = nct::fit::Fit::load(a.file, a.patient);
  nct::fit::Options options;
  options.out = a.out.empty() ? std::filesystem::path("fits") / std::filesystem::path(a.file).stem()
                                    / (a.patient.empty() ? "" : "patients/" + a.patient)
                              : std::filesystem::path(a.out);
  options.program = program;
  options.jobs = a.jobs;
  options.dry_run = a.dry_run;
  options.launcher = a.launcher;
  out = options.out;
  return f.cohort ? nct::fit::run_cohort(f, options) : nct::fit::run(f, options);
}

/// A study or a fit: a driver that starts each run as an MPI job of its
/// own, no MPI process itself; its page at the end (a finished or failed
/// study or fit). Its exit code (bad input: 2).
int drive(const std::string& verb, const DriverArgs& a)
{
  if (const char* size = std::getenv("OMPI_COMM_WORLD_SIZE"); size && std::atoi(size) > 1)
  {
    std::cerr << "error: nct " << verb << " starts an MPI job per run: run it without mpirun "
              << "(" << verb << ".ranks sets the ranks of each run)" << std::endl;
    return 2;
  }
  try
  {
    const auto program = std::filesystem::read_symlink("/proc/self/exe");
    std::filesystem::path out;
    const int code = verb == "fit" ? run_fit(a, program, out) : run_study(a, program, out);
    if ((code == 0 || code == 3) && !a.dry_run && !a.no_report)
      nct::report::after(out);
    return code;
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

/// A run's page, by rank 0 while the others wait (idle, not spinning): a
/// rank that exits first, with a diverged run's code 3, would have mpirun
/// stop rank 0 before its page is written.
void write_page(const std::filesystem::path& out, int rank)
{
  if (rank == 0)
    nct::report::after(out);
  MPI_Request done;
  MPI_Ibarrier(MPI_COMM_WORLD, &done);
  for (int finished = 0; !finished;)
  {
    MPI_Test(&done, &finished, MPI_STATUS_IGNORE);
    if (!finished)
      std::this_thread::sleep_for(std::chrono::milliseconds(20));
  }
}

/// nct check or nct run (`run`) of a scene, on the ranks of this MPI job;
/// a run's page at its end, a finished or a diverged one's. Its exit
/// code: 2 for bad input, 3 when the run diverged.
/// `nct check --cases FILE`: every case read as `nct check` reads one;
/// each refused one said as "case I:" and its error. Exit 2 if any is.
int check_cases(const std::string& file, int rank)
{
  std::ifstream in(file);
  int code = 0;
  std::size_t i = 0;
  for (std::string line; std::getline(in, line); ++i)
  {
    const auto c = nlohmann::json::parse(line);
    try
    {
      nct::read(MPI_COMM_WORLD, c.at("scene").get<std::string>(),
                c.at("sets").get<std::vector<std::string>>());
    }
    catch (const nct::scene::Error& e)
    {
      if (rank == 0)
        std::cerr << "case " << i << ":\n" << "error: " << e.what() << std::endl;
      code = 2;
    }
  }
  return code;
}

int run_scene(char* argv0, SceneArgs& a, bool run)
{
  nct::Runtime runtime(argv0);
  int rank = 0;
  MPI_Comm_rank(MPI_COMM_WORLD, &rank);
  std::filesystem::path out;
  try
  {
    if (!run && !a.cases.empty())
      return check_cases(a.cases, rank);
    if (a.scene_file.empty())
      throw nct::scene::Error("nct check: give a scene file, or --cases FILE");
    if (run)
      test_divergence(a.sets);
    const nct::Input input = nct::read(MPI_COMM_WORLD, a.scene_file, a.sets);
    if (!run)
    {
      if (rank == 0)
        std::cout << a.scene_file << ": ok\n";
      return 0;
    }
    nct::RunOptions options;
    options.out = a.out.empty() ? std::filesystem::path("runs")
                                      / std::filesystem::path(a.scene_file).stem()
                                : std::filesystem::path(a.out);
    options.petsc = parse_petsc(a.petsc);
    if (!a.resume.empty())
      options.out = a.resume, options.resume = true;
    out = options.out;
    nct::run(MPI_COMM_WORLD, input, options);
    if (!a.no_report)
      write_page(out, rank);
    return 0;
  }
  catch (const nct::scene::Error& e)
  {
    if (rank == 0)
      std::cerr << "error: " << e.what() << std::endl;
    return 2;
  }
  catch (const nct::io::CheckpointError& e)
  {
    if (rank == 0)
      std::cerr << "error: " << e.what() << std::endl;
    return 2;
  }
  catch (const nct::Diverged& e)
  {
    if (rank == 0)
      std::cerr << "error: " << e.what() << std::endl;
    if (!a.no_report)
      write_page(out, rank);
    return 3;
  }
  catch (const std::exception& e)
  {
    std::cerr << "error (rank " << rank << "): " << e.what() << std::endl;
    return 1;
  }
}

} // namespace

int main(int argc, char* argv[])
{
  CLI::App app{"nct: in-silico non-contact tonometry (Corvis ST air-puff test)"};
  app.require_subcommand(1);
  SceneArgs scene;
  DriverArgs driver;
  DescribeArgs listing;
  ReportArgs pages;
  add_check(app, scene);
  auto* run = add_run(app, scene);
  auto* study = add_study(app, driver);
  auto* fit = add_fit(app, driver);
  auto* report = add_report(app, pages);
  auto* describe = add_describe(app, listing);
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
    std::cout << (listing.biomarkers ? nct::biomarkers::describe(listing.markdown)
                                     : nct::scene::describe(listing.markdown));
    return 0;
  }
  if (report->parsed())
    return nct::report::write(pages.folder, pages.out);
  if (study->parsed() || fit->parsed())
    return drive(study->parsed() ? "study" : "fit", driver);
  return run_scene(argv[0], scene, run->parsed());
}
