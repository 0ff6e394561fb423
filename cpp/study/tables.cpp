// A study's tables (cpp/study/tables.h): the cases' table, the analysis
// of their responses and its console tables.
#include "study/tables.h"

#include <algorithm>
#include <cmath>
#include <iostream>
#include <sstream>

#include <nlohmann/json.hpp>

#include "biomarkers/registry.h"
#include "io/output.h"
#include "io/text.h"
#include "jobs/jobs.h"
#include "study/analysis.h"

namespace nct::study
{
using io::format;
using io::nan;
namespace fs = std::filesystem;

namespace
{

/// A number in a table: "nan", "inf" and "-inf" where it is not finite.
std::string number(double v)
{
  if (std::isnan(v))
    return "nan";
  if (std::isinf(v))
    return v > 0 ? "inf" : "-inf";
  return format("%.10g", v);
}

/// A number in a table, or nothing where it is not finite.
std::string number_or_blank(double v) { return std::isfinite(v) ? number(v) : ""; }

/// A JSON number, or null for NaN and infinities (JSON has neither).
nlohmann::json json_number(double v)
{
  return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json();
}

/// Is case c among those that show factor i's effect? Every case of a
/// factorial; one factor at a time, the cases that vary i and the base
/// (every factor at the scene's value).
bool compared_for(const Study& s, const Case& c, std::size_t i)
{
  return s.design == "factorial" || s.design == "table" || c.levels[i] >= 0
         || std::all_of(c.levels.begin(), c.levels.end(), [](int l) { return l < 0; });
}

/// The analysis' tables as they are written.
struct Tables
{
  nlohmann::json json; ///< analysis.json
  std::ostringstream effects, anova, mains;
};

/// Response j of every case; when a case gave none or every case gave the
/// same value, says so (on stdout and in `rj`) and returns nothing.
std::vector<double> analysable(const Study& s, const std::vector<Result>& results, std::size_t j,
                               nlohmann::json& rj)
{
  const std::string& name = s.responses[j];
  const std::size_t n = s.cases.size();
  std::vector<double> y(n);
  std::string missing;
  for (std::size_t c = 0; c < n; ++c)
  {
    y[c] = results[c].responses[j];
    if (!std::isfinite(y[c]))
      missing += (missing.empty() ? "" : ", ") + s.case_name(c);
  }
  if (!missing.empty())
  {
    rj["skipped"] = "no value from " + missing;
    std::cout << name << ": not analysed, no value from " << missing << "\n";
    return {};
  }
  if (std::all_of(y.begin(), y.end(), [&](double v) { return v == y[0]; }))
  {
    rj["constant"] = y[0];
    std::cout << name << ": " << number(y[0]) << " in every case, no effects\n";
    return {};
  }
  return y;
}

/// A term's name and effect.
using Effects = std::vector<std::pair<std::string, double>>;

/// A factorial's effects of response `name` (values y): its ANOVA's
/// terms into anova.csv and analysis.json.
Effects factorial_effects(const Study& s, const std::string& name, const std::vector<double>& y,
                          Tables& tables)
{
  const std::size_t k = s.factors.size(), n = s.cases.size();
  std::vector<std::vector<int>> coded(n, std::vector<int>(k));
  std::vector<std::string> labels;
  for (auto& f : s.factors)
    labels.push_back(f.label);
  for (std::size_t c = 0; c < n; ++c)
    for (std::size_t i = 0; i < k; ++i)
      coded[c][i] = 2 * s.cases[c].levels[i] - 1;
  const Anova a = factorial_anova(coded, y, labels);
  auto& rj = tables.json["responses"][name];
  Effects effects;
  for (auto& t : a.terms)
  {
    effects.emplace_back(t.name, t.effect);
    tables.anova << name << "," << t.name << ",1," << number(t.sum_sq) << "," << number(t.sum_sq)
                 << "," << number(t.f) << "," << number(t.p) << "," << number(t.percent) << "\n";
    rj["terms"][t.name] = {{"effect", t.effect}, {"sum_sq", t.sum_sq},
                           {"percent", t.percent}, {"F", json_number(t.f)},
                           {"p", json_number(t.p)}};
  }
  const double ms_error = a.error_df > 0 ? a.error_sum_sq / a.error_df : nan;
  tables.anova << name << ",error," << a.error_df << "," << number(a.error_sum_sq) << ","
               << number(ms_error) << ",,,"
               << number(a.total_sum_sq > 0 ? 100 * a.error_sum_sq / a.total_sum_sq : 0) << "\n"
               << name << ",total," << a.total_df << "," << number(a.total_sum_sq)
               << ",,,,100\n";
  rj["error"] = {{"df", a.error_df}, {"sum_sq", a.error_sum_sq}};
  rj["total"] = {{"df", a.total_df}, {"sum_sq", a.total_sum_sq}};
  tables.json["error_term"]
      = a.error_df > 0
            ? format("the interactions of three and more factors, pooled (%d dof): F and p "
                     "test each term against them",
                     a.error_df)
            : std::string("none: a 2^k design with k <= 2 and no replication leaves no "
                          "degrees of freedom once the main factors and two-way "
                          "interactions are fitted, so there is no F or p");
  return effects;
}

/// One factor at a time: each factor's effect is the response at its
/// highest value minus at its lowest (the base included).
Effects one_factor_effects(const Study& s, const std::string& name, const std::vector<double>& y,
                           Tables& tables)
{
  auto& rj = tables.json["responses"][name];
  Effects effects;
  for (std::size_t i = 0; i < s.factors.size(); ++i)
  {
    double lo = INFINITY, hi = -INFINITY, y_lo = nan, y_hi = nan;
    for (std::size_t c = 0; c < s.cases.size(); ++c)
    {
      if (!compared_for(s, s.cases[c], i))
        continue;
      const double x = s.factor_value(s.cases[c], i);
      if (x < lo)
        lo = x, y_lo = y[c];
      if (x > hi)
        hi = x, y_hi = y[c];
    }
    effects.emplace_back(s.factors[i].label, y_hi - y_lo);
    rj["terms"][s.factors[i].label] = {{"effect", y_hi - y_lo}, {"low", lo}, {"high", hi}};
  }
  tables.json["error_term"] = "none: one factor at a time has no ANOVA; the effects are "
                              "differences between single runs and interactions are not seen";
  return effects;
}

/// Response `name`'s effects ranked by size into effects.csv and
/// analysis.json; the first 8 on stdout.
void rank_effects(const std::string& name, Effects effects, Tables& tables)
{
  std::stable_sort(effects.begin(), effects.end(),
                   [](auto& a, auto& b) { return std::abs(a.second) > std::abs(b.second); });
  std::cout << name << ": effects, largest first\n";
  for (std::size_t r = 0; r < effects.size(); ++r)
  {
    tables.effects << name << "," << effects[r].first << "," << number(effects[r].second) << ","
                   << r + 1 << "\n";
    tables.json["responses"][name]["ranking"].push_back(effects[r].first);
    if (r < 8)
      std::cout << format("  %2zu  %-28s %+.4g\n", r + 1, effects[r].first.c_str(),
                          effects[r].second);
  }
}

/// Main effects: the mean response at each level of each factor (one
/// factor at a time: over the cases that vary it, and the base).
void main_effects(const Study& s, const std::string& name, const std::vector<double>& y,
                  Tables& tables)
{
  for (std::size_t i = 0; i < s.factors.size(); ++i)
  {
    std::vector<double> x, ys;
    for (std::size_t c = 0; c < s.cases.size(); ++c)
      if (compared_for(s, s.cases[c], i))
      {
        x.push_back(s.factor_value(s.cases[c], i));
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
      std::string level
          = at == f.values.end() ? number(values[l]) : f.levels[at - f.values.begin()];
      std::replace(level.begin(), level.end(), ',', ';');
      tables.mains << name << "," << f.label << "," << level << "," << number(values[l]) << ","
                   << number(means[l]) << "\n";
    }
  }
}

/// Pearson correlations of factors and responses over the cases that
/// gave every response, as correlation.csv (none: fewer than 3 such cases).
std::string correlation_csv(const Study& s, const std::vector<Result>& results,
                            nlohmann::json& json)
{
  const std::size_t k = s.factors.size();
  std::vector<std::string> names;
  std::vector<std::vector<double>> columns(k + s.responses.size());
  for (auto& f : s.factors)
    names.push_back(f.label);
  for (auto& r : s.responses)
    names.push_back(r);
  std::size_t used = 0;
  for (std::size_t c = 0; c < s.cases.size(); ++c)
  {
    const auto& r = results[c].responses;
    if (!std::all_of(r.begin(), r.end(), [](double v) { return std::isfinite(v); }))
      continue;
    ++used;
    for (std::size_t i = 0; i < k; ++i)
      columns[i].push_back(s.factor_value(s.cases[c], i));
    for (std::size_t j = 0; j < r.size(); ++j)
      columns[k + j].push_back(r[j]);
  }
  json["correlation_cases"] = used;
  if (used < 3)
    return "";
  std::ostringstream corr;
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
  return corr.str();
}

/// The effects, ANOVA, main effects and correlations of the finished
/// cases into the study folder; the rankings on stdout.
void analyse_factors(const Study& s, const std::vector<Result>& results, const fs::path& out)
{
  Tables tables;
  tables.json["design"] = s.design;
  tables.json["cases"] = s.cases.size();
  tables.effects << "response,term,effect,rank\n";
  tables.anova << "response,source,df,sum_sq,mean_sq,F,p,percent\n";
  tables.mains << "response,factor,level,value,mean\n";
  std::cout << "\n";
  for (std::size_t j = 0; j < s.responses.size(); ++j)
  {
    const std::string& name = s.responses[j];
    const std::vector<double> y = analysable(s, results, j, tables.json["responses"][name]);
    if (y.empty())
      continue;
    rank_effects(name,
                 s.design == "factorial" ? factorial_effects(s, name, y, tables)
                                         : one_factor_effects(s, name, y, tables),
                 tables);
    main_effects(s, name, y, tables);
  }
  const std::string corr = correlation_csv(s, results, tables.json);
  io::write_atomic(out / "effects.csv", tables.effects.str());
  if (s.design == "factorial")
    io::write_atomic(out / "anova.csv", tables.anova.str());
  io::write_atomic(out / "main_effects.csv", tables.mains.str());
  if (!corr.empty())
    io::write_atomic(out / "correlation.csv", corr);
  else
    fs::remove(out / "correlation.csv"); // a stale one from an earlier analysis
  io::write_atomic(out / "analysis.json", tables.json.dump(2) + "\n");
}

/// A table design's cases (a space-filling design, an emulator's
/// training runs) have no effects to rank: their correlations into the
/// study folder (correlation.csv, analysis.json); cases.csv holds the rest.
void analyse_table(const Study& s, const std::vector<Result>& results, const fs::path& out)
{
  nlohmann::json json;
  json["design"] = s.design;
  json["cases"] = s.cases.size();
  const std::string corr = correlation_csv(s, results, json);
  if (!corr.empty())
    io::write_atomic(out / "correlation.csv", corr);
  else
    fs::remove(out / "correlation.csv");
  io::write_atomic(out / "analysis.json", json.dump(2) + "\n");
}

/// The widest variant name (7 at least: the header "variant").
int variant_width(const Study& s)
{
  std::size_t width = 7;
  for (const Variant& v : s.variants)
    width = std::max(width, v.name.size());
  return int(width);
}

/// An ablation's variants with their cases and statuses, on stdout and in
/// analysis.json.
void list_variants(const Study& s, const std::vector<Result>& results, nlohmann::json& json)
{
  const std::size_t n = s.cases.size();
  const int width = variant_width(s);
  std::cout << "\nvariants against the baseline, " << s.variants[0].name << ":\n";
  for (std::size_t c = 0; c < n; ++c)
  {
    const Variant& v = s.variants[s.cases[c].variant];
    json["variants"].push_back({{"name", v.name}, {"description", v.description},
                                {"case", s.case_name(c)}, {"status", results[c].status},
                                {"set", v.sets}});
    std::cout << format("  %-*s  %s  %s%s\n", width, v.name.c_str(), s.case_name(c).c_str(),
                        results[c].status.c_str(),
                        v.description.empty() ? "" : ("  " + v.description).c_str());
  }
}

/// Response j of every variant against the baseline's: a table on stdout,
/// its rows in analysis.json.
std::vector<Comparison> compare_response(const Study& s, const std::vector<Result>& results,
                                         std::size_t j, nlohmann::json& json)
{
  const std::string& name = s.responses[j];
  const int width = variant_width(s);
  std::vector<double> y;
  for (auto& r : results)
    y.push_back(r.responses[j]);
  const std::vector<Comparison> table = compare_to_baseline(y);
  const std::string unit = biomarkers::find(name)->unit;
  auto& rj = json["responses"][name];
  rj["unit"] = unit;
  std::cout << "\n" << name << (unit.empty() ? "" : " [" + unit + "]") << "\n"
            << format("  %-*s  %12s  %12s  %9s\n", width, "variant", "value", "difference",
                      "percent");
  auto shown = [](double v, const char* spec)
  { return std::isfinite(v) ? format(spec, v) : std::string("-"); };
  for (std::size_t c = 0; c < s.cases.size(); ++c)
  {
    const Comparison& k = table[c];
    const std::string& variant = s.variants[s.cases[c].variant].name;
    rj["variants"].push_back({{"variant", variant}, {"value", json_number(k.value)},
                              {"difference", json_number(k.difference)},
                              {"percent", json_number(k.percent)}});
    const bool baseline = c == 0;
    std::cout << format("  %-*s  %12s  %12s  %9s\n", width, variant.c_str(),
                        shown(k.value, "%.6g").c_str(),
                        baseline ? "(baseline)" : shown(k.difference, "%+.4g").c_str(),
                        baseline                   ? ""
                        : std::isfinite(k.percent) ? format("%+.2f %%", k.percent).c_str()
                                                   : "-");
  }
  return table;
}

/// An ablation's variants against its baseline into the study folder
/// (ablation.csv, analysis.json); a table per response on stdout.
void analyse_ablation(const Study& s, const std::vector<Result>& results, const fs::path& out)
{
  nlohmann::json json;
  json["design"] = s.design;
  json["cases"] = s.cases.size();
  json["baseline"] = s.variants[0].name;
  json["difference"] = "value - the baseline's value";
  json["percent"] = "100 difference / |the baseline's value|; null when the baseline is 0 or "
                    "either value is missing";
  list_variants(s, results, json);
  std::vector<std::vector<Comparison>> table;
  for (std::size_t j = 0; j < s.responses.size(); ++j)
    table.push_back(compare_response(s, results, j, json));

  std::ostringstream csv;
  csv << "variant,response,value,difference,percent\n";
  for (std::size_t c = 0; c < s.cases.size(); ++c)
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

Result pending(const Study& s)
{
  Result r;
  r.responses.assign(s.responses.size(), nan);
  return r;
}

Result read_result(const Study& s, const fs::path& dir)
{
  Result r = pending(s);
  auto summary = nlohmann::json::parse(io::read_text(dir / "summary.json"));
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
  // The case's wall time closes each row unless a response already is it.
  const bool wall_listed =
      std::find(s.responses.begin(), s.responses.end(), "wall_s") != s.responses.end();
  for (auto& r : s.responses)
    out << "," << r;
  out << (wall_listed ? "\n" : ",wall_s\n");
  for (std::size_t c = 0; c < s.cases.size(); ++c)
  {
    out << s.case_name(c) << "," << results[c].status;
    if (s.cases[c].variant >= 0)
      out << "," << s.variants[s.cases[c].variant].name;
    for (std::size_t i = 0; i < s.factors.size(); ++i)
      out << "," << number(s.factor_value(s.cases[c], i));
    for (double v : results[c].responses)
      out << "," << number(v);
    if (!wall_listed)
      out << "," << number(results[c].wall_s);
    out << "\n";
  }
  return out.str();
}

void analyse(const Study& s, const std::vector<Result>& results, const fs::path& out)
{
  if (s.design == "ablation")
    analyse_ablation(s, results, out);
  else if (s.design == "table")
    analyse_table(s, results, out);
  else
    analyse_factors(s, results, out);
}

int report_outcome(const Study& s, const std::vector<Result>& results, const fs::path& out)
{
  std::size_t converged = 0;
  for (auto& r : results)
    converged += r.status == "converged";
  std::string tables = "cases.csv, ";
  if (s.design == "ablation")
    tables += "ablation.csv, ";
  else if (s.design == "table")
    tables += fs::exists(out / "correlation.csv") ? "correlation.csv, " : "";
  else
  {
    tables += "effects.csv, ";
    tables += s.design == "factorial" ? "anova.csv, " : "";
    tables += "main_effects.csv, ";
    tables += fs::exists(out / "correlation.csv") ? "correlation.csv, " : "";
  }
  std::cout << "\nstudy: " << converged << " of " << s.cases.size()
            << " cases converged; tables in " << out.string() << " (" << tables
            << "analysis.json)" << std::endl;
  return converged == s.cases.size() ? 0 : 3;
}

} // namespace nct::study
