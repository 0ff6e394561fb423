// Reading and validating a study file (cpp/study/study.h): its [study]
// table, its factors or variants, and every case's scene.
#include <algorithm>
#include <charconv>

#include <toml++/toml.h>

#include "biomarkers/registry.h"
#include "io/csv.h"
#include "io/format.h"
#include "io/toml_input.h"
#include "jobs/launcher_input.h"
#include "scene/scene.h"
#include "study/study.h"

namespace nct::study
{
using io::check_name;
using io::format;
using io::key_error;
using io::literal;
using io::string_list;
using scene::Error;
namespace fs = std::filesystem;

namespace
{

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

/// A table design's factor's optional range = [low, high] and scale
/// ("linear" or "log", which needs low > 0).
void read_range(const toml::table& ft, const std::string& where, Factor& f, const fs::path& file)
{
  f.scale = ft["scale"].value_or<std::string>("linear");
  if (f.scale != "linear" && f.scale != "log")
    throw key_error(file, where + "scale", "\"linear\" or \"log\", got \"" + f.scale + "\"");
  if (!ft.contains("range"))
  {
    if (ft.contains("scale"))
      throw key_error(file, where + "scale", "a scale needs a range = [low, high]");
    return;
  }
  const toml::array* r = ft["range"].as_array();
  if (!r || r->size() != 2 || !r->get(0)->is_number() || !r->get(1)->is_number())
    throw key_error(file, where + "range", "two numbers [low, high]");
  f.range = {*r->get(0)->value<double>(), *r->get(1)->value<double>()};
  if (!(f.range[0] < f.range[1]))
    throw key_error(file, where + "range", format("low %g is not below high %g", f.range[0],
                                                  f.range[1]));
  if (f.scale == "log" && f.range[0] <= 0)
    throw key_error(file, where + "range", format("a log scale needs low > 0, got %g",
                                                  f.range[0]));
}

/// One [[factor]] table (the i-th): its keys, label and levels.
Factor read_factor(const toml::table& ft, std::size_t i, const Study& s, io::KeyErrors& errors)
{
  const fs::path& file = s.file;
  const std::string where = "factor[" + std::to_string(i + 1) + "].";
  refuse_unknown_study_keys(ft, {"key", "levels", "label", "range", "scale"}, file, where, errors);
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
  if (s.design != "table" && (ft.contains("range") || ft.contains("scale")))
    throw key_error(file, where + (ft.contains("range") ? "range" : "scale"),
                    "a factor's range and scale belong to a table design (the box its design "
                    "fills); a " + s.design + " study gives levels");
  if (s.design == "table")
  {
    if (ft.contains("levels"))
      throw key_error(file, where + "levels", "a table design takes each case's values from "
                                              "study.cases: drop levels");
    read_range(ft, where, f, file);
    return f;
  }
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
  return f;
}

/// The case at these levels (per factor; -1: the scene's value): the
/// study's overrides, then each factor's keys set to its level.
Case case_at(const Study& s, const std::vector<int>& levels)
{
  Case c{levels, s.sets, -1, s.scene};
  for (std::size_t i = 0; i < s.factors.size(); ++i)
    if (levels[i] >= 0)
      for (auto& key : s.factors[i].keys)
        c.sets.push_back(key + "=" + s.factors[i].levels[levels[i]]);
  return c;
}

/// A 2^k factorial's cases, in Yates order (the first factor changes fastest).
void factorial_cases(Study& s)
{
  const std::size_t k = s.factors.size();
  if (k > 12)
    throw key_error(s.file, "factor", format("%zu factors make 2^%zu cases; at most 12 factors",
                                             k, k));
  for (std::size_t c = 0; c < (std::size_t(1) << k); ++c)
  {
    std::vector<int> levels(k);
    for (std::size_t i = 0; i < k; ++i)
      levels[i] = (c >> i) & 1;
    s.cases.push_back(case_at(s, levels));
  }
}

/// One factor at a time: the base scene, then each factor's levels that
/// differ from its value there; each factor's base value.
void one_factor_cases(Study& s)
{
  const std::size_t k = s.factors.size();
  // The base scene's value of each factor (its first key).
  toml::table base;
  try
  {
    base = toml::parse(scene::Scene::load(s.scene, s.sets).to_toml());
  }
  catch (const Error& e)
  {
    throw Error(s.file.string() + ": the base scene: " + e.what());
  }
  s.cases.push_back(case_at(s, std::vector<int>(k, -1)));
  for (std::size_t i = 0; i < k; ++i)
  {
    const toml::node* v = base.at_path(s.factors[i].keys[0]).node();
    if (!v || !v->is_number())
      throw key_error(s.file, "factor[" + std::to_string(i + 1) + "].key",
                      s.factors[i].keys[0] + " is not a number in the base scene: a "
                      "one-factor-at-a-time factor is numeric");
    s.base_values.push_back(*v->value<double>());
    for (std::size_t j = 0; j < s.factors[i].levels.size(); ++j)
      if (s.factors[i].values[j] != s.base_values[i])
      {
        std::vector<int> levels(k, -1);
        levels[i] = int(j);
        s.cases.push_back(case_at(s, levels));
      }
  }
}

/// v as the shortest TOML float literal that reads back as v.
std::string shortest_literal(double v)
{
  char buf[32];
  const auto end = std::to_chars(buf, buf + sizeof buf, v).ptr;
  std::string s(buf, end);
  if (s.find_first_of(".e") == std::string::npos)
    s += ".0";
  return s;
}

/// A table design's cases: a row of study.cases each, a column per
/// factor (named by its label); each factor's levels are its distinct
/// values in the order they first appear.
void table_cases(Study& s)
{
  io::NumberTable t;
  try
  {
    t = io::read_number_table(s.cases_file, "design table");
  }
  catch (const std::invalid_argument& e)
  {
    throw key_error(s.file, "study.cases", e.what());
  }
  std::vector<std::size_t> column(s.factors.size());
  for (std::size_t i = 0; i < s.factors.size(); ++i)
  {
    const auto at = std::find(t.header.begin(), t.header.end(), s.factors[i].label);
    if (at == t.header.end())
      throw key_error(s.file, "study.cases", s.cases_file.string() + ": no column '"
                                                 + s.factors[i].label + "' (factor "
                                                 + std::to_string(i + 1) + "'s label)");
    column[i] = std::size_t(at - t.header.begin());
  }
  for (const std::string& name : t.header)
    if (std::count(t.header.begin(), t.header.end(), name) > 1
        || std::none_of(s.factors.begin(), s.factors.end(),
                        [&](const Factor& f) { return f.label == name; }))
      throw key_error(s.file, "study.cases",
                      s.cases_file.string() + ": the column '" + name + "' is "
                          + (std::count(t.header.begin(), t.header.end(), name) > 1
                                 ? "given twice"
                                 : "no factor's label"));
  for (std::size_t r = 0; r < t.rows.size(); ++r)
  {
    std::vector<int> levels(s.factors.size());
    for (std::size_t i = 0; i < s.factors.size(); ++i)
    {
      Factor& f = s.factors[i];
      const double v = t.rows[r][column[i]];
      if (!f.range.empty() && (v < f.range[0] || v > f.range[1]))
        throw key_error(s.file, "study.cases",
                        format("%s:%d: %s = %s is outside its range [%g, %g]",
                               s.cases_file.string().c_str(), t.lines[r], f.label.c_str(),
                               shortest_literal(v).c_str(), f.range[0], f.range[1]));
      auto at = std::find(f.values.begin(), f.values.end(), v);
      if (at == f.values.end())
      {
        f.values.push_back(v);
        f.levels.push_back(shortest_literal(v));
        at = f.values.end() - 1;
      }
      levels[i] = int(at - f.values.begin());
    }
    for (std::size_t c = 0; c < s.cases.size(); ++c)
      if (s.cases[c].levels == levels)
        throw key_error(s.file, "study.cases",
                        format("%s:%d: the same case as line %d", s.cases_file.string().c_str(),
                               t.lines[r], t.lines[c]));
    s.cases.push_back(case_at(s, levels));
  }
}

/// The factors of a factorial, one-factor-at-a-time or table study, and
/// its cases (when every factor reads).
void read_factors(const toml::table& t, Study& s, io::KeyErrors& errors)
{
  const toml::array* factors = t["factor"].as_array();
  if (!factors || factors->empty() || !factors->is_array_of_tables())
    throw key_error(s.file, "factor", "missing: one [[factor]] table per factor (key, levels)");
  bool read = true;
  for (std::size_t i = 0; i < factors->size(); ++i)
    read = errors.attempt([&] {
      s.factors.push_back(read_factor(*factors->get(i)->as_table(), i, s, errors));
    }) && read;
  if (!read)
    return;
  if (s.design == "factorial")
    factorial_cases(s);
  else if (s.design == "table")
    table_cases(s);
  else
    one_factor_cases(s);
}

/// One [[variant]] table (the i-th) of an ablation study.
Variant read_variant(const toml::table& vt, std::size_t i, const Study& s, io::KeyErrors& errors)
{
  const fs::path& file = s.file;
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
  return v;
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
      Variant v = read_variant(*vs->get(i)->as_table(), i, s, errors);
      Case c{{}, s.sets, int(s.variants.size()), v.scene};
      c.sets.insert(c.sets.end(), v.sets.begin(), v.sets.end());
      s.cases.push_back(std::move(c));
      s.variants.push_back(std::move(v));
    });
}

/// study.responses: summary.json keys of the biomarker registry, each once.
std::vector<std::string> read_responses(const toml::table& st, const fs::path& file)
{
  if (!st["responses"])
    throw key_error(file, "study.responses", "missing: the summary.json keys to analyse");
  auto responses = string_list(*st["responses"].node(), file, "study.responses", false);
  if (responses.empty())
    throw key_error(file, "study.responses", "name at least one response");
  for (auto& r : responses)
  {
    if (!biomarkers::find(r))
    {
      std::string list;
      for (auto& k : biomarkers::registry())
        list += (list.empty() ? "" : ", ") + k.key;
      throw key_error(file, "study.responses", "unknown response '" + r + "'; one of " + list);
    }
    if (std::count(responses.begin(), responses.end(), r) > 1)
      throw key_error(file, "study.responses", "'" + r + "' is listed twice");
  }
  return responses;
}

/// The keys of the [study] table `st`; whether its scene and its design read.
std::pair<bool, bool> read_study_table(const toml::table& st, Study& s, io::KeyErrors& errors)
{
  const fs::path& file = s.file;
  std::set<std::string> known = {"scene", "design", "cases", "responses", "set", "ranks", "jobs",
                                 "mpiexec"};
  known.insert(jobs::launcher_keys().begin(), jobs::launcher_keys().end());
  refuse_unknown_study_keys(st, known, file, "study.", errors);

  const bool scene_read = errors.attempt([&] {
    const toml::node* scene = st["scene"].node();
    s.scene = scene_path(file, "study.scene", scene && scene->is_string() ? scene : nullptr);
  });
  const bool design_read = errors.attempt([&] {
    s.design = st["design"].value_or<std::string>("factorial");
    if (s.design != "factorial" && s.design != "ofat" && s.design != "ablation"
        && s.design != "table")
      throw key_error(file, "study.design", "\"factorial\" (2^k full), \"ofat\" (one factor "
                                            "at a time), \"ablation\" (named variants against "
                                            "the first) or \"table\" (the cases of a CSV "
                                            "file, study.cases), got \"" + s.design + "\"");
    const toml::node* cases = st["cases"].node();
    if (s.design == "table" && !(cases && cases->is_string()))
      throw key_error(file, "study.cases", "missing: a table design's CSV file (a column per "
                                           "factor's label, a row per case)");
    if (s.design != "table" && cases)
      throw key_error(file, "study.cases", "only a table design reads its cases from a file; "
                                           "this study's design is \"" + s.design + "\"");
    if (cases)
    {
      s.cases_file = file.parent_path() / *cases->value<std::string>();
      if (!fs::exists(s.cases_file))
        throw key_error(file, "study.cases", s.cases_file.string() + " not found");
    }
  });
  errors.attempt([&] { s.responses = read_responses(st, file); });
  errors.attempt([&] {
    if (auto* set = st["set"].node())
      s.sets = string_list(*set, file, "study.set", false);
  });

  const jobs::RunKeys runs = jobs::read_run_keys(st, "study", file, errors);
  s.ranks = runs.ranks;
  s.jobs = runs.jobs;
  s.mpiexec = runs.mpiexec;
  s.launcher = jobs::read_launcher(st, "study", file, errors);
  return {scene_read, design_read};
}

/// The design's cases: factors and their levels, or named variants.
void read_design(const toml::table& t, Study& s, bool scene_read, io::KeyErrors& errors)
{
  const bool ablation = s.design == "ablation";
  errors.attempt([&] {
    if (ablation && t.contains("factor"))
      throw key_error(s.file, "factor", "an ablation study compares [[variant]] tables and takes "
                                        "no [[factor]]; design = \"factorial\" or \"ofat\" "
                                        "varies factors");
    if (!ablation && t.contains("variant"))
      throw key_error(s.file, "variant", "[[variant]] tables are the cases of design = "
                                         "\"ablation\"; a " + s.design
                                             + " study varies [[factor]] tables");
    if (ablation)
      read_variants(t, s, errors);
    else if (scene_read || !t.contains("factor"))
      read_factors(t, s, errors);
  });
}

/// Every case's scene must load: unknown keys, types and ranges are
/// caught here, before anything runs (the base scene's own problems
/// once, not once per case). Two variants whose resolved scenes agree
/// would be the same case.
void check_scenes(const Study& s, io::KeyErrors& errors)
{
  errors.attempt([&] {
    try
    {
      scene::Scene::load(s.scene, s.sets);
    }
    catch (const Error& e)
    {
      throw key_error(s.file, "study.scene", std::string("the base scene with study.set: ")
                                                 + e.what());
    }
  });
  if (!errors.empty())
    return;
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
        throw Error(s.file.string() + ": " + s.case_name(c) + " (" + s.describe(s.cases[c])
                    + "): " + e.what());
      }
    });
  for (std::size_t c = 0; s.design == "ablation" && c < s.cases.size(); ++c)
    for (std::size_t d = 0; d < c; ++d)
      if (loaded[c] && loaded[d] && resolved[d] == resolved[c])
      {
        errors.add(key_error(s.file, "variant[" + std::to_string(c + 1) + "].set",
                             "'" + s.variants[c].name + "' makes the same scene as '"
                                 + s.variants[d].name + "' (with study.set, their overrides "
                                 "come to the same values): the two would be the same case")
                       .what());
        break;
      }
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
  Study s;
  s.file = file;
  const auto [scene_read, design_read] = read_study_table(*st, s, errors);
  if (design_read)
    read_design(t, s, scene_read, errors);
  if (errors.empty())
    check_scenes(s, errors);
  errors.raise();
  return s;
}

std::string Study::case_name(std::size_t c) const
{
  const int width = std::max<int>(3, std::to_string(cases.size()).size());
  return format("case-%0*zu", width, c + 1);
}

std::string Study::describe(const Case& c) const
{
  if (c.variant >= 0)
    return variants[c.variant].name;
  std::string out;
  for (std::size_t i = 0; i < factors.size(); ++i)
    out += (i ? ", " : "") + factors[i].label + "="
           + (c.levels[i] < 0 ? "base" : factors[i].levels[c.levels[i]]);
  return out;
}

double Study::factor_value(const Case& c, std::size_t i) const
{
  return c.levels[i] < 0 ? base_values[i] : factors[i].values[c.levels[i]];
}

} // namespace nct::study
