#include "study/study.h"

#include <algorithm>
#include <charconv>
#include <cerrno>
#include <chrono>
#include <cmath>
#include <csignal>
#include <cstring>
#include <fcntl.h>
#include <fstream>
#include <functional>
#include <iostream>
#include <map>
#include <regex>
#include <set>
#include <spawn.h>
#include <sstream>
#include <sys/wait.h>
#include <thread>
#include <unistd.h>

#include <nlohmann/json.hpp>
#include <toml++/toml.h>

#include "io/format.h"
#include "jobs/launcher_input.h"
#include "io/output.h"
#include "io/toml_input.h"
#include "biomarkers/registry.h"
#include "jobs/jobs.h"
#include "jobs/run_cache.h"
#include "scene/scene.h"
#include "study/analysis.h"

extern char** environ;

namespace nct::study
{
using io::format;
using io::key_error;
using io::literal;
using io::nan;
using io::check_name;
using io::string_list;
using jobs::read_text;
using jobs::tail;
using scene::Error;
namespace fs = std::filesystem;

namespace
{

// ---------------------------------------------------------------------------
// The study file
// ---------------------------------------------------------------------------




/// A scene file named at `key`, relative to the study file; it must exist.
fs::path scene_path(const fs::path& file, const std::string& key, const toml::node* node)
{
  return io::file_path(file, key, node, "scene file");
}


/// Refuse keys of `t` not in `known`, naming the table they are in by
/// `where` ("", "study.", "factor[2].", "variant[1].").
void refuse_unknown_study_keys(const toml::table& t, const std::set<std::string>& known,
                               const fs::path& file, const std::string& where,
                               io::KeyErrors& errors)
{
  const std::string table = where.empty()                    ? "a study file"
                            : where == "study."             ? "[study]"
                            : where.rfind("variant", 0) == 0 ? "[[variant]]"
                                                            : "[[factor]]";
  io::refuse_unknown_keys(t, known, file, where, table, errors);
}

std::string case_name(std::size_t i, std::size_t n)
{
  const int width = std::max<int>(3, std::to_string(n).size());
  return format("case-%0*zu", width, i + 1);
}

/// "C10=0.25, k1=0.005" (an ablation: the variant's name) for messages.
std::string describe_case(const Study& s, const Case& c)
{
  if (c.variant >= 0)
    return s.variants[c.variant].name;
  std::string out;
  for (std::size_t i = 0; i < s.factors.size(); ++i)
    out += (i ? ", " : "") + s.factors[i].label + "="
           + (c.levels[i] < 0 ? "base" : s.factors[i].levels[c.levels[i]]);
  return out;
}

/// The factors of a factorial or one-factor-at-a-time study, and its
/// cases (when every factor reads).
void read_factors(const toml::table& t, Study& s, io::KeyErrors& errors)
{
  const fs::path& file = s.file;
  const toml::array* fs_ = t["factor"].as_array();
  if (!fs_ || fs_->empty() || !fs_->is_array_of_tables())
    throw key_error(file, "factor", "missing: one [[factor]] table per factor (key, levels)");
  bool read = true;
  for (std::size_t i = 0; i < fs_->size(); ++i)
    read = errors.attempt([&] {
    const toml::table& ft = *fs_->get(i)->as_table();
    const std::string where = "factor[" + std::to_string(i + 1) + "].";
    refuse_unknown_study_keys(ft, {"key", "levels", "label"}, file, where, errors);
    Factor f;
    if (!ft["key"])
      throw key_error(file, where + "key", "missing: the scene key (or keys) the factor sets");
    f.keys = string_list(*ft["key"].node(), file, where + "key", true);
    if (f.keys.empty())
      throw key_error(file, where + "key", "name at least one scene key");
    f.label = ft["label"].value_or(std::string(f.keys[0]));
    check_name(file, where + "label", f.label, "a CSV column");
    for (auto& g : s.factors)
      if (g.label == f.label)
        throw key_error(file, where + "label", "'" + f.label + "' names two factors");
    const toml::array* levels = ft["levels"].as_array();
    if (!levels)
      throw key_error(file, where + "levels", "missing or not an array: the factor's levels");
    const bool factorial = s.design == "factorial";
    if (factorial && levels->size() != 2)
      throw key_error(file, where + "levels", format("a two-level factorial takes 2 levels, got %zu",
                                                     levels->size()));
    if (!factorial && levels->size() < 1)
      throw key_error(file, where + "levels", "give at least one level");
    for (std::size_t j = 0; j < levels->size(); ++j)
    {
      const toml::node& v = *levels->get(j);
      if (!(v.is_number() || v.is_boolean() || v.is_string()))
        throw key_error(file, where + "levels", "a level is a number, a boolean or a string, got "
                                                    + literal(v));
      if (!factorial && !v.is_number())
        throw key_error(file, where + "levels", "one-factor-at-a-time levels are numbers, got "
                                                    + literal(v));
      f.levels.push_back(literal(v));
      f.values.push_back(v.is_number()    ? *v.value<double>()
                         : v.is_boolean() ? double(*v.value<bool>())
                                          : double(j));
      if (std::count(f.levels.begin(), f.levels.end(), f.levels.back()) > 1)
        throw key_error(file, where + "levels", "level " + f.levels.back() + " is given twice");
    }
    s.factors.push_back(std::move(f));
  }) && read;
  if (!read)
    return;
  const std::size_t k = s.factors.size();
  if (s.design == "factorial" && k > 12)
    throw key_error(file, "factor", format("%zu factors make 2^%zu cases; at most 12 factors", k, k));

  // Cases
  auto sets_of = [&](const std::vector<int>& levels)
  {
    Case c{levels, s.sets, -1, s.scene};
    for (std::size_t i = 0; i < k; ++i)
      if (levels[i] >= 0)
        for (auto& key : s.factors[i].keys)
          c.sets.push_back(key + "=" + s.factors[i].levels[levels[i]]);
    return c;
  };
  if (s.design == "factorial")
    for (std::size_t c = 0; c < (std::size_t(1) << k); ++c)
    {
      std::vector<int> levels(k);
      for (std::size_t i = 0; i < k; ++i)
        levels[i] = (c >> i) & 1;
      s.cases.push_back(sets_of(levels));
    }
  else
  {
    // The base scene's value of each factor (its first key).
    toml::table base;
    try
    {
      base = toml::parse(scene::Scene::load(s.scene, s.sets).to_toml());
    }
    catch (const Error& e)
    {
      throw Error(file.string() + ": the base scene: " + e.what());
    }
    s.cases.push_back(sets_of(std::vector<int>(k, -1)));
    for (std::size_t i = 0; i < k; ++i)
    {
      const toml::node* v = base.at_path(s.factors[i].keys[0]).node();
      if (!v || !v->is_number())
        throw key_error(file, "factor[" + std::to_string(i + 1) + "].key",
                        s.factors[i].keys[0] + " is not a number in the base scene: a "
                        "one-factor-at-a-time factor is numeric");
      s.base_values.push_back(*v->value<double>());
      for (std::size_t j = 0; j < s.factors[i].levels.size(); ++j)
        if (s.factors[i].values[j] != s.base_values[i])
        {
          std::vector<int> levels(k, -1);
          levels[i] = int(j);
          s.cases.push_back(sets_of(levels));
        }
    }
  }
}

/// The variants of an ablation study, one case each: the study's
/// overrides, then the variant's.
void read_variants(const toml::table& t, Study& s, io::KeyErrors& errors)
{
  const fs::path& file = s.file;
  const toml::array* vs = t["variant"].as_array();
  if (!vs)
    throw key_error(file, "variant", "missing: one [[variant]] table per variant (name, set), "
                                     "the first the baseline");
  if (vs->size() < 2)
    throw key_error(file, "variant", format("an ablation compares variants with the first, the "
                                            "baseline: give at least 2 [[variant]] tables, got %zu",
                                            vs->size()));
  if (!vs->is_array_of_tables())
    throw key_error(file, "variant", "each variant is a [[variant]] table (name, set)");
  for (std::size_t i = 0; i < vs->size(); ++i)
    errors.attempt([&] {
    const toml::table& vt = *vs->get(i)->as_table();
    const std::string where = "variant[" + std::to_string(i + 1) + "].";
    refuse_unknown_study_keys(vt, {"name", "scene", "set", "description"}, file, where, errors);
    Variant v;
    auto name = vt["name"].value_exact<std::string>();
    if (!name)
      throw key_error(file, where + "name", "missing or not a string: the variant's name (its "
                                            "row in the tables)");
    v.name = *name;
    check_name(file, where + "name", v.name, "a CSV row");
    for (auto& w : s.variants)
      if (w.name == v.name)
        throw key_error(file, where + "name", "'" + v.name + "' names two variants");
    if (const toml::node* d = vt["description"].node())
    {
      if (!d->is_string())
        throw key_error(file, where + "description", "expected a string, got " + literal(*d));
      v.description = *d->value<std::string>();
      if (v.description.find_first_of("\r\n") != std::string::npos)
        throw key_error(file, where + "description", "one line: it labels tables and plots");
    }
    v.scene = vt["scene"] ? scene_path(file, where + "scene", vt["scene"].node()) : s.scene;
    if (const toml::node* set = vt["set"].node())
      v.sets = string_list(*set, file, where + "set", false);
    Case c{{}, s.sets, int(s.variants.size()), v.scene};
    c.sets.insert(c.sets.end(), v.sets.begin(), v.sets.end());
    s.cases.push_back(std::move(c));
    s.variants.push_back(std::move(v));
  });
}

} // namespace

Study Study::load(const fs::path& file)
{
  const toml::table t = io::parse_toml(file, "study file");
  io::KeyErrors errors(file, t);
  refuse_unknown_study_keys(t, {"study", "factor", "variant"}, file, "", errors);
  const toml::table* st = t["study"].as_table();
  if (!st)
  {
    errors.add(key_error(file, "study", "missing: a [study] table names the scene, design and "
                                        "responses")
                   .what());
    errors.raise();
  }
  std::set<std::string> known = {"scene", "design", "responses", "set", "ranks", "jobs",
                                 "mpiexec"};
  known.insert(jobs::launcher_keys().begin(), jobs::launcher_keys().end());
  refuse_unknown_study_keys(*st, known, file, "study.", errors);

  Study s;
  s.file = file;
  const bool scene_read = errors.attempt([&] {
    const toml::node* scene = (*st)["scene"].node();
    s.scene = scene_path(file, "study.scene", scene && scene->is_string() ? scene : nullptr);
  });

  const bool design_read = errors.attempt([&] {
    s.design = (*st)["design"].value_or<std::string>("factorial");
    if (s.design != "factorial" && s.design != "ofat" && s.design != "ablation")
      throw key_error(file, "study.design", "\"factorial\" (2^k full), \"ofat\" (one factor "
                                            "at a time) or \"ablation\" (named variants against "
                                            "the first), got \"" + s.design + "\"");
  });

  errors.attempt([&] {
    if (!(*st)["responses"])
      throw key_error(file, "study.responses", "missing: the summary.json keys to analyse");
    s.responses = string_list(*(*st)["responses"].node(), file, "study.responses", false);
    if (s.responses.empty())
      throw key_error(file, "study.responses", "name at least one response");
    for (auto& r : s.responses)
    {
      if (!biomarkers::find(r))
      {
        std::string list;
        for (auto& k : biomarkers::registry())
          list += (list.empty() ? "" : ", ") + k.key;
        throw key_error(file, "study.responses", "unknown response '" + r + "'; one of " + list);
      }
      if (std::count(s.responses.begin(), s.responses.end(), r) > 1)
        throw key_error(file, "study.responses", "'" + r + "' is listed twice");
    }
  });

  errors.attempt([&] {
    if (auto* set = (*st)["set"].node())
      s.sets = string_list(*set, file, "study.set", false);
  });

  auto integer = [&](const char* key, long def, long lo, long hi)
  { return io::integer(*st, "study", key, def, lo, hi, file); };
  s.ranks = 1;
  errors.attempt([&] { s.ranks = integer("ranks", 1, 1, 4096); });
  errors.attempt([&] {
    const long cores = std::max(1u, std::thread::hardware_concurrency());
    s.jobs = integer("jobs", std::max(1L, cores / s.ranks), 1, 4096);
  });
  errors.attempt([&] {
    s.mpiexec = (*st)["mpiexec"].value_or<std::string>("mpiexec --bind-to none");
    if (s.mpiexec.find_first_not_of(" \t") == std::string::npos)
      throw key_error(file, "study.mpiexec",
                      "empty: the MPI launcher, e.g. \"mpiexec --bind-to none\"");
  });
  s.launcher = jobs::read_launcher(*st, "study", file, errors);

  // The design's cases: factors and their levels, or named variants.
  const bool ablation = s.design == "ablation";
  if (design_read)
    errors.attempt([&] {
      if (ablation && t.contains("factor"))
        throw key_error(file, "factor", "an ablation study compares [[variant]] tables and takes "
                                        "no [[factor]]; design = \"factorial\" or \"ofat\" "
                                        "varies factors");
      if (!ablation && t.contains("variant"))
        throw key_error(file, "variant", "[[variant]] tables are the cases of design = "
                                         "\"ablation\"; a " + s.design
                                             + " study varies [[factor]] tables");
      if (ablation)
        read_variants(t, s, errors);
      else if (scene_read || !t.contains("factor"))
        read_factors(t, s, errors);
    });

  // Every case's scene must load: unknown keys, types and ranges are
  // caught here, before anything runs (the base scene's own problems
  // once). Two variants whose resolved scenes agree would be the same case.
  // The base scene with the study's overrides first: its problems once,
  // not once per case.
  if (errors.empty())
    errors.attempt([&] {
      try
      {
        scene::Scene::load(s.scene, s.sets);
      }
      catch (const Error& e)
      {
        throw key_error(file, "study.scene", std::string("the base scene with study.set: ")
                                                 + e.what());
      }
    });
  if (errors.empty())
  {
    std::vector<std::string> resolved(s.cases.size());
    std::vector<bool> loaded(s.cases.size(), false);
    for (std::size_t c = 0; c < s.cases.size(); ++c)
      loaded[c] = errors.attempt([&] {
        try
        {
          resolved[c] = scene::Scene::load(s.cases[c].scene, s.cases[c].sets).to_toml();
        }
        catch (const Error& e)
        {
          throw Error(file.string() + ": " + case_name(c, s.cases.size()) + " ("
                      + describe_case(s, s.cases[c]) + "): " + e.what());
        }
      });
    for (std::size_t c = 0; ablation && c < s.cases.size(); ++c)
      for (std::size_t d = 0; d < c; ++d)
        if (loaded[c] && loaded[d] && resolved[d] == resolved[c])
        {
          errors.add(key_error(file, "variant[" + std::to_string(c + 1) + "].set",
                               "'" + s.variants[c].name + "' makes the same scene as '"
                                   + s.variants[d].name + "' (with study.set, their overrides "
                                   "come to the same values): the two would be the same case")
                         .what());
          break;
        }
  }
  errors.raise();
  return s;
}

namespace
{

/// The job of one case: nct <verb> scene --set ... [--out dir], its
/// console into `log`; `run` on the study's ranks, `check` serially.
jobs::Job command(const Study& s, const Options& o, const Case& c, const std::string& verb,
                  const fs::path& out, const fs::path& log)
{
  return {jobs::nct_command(o.program, verb, c.scene, c.sets, out), log,
          verb == "run" ? s.ranks : 1, s.mpiexec, nullptr};
}

/// What case c's folder records: its name, scene and overrides.
nlohmann::json case_record(const Study& s, std::size_t c)
{
  nlohmann::json record = jobs::run_record(s.cases[c].scene, s.cases[c].sets);
  record["case"] = case_name(c, s.cases.size());
  return record;
}

// ---------------------------------------------------------------------------
// The results table and its analysis
// ---------------------------------------------------------------------------

/// What one case gave.
struct Result
{
  std::string status = "pending"; ///< pending, converged, failed, error
  std::vector<double> responses;  ///< NaN where the case gave none
  double wall_s = nan;
};

std::string number(double v)
{
  if (std::isnan(v))
    return "nan";
  if (std::isinf(v))
    return v > 0 ? "inf" : "-inf";
  return format("%.10g", v);
}

/// A JSON number, or null for NaN and infinities (JSON has neither).
nlohmann::json json_number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(); }

/// Is case c among those that show factor i's effect? Every case of a
/// factorial; one factor at a time, the cases that vary i and the base
/// (every factor at the scene's value).
bool compared_for(const Study& s, const Case& c, std::size_t i)
{
  return s.design == "factorial" || c.levels[i] >= 0
         || std::all_of(c.levels.begin(), c.levels.end(), [](int l) { return l < 0; });
}

/// The factor's value in a case (the base scene's for -1).
double value(const Study& s, const Case& c, std::size_t i)
{
  return c.levels[i] < 0 ? s.base_values[i] : s.factors[i].values[c.levels[i]];
}

Result read_result(const Study& s, const fs::path& dir)
{
  Result r;
  r.responses.assign(s.responses.size(), nan);
  auto summary = nlohmann::json::parse(read_text(dir / "summary.json"));
  r.status = summary.value("status", "failed");
  r.wall_s = summary.value("wall_s", nan);
  for (std::size_t j = 0; j < s.responses.size(); ++j)
    if (summary.contains(s.responses[j]) && summary[s.responses[j]].is_number())
      r.responses[j] = summary[s.responses[j]].get<double>();
  return r;
}

std::string cases_csv(const Study& s, const std::vector<Result>& results)
{
  std::ostringstream out;
  out << "case,status";
  if (!s.variants.empty())
    out << ",variant";
  for (auto& f : s.factors)
    out << "," << f.label;
  for (auto& r : s.responses)
    out << "," << r;
  out << ",wall_s\n";
  for (std::size_t c = 0; c < s.cases.size(); ++c)
  {
    out << case_name(c, s.cases.size()) << "," << results[c].status;
    if (s.cases[c].variant >= 0)
      out << "," << s.variants[s.cases[c].variant].name;
    for (std::size_t i = 0; i < s.factors.size(); ++i)
      out << "," << number(value(s, s.cases[c], i));
    for (double v : results[c].responses)
      out << "," << number(v);
    out << "," << number(results[c].wall_s) << "\n";
  }
  return out.str();
}

/// The effects, ANOVA, main effects and correlations of the finished
/// cases into the study folder; the rankings on stdout.
void analyse(const Study& s, const std::vector<Result>& results, const fs::path& out)
{
  const std::size_t k = s.factors.size(), n = s.cases.size();
  nlohmann::json json;
  json["design"] = s.design;
  json["cases"] = n;
  std::ostringstream effects, anova, mains;
  effects << "response,term,effect,rank\n";
  anova << "response,source,df,sum_sq,mean_sq,F,p,percent\n";
  mains << "response,factor,level,value,mean\n";
  std::cout << "\n";

  for (std::size_t j = 0; j < s.responses.size(); ++j)
  {
    const std::string& name = s.responses[j];
    std::vector<double> y(n);
    std::vector<std::string> missing;
    for (std::size_t c = 0; c < n; ++c)
    {
      y[c] = results[c].responses[j];
      if (!std::isfinite(y[c]))
        missing.push_back(case_name(c, n));
    }
    auto& rj = json["responses"][name];
    if (!missing.empty())
    {
      std::string list;
      for (auto& m : missing)
        list += (list.empty() ? "" : ", ") + m;
      rj["skipped"] = "no value from " + list;
      std::cout << name << ": not analysed, no value from " << list << "\n";
      continue;
    }

    if (std::all_of(y.begin(), y.end(), [&](double v) { return v == y[0]; }))
    {
      rj["constant"] = y[0];
      std::cout << name << ": " << number(y[0]) << " in every case, no effects\n";
      continue;
    }

    // (term, effect) of this response, ranked by size.
    std::vector<std::pair<std::string, double>> ranked;
    if (s.design == "factorial")
    {
      std::vector<std::vector<int>> coded(n, std::vector<int>(k));
      std::vector<std::string> labels;
      for (auto& f : s.factors)
        labels.push_back(f.label);
      for (std::size_t c = 0; c < n; ++c)
        for (std::size_t i = 0; i < k; ++i)
          coded[c][i] = 2 * s.cases[c].levels[i] - 1;
      const Anova a = factorial_anova(coded, y, labels);
      for (auto& t : a.terms)
      {
        ranked.emplace_back(t.name, t.effect);
        anova << name << "," << t.name << ",1," << number(t.sum_sq) << "," << number(t.sum_sq)
              << "," << number(t.f) << "," << number(t.p) << "," << number(t.percent) << "\n";
        rj["terms"][t.name] = {{"effect", t.effect}, {"sum_sq", t.sum_sq},
                               {"percent", t.percent}, {"F", json_number(t.f)},
                               {"p", json_number(t.p)}};
      }
      const double ms_error = a.error_df > 0 ? a.error_sum_sq / a.error_df : nan;
      anova << name << ",error," << a.error_df << "," << number(a.error_sum_sq) << ","
            << number(ms_error) << ",,," << number(a.total_sum_sq > 0 ? 100 * a.error_sum_sq
                                                                            / a.total_sum_sq
                                                                      : 0)
            << "\n"
            << name << ",total," << a.total_df << "," << number(a.total_sum_sq) << ",,,,100\n";
      rj["error"] = {{"df", a.error_df}, {"sum_sq", a.error_sum_sq}};
      rj["total"] = {{"df", a.total_df}, {"sum_sq", a.total_sum_sq}};
      json["error_term"]
          = a.error_df > 0
                ? format("the interactions of three and more factors, pooled (%d dof): F and p "
                         "test each term against them",
                         a.error_df)
                : std::string("none: a 2^k design with k <= 2 and no replication leaves no "
                              "degrees of freedom once the main factors and two-way "
                              "interactions are fitted, so there is no F or p");
    }
    else
    {
      // One factor at a time: each factor's effect is the response at
      // its highest value minus at its lowest (the base included).
      for (std::size_t i = 0; i < k; ++i)
      {
        double lo = INFINITY, hi = -INFINITY, y_lo = nan, y_hi = nan;
        for (std::size_t c = 0; c < n; ++c)
        {
          if (!compared_for(s, s.cases[c], i))
            continue;
          const double x = value(s, s.cases[c], i);
          if (x < lo)
            lo = x, y_lo = y[c];
          if (x > hi)
            hi = x, y_hi = y[c];
        }
        ranked.emplace_back(s.factors[i].label, y_hi - y_lo);
        rj["terms"][s.factors[i].label] = {{"effect", y_hi - y_lo}, {"low", lo}, {"high", hi}};
      }
      json["error_term"] = "none: one factor at a time has no ANOVA; the effects are "
                           "differences between single runs and interactions are not seen";
    }
    std::stable_sort(ranked.begin(), ranked.end(),
                     [](auto& a, auto& b) { return std::abs(a.second) > std::abs(b.second); });
    std::cout << name << ": effects, largest first\n";
    for (std::size_t r = 0; r < ranked.size(); ++r)
    {
      effects << name << "," << ranked[r].first << "," << number(ranked[r].second) << "," << r + 1
              << "\n";
      rj["ranking"].push_back(ranked[r].first);
      if (r < 8)
        std::cout << format("  %2zu  %-28s %+.4g\n", r + 1, ranked[r].first.c_str(),
                            ranked[r].second);
    }

    // Main effects: the mean response at each level of each factor (one
    // factor at a time: over the cases that vary it, and the base).
    for (std::size_t i = 0; i < k; ++i)
    {
      std::vector<double> x, ys;
      for (std::size_t c = 0; c < n; ++c)
        if (compared_for(s, s.cases[c], i))
        {
          x.push_back(value(s, s.cases[c], i));
          ys.push_back(y[c]);
        }
      std::vector<double> values = x;
      std::sort(values.begin(), values.end());
      values.erase(std::unique(values.begin(), values.end()), values.end());
      const auto means = level_means(x, values, ys);
      const Factor& f = s.factors[i];
      for (std::size_t l = 0; l < values.size(); ++l)
      {
        auto at = std::find(f.values.begin(), f.values.end(), values[l]);
        std::string level = at == f.values.end() ? number(values[l]) : f.levels[at - f.values.begin()];
        std::replace(level.begin(), level.end(), ',', ';');
        mains << name << "," << f.label << "," << level << "," << number(values[l]) << ","
              << number(means[l]) << "\n";
      }
    }
  }

  // Pearson correlations of factors and responses over the cases that
  // gave every response.
  std::vector<std::string> names;
  std::vector<std::vector<double>> columns(k + s.responses.size());
  for (auto& f : s.factors)
    names.push_back(f.label);
  for (auto& r : s.responses)
    names.push_back(r);
  std::size_t used = 0;
  for (std::size_t c = 0; c < n; ++c)
  {
    const auto& r = results[c].responses;
    if (!std::all_of(r.begin(), r.end(), [](double v) { return std::isfinite(v); }))
      continue;
    ++used;
    for (std::size_t i = 0; i < k; ++i)
      columns[i].push_back(value(s, s.cases[c], i));
    for (std::size_t j = 0; j < r.size(); ++j)
      columns[k + j].push_back(r[j]);
  }
  std::ostringstream corr;
  json["correlation_cases"] = used;
  if (used >= 3)
  {
    const auto r = pearson(columns);
    for (auto& name : names)
      corr << "," << name;
    corr << "\n";
    for (std::size_t a = 0; a < names.size(); ++a)
    {
      corr << names[a];
      for (std::size_t b = 0; b < names.size(); ++b)
        corr << "," << number(r[a][b]);
      corr << "\n";
    }
  }
  io::write_atomic(out / "effects.csv", effects.str());
  if (s.design == "factorial")
    io::write_atomic(out / "anova.csv", anova.str());
  io::write_atomic(out / "main_effects.csv", mains.str());
  if (used >= 3)
    io::write_atomic(out / "correlation.csv", corr.str());
  else
    fs::remove(out / "correlation.csv"); // a stale one from an earlier analysis
  io::write_atomic(out / "analysis.json", json.dump(2) + "\n");
}

/// A number in a table, or nothing where it is not finite.
std::string number_or_blank(double v) { return std::isfinite(v) ? number(v) : ""; }

/// An ablation's variants against its baseline into the study folder
/// (ablation.csv, analysis.json); a table per response on stdout.
void analyse_ablation(const Study& s, const std::vector<Result>& results, const fs::path& out)
{
  const std::size_t n = s.cases.size();
  nlohmann::json json;
  json["design"] = s.design;
  json["cases"] = n;
  json["baseline"] = s.variants[0].name;
  json["difference"] = "value - the baseline's value";
  json["percent"] = "100 difference / |the baseline's value|; null when the baseline is 0 or "
                    "either value is missing";
  std::size_t width = 7;
  for (std::size_t c = 0; c < n; ++c)
  {
    const Variant& v = s.variants[s.cases[c].variant];
    width = std::max(width, v.name.size());
    json["variants"].push_back({{"name", v.name}, {"description", v.description},
                                {"case", case_name(c, n)}, {"status", results[c].status},
                                {"set", v.sets}});
  }

  std::cout << "\nvariants against the baseline, " << s.variants[0].name << ":\n";
  for (std::size_t c = 0; c < n; ++c)
  {
    const Variant& v = s.variants[s.cases[c].variant];
    std::cout << format("  %-*s  %s  %s%s\n", int(width), v.name.c_str(), case_name(c, n).c_str(),
                        results[c].status.c_str(),
                        v.description.empty() ? "" : ("  " + v.description).c_str());
  }

  std::vector<std::vector<Comparison>> table;
  for (std::size_t j = 0; j < s.responses.size(); ++j)
  {
    const std::string& name = s.responses[j];
    std::vector<double> y;
    for (auto& r : results)
      y.push_back(r.responses[j]);
    table.push_back(compare_to_baseline(y));
    const std::string unit = biomarkers::find(name)->unit;
    auto& rj = json["responses"][name];
    rj["unit"] = unit;
    std::cout << "\n" << name << (unit.empty() ? "" : " [" + unit + "]") << "\n"
              << format("  %-*s  %12s  %12s  %9s\n", int(width), "variant", "value", "difference",
                        "percent");
    for (std::size_t c = 0; c < n; ++c)
    {
      const Comparison& k = table[j][c];
      const std::string& variant = s.variants[s.cases[c].variant].name;
      rj["variants"].push_back({{"variant", variant}, {"value", json_number(k.value)},
                                {"difference", json_number(k.difference)},
                                {"percent", json_number(k.percent)}});
      auto shown = [](double v, const char* spec)
      { return std::isfinite(v) ? format(spec, v) : std::string("-"); };
      const bool baseline = c == 0;
      std::cout << format("  %-*s  %12s  %12s  %9s\n", int(width), variant.c_str(),
                          shown(k.value, "%.6g").c_str(),
                          baseline ? "(baseline)" : shown(k.difference, "%+.4g").c_str(),
                          baseline                  ? ""
                          : std::isfinite(k.percent) ? format("%+.2f %%", k.percent).c_str()
                                                     : "-");
    }
  }

  std::ostringstream csv;
  csv << "variant,response,value,difference,percent\n";
  for (std::size_t c = 0; c < n; ++c)
    for (std::size_t j = 0; j < s.responses.size(); ++j)
    {
      const Comparison& k = table[j][c];
      csv << s.variants[s.cases[c].variant].name << "," << s.responses[j] << ","
          << number_or_blank(k.value) << "," << number_or_blank(k.difference) << ","
          << number_or_blank(k.percent) << "\n";
    }
  io::write_atomic(out / "ablation.csv", csv.str());
  io::write_atomic(out / "analysis.json", json.dump(2) + "\n");
}

} // namespace

int run(const Study& s, const Options& o)
{
  const std::size_t n = s.cases.size();
  const int at_once = o.jobs > 0 ? o.jobs : s.jobs;
  // Slurm must take the options before anything runs or is submitted.
  const jobs::Launcher launcher
      = jobs::launcher_for(s.launcher, o.launcher, o.out, s.ranks, "study", s.file);
  std::error_code ec;
  fs::create_directories(o.out / "cases", ec);
  if (ec)
    throw std::runtime_error("cannot create the study folder " + o.out.string() + ": "
                             + ec.message());

  // Finished cases (a summary.json from the same overrides) are kept; a
  // folder from other overrides means another study: refuse to mix.
  const jobs::RunCache cases(o.out / "cases", "case.json", "summary.json");
  std::vector<Result> results(n);
  std::vector<std::size_t> todo;
  for (std::size_t c = 0; c < n; ++c)
  {
    const std::string name = case_name(c, n);
    results[c].responses.assign(s.responses.size(), nan);
    if (!cases.agrees(name, case_record(s, c)))
      throw Error(s.file.string() + ": " + o.out.string() + " holds another study (" + name
                  + " was run with other keys); give a new --out or remove it");
    if (cases.finished(name))
      results[c] = read_result(s, cases.path(name));
    else
      todo.push_back(c);
  }
  std::cout << "study " << s.file.string() << ": " << s.design << ", "
            << (s.variants.empty() ? format("%zu factor(s)", s.factors.size())
                                   : format("%zu variants", s.variants.size()))
            << ", " << n << " cases (" << n - todo.size() << " already done), "
            << at_once << " at once on " << s.ranks << " rank(s) each"
            << (launcher.kind == jobs::Launcher::Kind::slurm ? " through Slurm" : "") << " -> "
            << o.out.string()
            << std::endl;

  jobs::catch_interrupts();

  // Check every case to run (nct check: the eye geometry, the puff...)
  // before running any.
  std::vector<jobs::Job> checks;
  for (std::size_t c : todo)
    checks.push_back(command(s, o, s.cases[c], "check", {},
                             o.out / "cases" / (case_name(c, n) + ".check.log")));
  std::string bad;
  const bool checked = jobs::run(checks, std::max(at_once * s.ranks, 1),
                                [&](std::size_t i, int code)
                                {
                                  if (code != 0 && bad.empty())
                                  {
                                    std::string why = tail(read_text(checks[i].log), 3);
                                    if (why.rfind("error: ", 0) == 0)
                                      why.erase(0, 7);
                                    bad = case_name(todo[i], n) + " ("
                                          + describe_case(s, s.cases[todo[i]]) + "): " + why;
                                  }
                                  fs::remove(checks[i].log);
                                });
  if (!checked)
  {
    std::cerr << "study: interrupted while checking the cases" << std::endl;
    return 130;
  }
  if (!bad.empty())
  {
    while (!bad.empty() && bad.back() == '\n')
      bad.pop_back();
    throw Error(s.file.string() + ": " + bad);
  }
  if (o.dry_run)
  {
    for (std::size_t c = 0; c < n; ++c)
    {
      std::string sets; // an ablation: what the variant sets
      for (std::size_t i = 0; s.cases[c].variant >= 0 && i < s.cases[c].sets.size(); ++i)
        sets += (i ? " " : " (") + s.cases[c].sets[i] + (i + 1 < s.cases[c].sets.size() ? "" : ")");
      std::cout << "  " << case_name(c, n) << ": " << describe_case(s, s.cases[c]) << sets
                << (std::find(todo.begin(), todo.end(), c) == todo.end() ? "  (done)" : "")
                << "\n";
    }
    std::cout << "study: every case checks out; nothing run (--dry-run)" << std::endl;
    return 0;
  }

  io::write_atomic(o.out / "study.toml", read_text(s.file));
  std::vector<jobs::Job> runs;
  for (std::size_t c : todo)
    // An interrupted case starts afresh (one still running on a cluster is followed).
    runs.push_back(cases.nct_run(case_name(c, n), o.program, s.cases[c].scene, s.cases[c].sets,
                                 s.ranks, s.mpiexec, {{"case", case_name(c, n)}}));
  const auto start = std::chrono::steady_clock::now();
  std::size_t finished = n - todo.size();
  io::write_atomic(o.out / "cases.csv", cases_csv(s, results));
  const bool complete = jobs::run(
      launcher, runs, at_once,
      [&](std::size_t i, int code)
      {
        const std::size_t c = todo[i];
        const fs::path dir = o.out / "cases" / case_name(c, n);
        if (fs::exists(dir / "summary.json"))
          results[c] = read_result(s, dir);
        else if (jobs::interrupted())
          return; // stopped: it stays pending
        else
        {
          results[c].status = "error";
          std::cerr << case_name(c, n) << ": nct run exited with " << code << " and no summary; "
                    << (dir / "console.log").string() << " ends:\n"
                    << tail(read_text(dir / "console.log"), 5);
        }
        ++finished;
        const double elapsed
            = std::chrono::duration<double>(std::chrono::steady_clock::now() - start).count();
        std::string line = format("[%zu/%zu] %s %s (%s)", finished, n, case_name(c, n).c_str(),
                                  results[c].status.c_str(),
                                  describe_case(s, s.cases[c]).c_str());
        for (std::size_t j = 0; j < std::min<std::size_t>(s.responses.size(), 4); ++j)
          line += " " + s.responses[j] + "=" + format("%.4g", results[c].responses[j]);
        const std::size_t done_now = finished - (n - todo.size());
        line += format("  %.0f s elapsed, about %.0f s to go", elapsed,
                       elapsed / done_now * (n - finished));
        std::cout << line << std::endl;
        io::write_atomic(o.out / "cases.csv", cases_csv(s, results));
      });
  if (!complete)
  {
    std::cerr << "study: interrupted with " << finished << " of " << n
              << " cases done; the same command resumes it" << std::endl;
    return 130;
  }

  io::write_atomic(o.out / "cases.csv", cases_csv(s, results));
  if (s.design == "ablation")
    analyse_ablation(s, results, o.out);
  else
    analyse(s, results, o.out);
  std::size_t converged = 0;
  for (auto& r : results)
    converged += r.status == "converged";
  std::string tables = "cases.csv, ";
  if (s.design == "ablation")
    tables += "ablation.csv, ";
  else
  {
    tables += "effects.csv, ";
    tables += s.design == "factorial" ? "anova.csv, " : "";
    tables += "main_effects.csv, ";
    tables += fs::exists(o.out / "correlation.csv") ? "correlation.csv, " : "";
  }
  std::cout << "\nstudy: " << converged << " of " << n << " cases converged; tables in "
            << o.out.string() << " (" << tables << "analysis.json); plots: /usr/bin/python3 "
            << "scripts/plot-study.py " << o.out.string() << std::endl;
  return converged == n ? 0 : 3;
}

} // namespace nct::study
