// A cohort's fits (cpp/fit/fit.h): every patient's `nct fit --patient`,
// several at once sharing the forward runs' jobs, and one table of them.
#include <algorithm>
#include <chrono>
#include <cmath>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "fit/fit.h"
#include "fit/results.h"
#include "io/format.h"
#include "io/output.h"
#include "io/text.h"
#include "io/toml_input.h"
#include "jobs/jobs.h"
#include "jobs/launcher_input.h"
#include "jobs/run_cache.h"
#include "scene/scene.h"

namespace nct::fit
{
namespace fs = std::filesystem;
using io::format;

namespace
{

/// A patient's row as recorded in its folder: a changed row is fitted again.
nlohmann::json patient_record(const Patient& p)
{
  return {{"patient", p.id},    {"folder", fs::absolute(p.folder).lexically_normal()},
          {"sets", p.sets},     {"priors", p.priors},
          {"truths", p.truths}, {"covariates", p.covariates}};
}

/// A CSV cell: a number as written back exactly, text as it is, none empty.
std::string csv_cell(const nlohmann::ordered_json& v)
{
  if (v.is_number_integer())
    return std::to_string(v.get<long>());
  if (v.is_number())
    return io::literal(v.get<double>());
  if (v.is_boolean())
    return v.get<bool>() ? "1" : "0";
  if (v.is_string())
  {
    std::string s = v.get<std::string>();
    std::replace(s.begin(), s.end(), ',', ';');
    return s;
  }
  return "";
}

/// One row of the cohort's table from a patient's fit.json (null: not fitted).
nlohmann::ordered_json cohort_row(const Patient& p, const nlohmann::json& result,
                           const std::string& status)
{
  nlohmann::ordered_json r = nlohmann::ordered_json::object();
  r["patient"] = p.id;
  r["status"] = status;
  for (auto& [name, value] : p.covariates)
    r[name] = value;
  for (auto& set : p.sets)
    r[set.substr(0, set.find('='))] = set.substr(set.find('=') + 1);
  if (result.is_null())
    return r;
  const auto& params = result["parameters"];
  for (std::size_t i = 0; i < params.size(); ++i)
  {
    const auto& q = params[i];
    const std::string l = q["label"];
    r[l] = q["value"];
    r[l + "_se"] = q["se"];
    r[l + "_lo"] = q["ci95"][0];
    r[l + "_hi"] = q["ci95"][1];
    r[l + "_at_bound"] = q["at_bound"];
    if (q.contains("prior"))
      r[l + "_prior"] = q["prior"]["mean"];
    if (auto t = p.truths.find(l); t != p.truths.end())
    {
      r["truth_" + l] = t->second;
      r[l + "_error"] = q["value"].get<double>() - t->second;
      if (!q["ci95"][0].is_null() && !q["ci95"][1].is_null())
        r[l + "_inside"] = q["ci95"][0].get<double>() <= t->second
                           && t->second <= q["ci95"][1].get<double>();
    }
    for (std::size_t j = i + 1; j < params.size(); ++j)
      r["corr_" + l + "_" + params[j]["label"].get<std::string>()] = result["correlation"][i][j];
  }
  for (const char* k : {"chi2", "dof", "reduced_chi2", "iterations", "forward_runs", "wall_s"})
    r[k] = result[k];
  std::string warnings;
  for (auto& w : result["warnings"])
    warnings += (warnings.empty() ? "" : " | ") + w.get<std::string>();
  r["warnings"] = warnings;
  return r;
}

/// The table's columns: the first row's order, then any other's new ones.
std::vector<std::string> columns(const nlohmann::ordered_json& rows)
{
  std::vector<std::string> out;
  for (auto& r : rows)
    for (auto& [k, v] : r.items())
      if (!std::count(out.begin(), out.end(), k))
        out.push_back(k);
  // warnings last: the widest
  auto w = std::find(out.begin(), out.end(), "warnings");
  if (w != out.end())
    std::rotate(w, w + 1, out.end());
  return out;
}

/// The rows as CSV: a header of every column, a line per row.
std::string to_csv(const nlohmann::ordered_json& rows)
{
  std::ostringstream csv;
  const auto cols = columns(rows);
  for (std::size_t c = 0; c < cols.size(); ++c)
    csv << (c ? "," : "") << cols[c];
  csv << "\n";
  for (auto& r : rows)
  {
    for (std::size_t c = 0; c < cols.size(); ++c)
      csv << (c ? "," : "") << (r.contains(cols[c]) ? csv_cell(r[cols[c]]) : "");
    csv << "\n";
  }
  return csv.str();
}

/// Every patient's scene at the start must pass nct check (its eye's
/// geometry with its thickness, radius...) before anything runs: a
/// scene::Error naming each row that does not.
void check_patients(const Fit& fit, const Options& o)
{
  const Cohort& cohort = *fit.cohort;
  std::vector<jobs::SceneCase> cases;
  for (const Patient& p : cohort.patients)
  {
    std::vector<std::string> sets = fit.sets;
    sets.insert(sets.end(), p.sets.begin(), p.sets.end());
    for (const Parameter& q : fit.parameters)
      for (const auto& k : q.keys)
        sets.push_back(k + "=" + io::literal(q.start));
    cases.push_back({fit.scene, sets});
  }
  std::vector<std::pair<std::size_t, std::string>> refused;
  try
  {
    refused = jobs::check_scenes(o.program, cases, o.out / "check");
  }
  catch (const std::runtime_error&)
  {
    if (jobs::interrupted())
      return; // the cohort stops
    throw;
  }
  std::string problems;
  for (const auto& [i, why] : refused)
  {
    const Patient& p = cohort.patients[i];
    problems += format("%s%s row %zu (patient %s): the start's scene: %s",
                       problems.empty() ? "" : "\n", cohort.table.string().c_str(), p.row,
                       p.id.c_str(), jobs::tail(why, 2).c_str());
  }
  if (!problems.empty())
    throw scene::Error(problems);
  fs::remove_all(o.out / "check");
}

/// How the jobs (forward runs at once) are shared among the patients
/// fitted at once: by default a job each, so that no job waits while a
/// patient's iteration finishes its last runs (a cohort's throughput, not
/// a patient's latency).
struct Sharing
{
  int jobs;        ///< forward runs at once in all
  int at_once;     ///< patients fitted at once
  int per_patient; ///< forward runs at once of each
};

Sharing share_jobs(const Fit& fit, const Options& o)
{
  const int jobs = o.jobs > 0 ? o.jobs : fit.jobs;
  const int at_once = std::min(int(fit.cohort->patients.size()),
                               fit.cohort->at_once > 0 ? fit.cohort->at_once : jobs);
  return {jobs, at_once, std::max(1, jobs / at_once)};
}

/// The patients to fit (their indices; the others' fits are kept) and
/// their jobs: each an `nct fit --patient` into its folder, where its row
/// is recorded and its fit resumes from the forward runs it has.
std::vector<std::size_t> patients_to_fit(const Fit& fit, const Options& o,
                                         const jobs::RunCache& fits, int per_patient,
                                         std::vector<jobs::Job>& todo)
{
  std::vector<std::size_t> index;
  for (std::size_t i = 0; i < fit.cohort->patients.size(); ++i)
  {
    const Patient& p = fit.cohort->patients[i];
    const nlohmann::json row = patient_record(p);
    if (fits.reusable(p.id, row))
      continue;
    const fs::path dir = fits.path(p.id);
    // The cohort's page covers its patients: theirs only on request.
    std::vector<std::string> argv = {o.program.string(), "fit", fs::absolute(fit.file).string(),
                                     "--patient", p.id, "--out", fs::absolute(dir).string(),
                                     "--jobs", std::to_string(per_patient), "--no-report"};
    if (!o.launcher.empty())
      argv.insert(argv.end(), {"--launcher", o.launcher});
    todo.push_back({argv, fs::absolute(dir / "fit.log"), 1, "", nullptr});
    fits.prepare(todo.back(), p.id, row, jobs::RunCache::Restart::resume);
    index.push_back(i);
  }
  return index;
}

/// A patient's line when its fit ends (exit `code`): its parameters, or
/// why it failed.
std::string patient_line(const Patient& p, const fs::path& dir, int code)
{
  std::string line = format("patient %-12s ", p.id.c_str());
  if (code == 130 || jobs::interrupted())
    return line + "interrupted";
  if (!fs::exists(dir / "fit.json"))
    return line + format("failed (exit %d): %s", code,
                         jobs::tail(io::read_text(dir / "fit.log"), 2).c_str());
  const auto r = nlohmann::json::parse(io::read_text(dir / "fit.json"));
  line += r["status"].get<std::string>();
  for (auto& q : r["parameters"])
    line += format("  %s %.5g", q["label"].get<std::string>().c_str(), q["value"].get<double>())
            + (q["se"].is_null() ? std::string(" (no SE)")
                                 : format(" +- %.2g", q["se"].get<double>()));
  line += format("  chi2/dof %.3g  %d runs", r["reduced_chi2"].get<double>(),
                 r["forward_runs"].get<int>());
  return line;
}

/// cohort.csv and cohort.json: a row per patient, fitted or not; the
/// closing line. Returns the exit code: 0 when every fit converged, else 3.
int report_cohort(const Fit& fit, const Options& o, const jobs::RunCache& fits,
                  const Sharing& sharing, double wall)
{
  const Cohort& cohort = *fit.cohort;
  const int n = int(cohort.patients.size());
  nlohmann::ordered_json rows = nlohmann::ordered_json::array();
  int converged = 0, inside = 0, with_truth = 0;
  for (const Patient& p : cohort.patients)
  {
    nlohmann::json result;
    std::string status = "failed";
    if (fs::exists(fits.path(p.id) / "fit.json"))
    {
      result = nlohmann::json::parse(io::read_text(fits.path(p.id) / "fit.json"));
      status = result["status"];
    }
    converged += status == "converged";
    rows.push_back(cohort_row(p, result, status));
    for (auto& [label, truth] : p.truths)
      if (rows.back().contains(label + "_inside"))
        ++with_truth, inside += rows.back()[label + "_inside"].get<bool>();
  }
  io::write_atomic(o.out / "cohort.csv", to_csv(rows));
  nlohmann::ordered_json out = {{"fit", fs::absolute(fit.file).string()},
                                {"table", fs::absolute(cohort.table).string()},
                                {"patients", n},
                                {"converged", converged},
                                {"patients_at_once", sharing.at_once},
                                {"jobs_per_patient", sharing.per_patient},
                                {"wall_s", wall},
                                {"rows", rows}};
  if (with_truth)
    out["truths_inside_ci95"] = {{"held", inside}, {"of", with_truth}};
  io::write_atomic(o.out / "cohort.json", out.dump(2) + "\n");
  std::cout << "\ncohort: " << converged << " of " << n << " fits converged";
  if (with_truth)
    std::cout << "; " << inside << " of " << with_truth << " truths inside their 95 % intervals";
  std::cout << format("; %.0f s", wall) << "\ncohort.csv, cohort.json in " << o.out.string()
            << std::endl;
  return converged == n ? 0 : 3;
}

} // namespace

int run_cohort(const Fit& fit, const Options& o)
{
  const auto start = std::chrono::steady_clock::now();
  auto seconds = [&]
  { return std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count(); };
  const Cohort& cohort = *fit.cohort;
  const jobs::RunCache fits(o.out / "patients", "patient.json", "fit.json");
  claim_folder(fit, o.out, "cohort");
  jobs::catch_interrupts();
  // Slurm must take the options before any patient's fit starts.
  jobs::launcher_for(fit.launcher, o.launcher, o.out, fit.ranks, "fit", fit.file);
  const Sharing sharing = share_jobs(fit, o);
  check_patients(fit, o);
  if (jobs::interrupted())
    return 130;

  std::vector<jobs::Job> todo;
  const std::vector<std::size_t> index = patients_to_fit(fit, o, fits, sharing.per_patient, todo);
  const int n = int(cohort.patients.size()), kept = n - int(todo.size());
  std::cout << "cohort " << fit.file.string() << ": " << n << " patient(s) from "
            << cohort.table.string() << ", " << fit.parameters.size() << " parameter(s) each; "
            << sharing.at_once << " patient(s) at once, " << sharing.per_patient
            << " forward run(s) at once each -> " << o.out.string() << " (" << kept
            << " fitted before)" << std::endl;
  if (o.dry_run)
  {
    std::cout << "cohort: every patient's fit checks out; nothing run (--dry-run)" << std::endl;
    return 0;
  }
  io::write_atomic(o.out / "fit.toml", io::read_text(fit.file));

  int finished = kept;
  const bool complete = jobs::run(todo, sharing.at_once, [&](std::size_t k, int code)
  {
    const Patient& p = cohort.patients[index[k]];
    ++finished;
    std::cout << patient_line(p, fits.path(p.id), code) << "  "
              << jobs::progress(finished, n, finished - kept, seconds()) << std::endl;
  });
  if (!complete)
  {
    std::cerr << "cohort: interrupted; the same command resumes it (finished patients are "
                 "kept, the others' forward runs too)"
              << std::endl;
    return 130;
  }
  return report_cohort(fit, o, fits, sharing, seconds());
}

} // namespace nct::fit
