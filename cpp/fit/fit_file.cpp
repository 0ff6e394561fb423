// Reading and validating a fit file (fit/fit_file.h).
#include "fit/fit_file.h"

#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <sstream>

#include "biomarkers/registry.h"
#include "fit/emulated.h"
#include "io/text.h"
#include "jobs/jobs.h"
#include "jobs/launcher_input.h"
#include "io/csv.h"
#include "io/format.h"
#include "io/toml_input.h"
#include "scene/scene.h"
#include "settings/settings.h"

namespace nct::fit
{
namespace fs = std::filesystem;
using io::format;
using io::key_error;
using io::literal;
using scene::Error;

namespace
{

/// A number at `key` (an integer is taken as a real), or nullopt if absent.
std::optional<double> number(const toml::table& t, const std::string& name,
                             const fs::path& file, const std::string& key)
{
  const toml::node* n = t[name].node();
  if (!n)
    return std::nullopt;
  if (auto v = n->value<double>(); v && (n->is_floating_point() || n->is_integer())
                                   && std::isfinite(*v))
    return *v;
  throw key_error(file, key, "expected a finite number, got " + literal(*n));
}

double required(const toml::table& t, const std::string& name, const fs::path& file,
                const std::string& key, const std::string& what)
{
  auto v = number(t, name, file, key);
  if (!v)
    throw key_error(file, key, "missing: " + what);
  return *v;
}

/// The readings of the biomarker registry: the summary.json values a fit
/// may compare.
const std::vector<std::string>& readings()
{
  static const std::vector<std::string> list = []
  {
    std::vector<std::string> out;
    for (auto& e : biomarkers::registry())
      if (e.reading)
        out.push_back(e.key);
    return out;
  }();
  return list;
}

/// The frames.csv columns a curve may follow (lengths in mm).
const std::vector<std::string>& curve_quantities()
{
  static const std::vector<std::string> list = {"apex_displacement_mm", "whole_eye_motion_mm"};
  return list;
}

std::string join(const std::vector<std::string>& items)
{
  std::string out;
  for (auto& s : items)
    out += (out.empty() ? "" : ", ") + s;
  return out;
}

/// The CSV of a curve or profile: `columns` (without the SD) and an
/// optional last column sd_mm; returns the rows, the SD column NaN when
/// absent.
std::vector<std::vector<double>> read_points(const fs::path& csv, const std::string& columns,
                                             const fs::path& file, const std::string& key)
{
  std::ifstream in(csv);
  std::string header;
  std::getline(in, header);
  header.erase(std::remove_if(header.begin(), header.end(), ::isspace), header.end());
  const bool with_sd = header == columns + ",sd_mm";
  std::vector<std::vector<double>> rows;
  try
  {
    if (columns == "t_ms,value_mm")
    {
      if (with_sd)
        for (auto& r : io::read_csv<3>(csv, columns + ",sd_mm", "observation").values)
          rows.push_back({r[0], r[1], r[2]});
      else
        for (auto& r : io::read_csv<2>(csv, columns, "observation").values)
          rows.push_back({r[0], r[1], NAN});
    }
    else if (with_sd)
      for (auto& r : io::read_csv<4>(csv, columns + ",sd_mm", "observation").values)
        rows.push_back({r[0], r[1], r[2], r[3]});
    else
      for (auto& r : io::read_csv<3>(csv, columns, "observation").values)
        rows.push_back({r[0], r[1], r[2], NAN});
  }
  catch (const std::invalid_argument& e)
  {
    throw key_error(file, key, std::string(e.what()) + " (or " + columns + ",sd_mm)");
  }
  return rows;
}

/// The declaration of scene key `k` (a "*" declaration matches a part
/// name), or null.
const scene::Key* declared_key(const std::string& k)
{
  const auto& declared = scene::keys();
  auto matches = [&](const scene::Key& d)
  {
    const auto star = d.name.find('*');
    if (star == std::string::npos)
      return d.name == k;
    const std::string pre = d.name.substr(0, star), post = d.name.substr(star + 1);
    if (k.size() <= pre.size() + post.size() || k.compare(0, pre.size(), pre) != 0
        || k.compare(k.size() - post.size(), post.size(), post) != 0)
      return false;
    return k.substr(pre.size(), k.size() - pre.size() - post.size()).find('.')
           == std::string::npos;
  };
  auto d = std::find_if(declared.begin(), declared.end(), matches);
  return d == declared.end() ? nullptr : &*d;
}

/// The cells of a CSV line (no quoting), each trimmed.
std::vector<std::string> split_csv_line(const std::string& line)
{
  std::vector<std::string> out;
  std::istringstream in(line);
  for (std::string c; std::getline(in, c, ',');)
  {
    const auto a = c.find_first_not_of(" \t\r"), b = c.find_last_not_of(" \t\r");
    out.push_back(a == std::string::npos ? "" : c.substr(a, b - a + 1));
  }
  if (!line.empty() && line.back() == ',')
    out.emplace_back();
  return out;
}

/// What a column of a patients' table holds.
enum class Role
{
  patient,    ///< the patient's name
  folder,     ///< the readings' folder
  key,        ///< a scene key's value
  prior_mean, ///< prior.<label>.mean
  prior_sd,   ///< prior.<label>.sd
  truth,      ///< truth.<label>
  covariate   ///< carried as it is
};
using Column = std::pair<Role, std::string>; ///< the role, and the key or label

/// Each column's role from the table's header; a column of no known kind,
/// or one missing, named.
std::vector<Column> column_roles(const std::vector<std::string>& header, const Cohort& c,
                                 const fs::path& file)
{
  const std::string table = c.table.string();
  std::vector<Column> roles;
  std::set<std::string> seen;
  for (const auto& h : header)
  {
    if (!seen.insert(h).second)
      throw Error(format("%s: the column '%s' is there twice", table.c_str(), h.c_str()));
    auto ends = [&](const std::string& tail)
    { return h.size() > tail.size() && h.compare(h.size() - tail.size(), tail.size(), tail) == 0; };
    if (h == "patient" || h == "folder")
      roles.push_back({h == "patient" ? Role::patient : Role::folder, h});
    else if (h.rfind("prior.", 0) == 0 && (ends(".mean") || ends(".sd")))
      roles.push_back({ends(".mean") ? Role::prior_mean : Role::prior_sd,
                       h.substr(6, h.rfind('.') - 6)});
    else if (h.rfind("truth.", 0) == 0)
      roles.push_back({Role::truth, h.substr(6)});
    else if (std::count(c.covariates.begin(), c.covariates.end(), h))
      roles.push_back({Role::covariate, h});
    else if (declared_key(h))
      roles.push_back({Role::key, h});
    else
      throw Error(format("%s: the column '%s' is none of patient, folder, a scene key ('nct "
                         "describe'), prior.<label>.mean, prior.<label>.sd, truth.<label> or a "
                         "covariate (cohort.covariates in %s)",
                         table.c_str(), h.c_str(), file.string().c_str()));
  }
  for (const char* required : {"patient", "folder"})
    if (!seen.count(required))
      throw Error(format("%s: the column '%s' is missing (%s)", table.c_str(), required,
                         std::string(required) == "patient"
                             ? "each patient's name"
                             : "each patient's readings folder, relative to the table"));
  for (const auto& [role, label] : roles)
    if ((role == Role::prior_mean && !seen.count("prior." + label + ".sd"))
        || (role == Role::prior_sd && !seen.count("prior." + label + ".mean")))
      throw Error(format("%s: the column 'prior.%s.%s' is missing (a prior is a mean and an "
                         "SD)",
                         table.c_str(), label.c_str(), role == Role::prior_mean ? "sd" : "mean"));
  for (const auto& cov : c.covariates)
    if (!seen.count(cov))
      throw Error(format("%s: the covariate '%s' (cohort.covariates in %s) is not a column",
                         table.c_str(), cov.c_str(), file.string().c_str()));

  return roles;
}

/// A number in cell i of a patients' table's row (`where` names the row).
double real_cell(const std::vector<std::string>& row, const std::vector<std::string>& header,
                 std::size_t i, const std::string& where)
{
  std::size_t used = 0;
  double v = NAN;
  try
  {
    v = std::stod(row[i], &used);
  }
  catch (const std::exception&)
  {
  }
  if (used != row[i].size() || !std::isfinite(v))
    throw Error(format("%s, column '%s': expected a number, got '%s'", where.c_str(),
                       header[i].c_str(), row[i].c_str()));
  return v;
}

/// One patient from a row of the patients' table (the `number`-th, at
/// `where`): each cell by its column's role; an empty cell keeps the fit
/// file's (or the scene's) value. Its id must be none of `ids`, the rows'
/// before.
Patient read_patient(const std::vector<std::string>& row, const std::vector<std::string>& header,
                     const std::vector<Column>& roles, const Cohort& c, std::size_t number,
                     const std::string& where, const std::set<std::string>& ids)
{
  Patient p;
  p.row = number;
  if (row.size() != header.size())
    throw Error(format("%s: %zu cells for the header's %zu columns", where.c_str(), row.size(),
                       header.size()));
  std::map<std::string, double> means, sds;
  for (std::size_t i = 0; i < row.size(); ++i)
  {
    const auto& [role, name] = roles[i];
    if (row[i].empty() && role != Role::patient && role != Role::folder)
      continue; // the fit file's (or the scene's) value
    switch (role)
    {
    case Role::patient:
      p.id = row[i];
      break;
    case Role::folder:
      p.folder = c.table.parent_path() / row[i];
      break;
    case Role::key:
      p.sets.push_back(name + "=" + row[i]);
      break;
    case Role::prior_mean:
      means[name] = real_cell(row, header, i, where);
      break;
    case Role::prior_sd:
      sds[name] = real_cell(row, header, i, where);
      if (!(sds[name] > 0))
        throw Error(format("%s, column '%s': must be above 0, got %s", where.c_str(),
                           header[i].c_str(), row[i].c_str()));
      break;
    case Role::truth:
      p.truths[name] = real_cell(row, header, i, where);
      break;
    case Role::covariate:
      p.covariates.push_back({name, row[i]});
      break;
    }
  }
  try
  {
    io::check_name(c.table, "patient", p.id, "the patient's folder in the output");
  }
  catch (const Error& e)
  {
    throw Error(where + ", column 'patient': " + (p.id.empty() ? "empty" : e.what()));
  }
  if (ids.count(p.id))
    throw Error(format("%s: the patient '%s' is there twice", where.c_str(), p.id.c_str()));
  if (!fs::is_directory(p.folder))
    throw Error(format("%s (patient %s), column 'folder': %s is not a folder", where.c_str(),
                       p.id.c_str(), p.folder.string().c_str()));
  for (auto& [label, mean] : means)
  {
    if (!sds.count(label))
      throw Error(format("%s (patient %s): prior.%s.mean without its prior.%s.sd",
                         where.c_str(), p.id.c_str(), label.c_str(), label.c_str()));
    p.priors[label] = {mean, sds[label]};
  }
  for (auto& [label, sd] : sds)
    if (!means.count(label))
      throw Error(format("%s (patient %s): prior.%s.sd without its prior.%s.mean",
                         where.c_str(), p.id.c_str(), label.c_str(), label.c_str()));
  return p;
}

/// The [cohort] table of a fit file and its patients' table (docs/manual.md,
/// "Fit a cohort"): every column known, every cell readable, before any run.
Cohort read_cohort(const toml::table& ct, const fs::path& file)
{
  io::KeyErrors errors(file, ct);
  io::refuse_unknown_keys(ct, {"table", "covariates", "patients"}, file, "cohort.", "[cohort]",
                          errors);
  errors.raise();
  Cohort c;
  c.table = io::file_path(file, "cohort.table", ct["table"].node(), "patients' table (CSV)");
  if (const toml::node* cov = ct["covariates"].node())
    c.covariates = io::string_list(*cov, file, "cohort.covariates", true);
  c.at_once = int(io::integer(ct, "cohort", "patients", 0, 1, 4096, file));
  const std::string table = c.table.string();

  std::istringstream in(io::read_text(c.table));
  std::string line;
  std::size_t number = 0; // the file's line
  auto next = [&]
  {
    while (std::getline(in, line))
    {
      ++number;
      if (line.find_first_not_of(" \t\r") != std::string::npos && line[0] != '#')
        return true;
    }
    return false;
  };
  if (!next())
    throw Error(table + ": empty: a header (patient,folder,...) and a row per patient");
  const std::vector<std::string> header = split_csv_line(line);
  const std::vector<Column> roles = column_roles(header, c, file);
  std::set<std::string> ids;
  while (next())
  {
    const std::size_t row = c.patients.size() + 1;
    const std::string where = format("%s line %zu (row %zu)", table.c_str(), number, row);
    c.patients.push_back(read_patient(split_csv_line(line), header, roles, c, row, where, ids));
    ids.insert(c.patients.back().id);
  }
  if (c.patients.empty())
    throw Error(table + ": no patient: a row per patient under the header");
  return c;
}

Parameter read_parameter(const toml::table& pt, std::size_t i, const Fit& fit,
                         io::KeyErrors& errors)
{
  const fs::path& file = fit.file;
  const std::string where = "parameter[" + std::to_string(i + 1) + "].";
  io::refuse_unknown_keys(pt, {"key", "label", "start", "bounds", "log", "prior"}, file, where,
                          "[[parameter]]", errors);
  Parameter p;
  if (!pt["key"])
    throw key_error(file, where + "key", "missing: the scene key (or keys) the parameter sets");
  p.keys = io::string_list(*pt["key"].node(), file, where + "key", true);
  if (p.keys.empty())
    throw key_error(file, where + "key", "name at least one scene key");
  for (auto& k : p.keys)
  {
    // The key must be a real scene key.
    const scene::Key* d = declared_key(k);
    if (!d)
      throw key_error(file, where + "key", "'" + k + "' is not a scene key ('nct describe' "
                                                    "lists them)");
    if (d->kind != scene::Kind::real)
      throw key_error(file, where + "key", "'" + k + "' is not a real number; a fit varies "
                                                    "numeric keys (stiffness, IOP...)");
  }
  p.label = pt["label"].value_or(p.keys[0].substr(p.keys[0].rfind('.') + 1));
  io::check_name(file, where + "label", p.label, "a column of iterations.csv");
  for (auto& q : fit.parameters)
  {
    if (q.label == p.label)
      throw key_error(file, where + "label", "'" + p.label + "' names two parameters");
    for (auto& k : q.keys)
      if (std::count(p.keys.begin(), p.keys.end(), k))
        throw key_error(file, where + "key", "'" + k + "' is fitted twice (also by '"
                                                  + q.label + "')");
  }

  const toml::array* bounds = pt["bounds"].as_array();
  if (!bounds || bounds->size() != 2 || !bounds->get(0)->value<double>()
      || !bounds->get(1)->value<double>())
    throw key_error(file, where + "bounds", "missing or not [lower, upper] (two numbers)");
  p.lower = *bounds->get(0)->value<double>();
  p.upper = *bounds->get(1)->value<double>();
  if (!(p.lower < p.upper))
    throw key_error(file, where + "bounds", format("lower %g is not below upper %g", p.lower,
                                                   p.upper));
  p.start = required(pt, "start", file, where + "start", "the first guess");
  if (p.start < p.lower || p.start > p.upper)
    throw key_error(file, where + "start", format("%g is outside the bounds [%g, %g]", p.start,
                                                  p.lower, p.upper));
  const toml::node* log = pt["log"].node();
  if (log && !log->is_boolean())
    throw key_error(file, where + "log", "expected true (fit log(value)) or false, got "
                                             + literal(*log));
  p.log = log ? *log->value<bool>() : p.lower > 0;
  if (p.log && p.lower <= 0)
    throw key_error(file, where + "log", format("a log-scale parameter needs bounds above 0, "
                                                "got lower %g", p.lower));
  if (const toml::node* prior = pt["prior"].node())
  {
    const toml::table* t = prior->as_table();
    if (!t)
      throw key_error(file, where + "prior", "expected {mean = ..., sd = ...}, got "
                                                 + literal(*prior));
    io::refuse_unknown_keys(*t, {"mean", "sd"}, file, where + "prior.", "a prior", errors);
    p.prior = true;
    p.prior_mean = required(*t, "mean", file, where + "prior.mean", "the measured value");
    p.prior_sd = required(*t, "sd", file, where + "prior.sd", "the measurement's SD");
    if (!(p.prior_sd > 0))
      throw key_error(file, where + "prior.sd", format("must be above 0, got %g", p.prior_sd));
  }

  // The scene must take the parameter at its start and both bounds (the
  // keys' ranges, contradictions).
  for (double v : {p.start, p.lower, p.upper})
  {
    std::vector<std::string> sets = fit.sets;
    for (auto& k : p.keys)
      sets.push_back(k + "=" + literal(v));
    try
    {
      scene::Scene::load(fit.scene, sets);
    }
    catch (const Error& e)
    {
      throw key_error(file, where + (v == p.start ? "start" : "bounds"), e.what());
    }
  }
  return p;
}

/// An observation's key `sd` (above 0), NaN when absent.
double observation_sd(const toml::table& ot, const fs::path& file, const std::string& where)
{
  auto sd = number(ot, "sd", file, where + "sd");
  if (sd && !(*sd > 0))
    throw key_error(file, where + "sd", format("must be above 0, got %g", *sd));
  return sd ? *sd : NAN;
}

/// A biomarker observation (`where`: "observation[i]."): a summary.json
/// reading, its measured value and SD.
Observation read_biomarker(const toml::table& ot, const std::string& where, const fs::path& file,
                           io::KeyErrors& errors)
{
  io::refuse_unknown_keys(ot, {"biomarker", "value", "sd", "label"}, file, where,
                          "a biomarker observation", errors);
  Observation o;
  o.kind = Kind::biomarker;
  o.quantity = ot["biomarker"].value_or(std::string());
  if (const auto* e = biomarkers::find(o.quantity); !e || !e->reading)
    throw key_error(file, where + "biomarker", "'" + o.quantity + "' is not a biomarker a "
                                               "puff run gives; one of " + join(readings()));
  o.value = {required(ot, "value", file, where + "value", "the measured value")};
  const double sd = observation_sd(ot, file, where);
  if (std::isnan(sd))
    throw key_error(file, where + "sd", "missing: the measurement's SD (its weight)");
  o.sd = {sd};
  o.t = {NAN};
  o.x = {NAN};
  o.label = o.quantity;
  return o;
}

/// The CSV file of a curve or profile at key `name`: relative to the fit
/// file, or to a cohort's patient's folder.
fs::path observation_file(const toml::table& ot, const std::string& name,
                          const std::string& where, const Fit& fit)
{
  if (!fit.patient)
    return io::file_path(fit.file, where + name, ot[name].node(), "CSV file");
  const auto csv = ot[name].value_exact<std::string>();
  if (!csv)
    throw key_error(fit.file, where + name, "missing or not a string: CSV file");
  const fs::path path = fit.patient->folder / *csv;
  if (!fs::is_regular_file(path))
    throw key_error(fit.file, where + name, "the patient's CSV file " + path.string()
                                                + " not found");
  return path;
}

/// A curve (frames.csv's column against time) or profile (the corneal
/// surface at times and x) observation: its quantity, and its points
/// from its CSV, each within the puff's `duration`, with its SD.
Observation read_curve_or_profile(const toml::table& ot, const std::string& where,
                                  const Fit& fit, std::optional<double> duration,
                                  io::KeyErrors& errors)
{
  const fs::path& file = fit.file;
  const bool curve = ot.contains("curve");
  Observation o;
  o.kind = curve ? Kind::curve : Kind::profile;
  const std::string name = curve ? "curve" : "profile";
  if (curve)
    io::refuse_unknown_keys(ot, {"curve", "quantity", "sd", "label"}, file, where,
                            "a curve observation", errors);
  else
    io::refuse_unknown_keys(ot, {"profile", "surface", "reference", "sd", "label"}, file, where,
                            "a profile observation", errors);
  o.file = observation_file(ot, name, where, fit);
  const double sd = observation_sd(ot, file, where);
  if (curve)
  {
    o.quantity = ot["quantity"].value_or(std::string("apex_displacement_mm"));
    if (std::find(curve_quantities().begin(), curve_quantities().end(), o.quantity)
        == curve_quantities().end())
      throw key_error(file, where + "quantity", "'" + o.quantity + "': one of the frames.csv "
                                                "columns " + join(curve_quantities()));
    o.label = o.quantity;
  }
  else
  {
    o.quantity = ot["surface"].value_or(std::string("anterior"));
    if (o.quantity != "anterior" && o.quantity != "posterior")
      throw key_error(file, where + "surface", "\"anterior\" or \"posterior\", got \""
                                                   + o.quantity + "\"");
    const std::string reference = ot["reference"].value_or(std::string("rest"));
    if (reference != "rest" && reference != "absolute")
      throw key_error(file, where + "reference",
                      "\"rest\" (y is the surface's axial displacement from its t = 0 "
                      "profile) or \"absolute\" (the model's coordinates), got \""
                          + reference + "\"");
    o.relative = reference == "rest";
    o.label = "profile_" + o.quantity;
  }
  const auto rows = read_points(o.file, curve ? "t_ms,value_mm" : "t_ms,x_mm,y_mm", file,
                                where + name);
  const bool file_sd = !std::isnan(rows[0].back());
  if (file_sd && !std::isnan(sd))
    throw key_error(file, where + "sd", "the CSV has an sd_mm column: give the SD there or "
                                        "here, not both");
  if (!file_sd && std::isnan(sd))
    throw key_error(file, where + "sd", "missing: the points' SD (or an sd_mm column in "
                                            + o.file.string() + ")");
  for (std::size_t r = 0; r < rows.size(); ++r)
  {
    const auto& row = rows[r];
    const double t = row[0];
    if (duration && (t < 0 || t > *duration))
      throw key_error(file, where + name, format("%s row %zu: t = %g ms is outside the puff "
                                                 "the scene simulates, [0, %g] ms",
                                                 o.file.string().c_str(), r + 1, t, *duration));
    o.t.push_back(t);
    o.x.push_back(curve ? NAN : row[1]);
    o.value.push_back(curve ? row[1] : row[2]);
    o.sd.push_back(file_sd ? row.back() : sd);
    if (!(o.sd.back() > 0))
      throw key_error(file, where + name, format("%s row %zu: sd_mm must be above 0, got %g",
                                                 o.file.string().c_str(), r + 1, o.sd.back()));
  }
  return o;
}

/// The i-th [[observation]] table: a biomarker, curve or profile, and its
/// label (each once).
Observation read_observation(const toml::table& ot, std::size_t i, const Fit& fit,
                             std::optional<double> duration, io::KeyErrors& errors)
{
  const fs::path& file = fit.file;
  const std::string where = "observation[" + std::to_string(i + 1) + "].";
  const int kinds = ot.contains("biomarker") + ot.contains("curve") + ot.contains("profile");
  if (kinds != 1)
    throw key_error(file, where.substr(0, where.size() - 1),
                    "give exactly one of biomarker (a summary.json value), curve (a CSV "
                    "t_ms,value_mm[,sd_mm]) or profile (a CSV t_ms,x_mm,y_mm[,sd_mm])");
  Observation o = ot.contains("biomarker") ? read_biomarker(ot, where, file, errors)
                                           : read_curve_or_profile(ot, where, fit, duration,
                                                                   errors);
  if (auto label = ot["label"].value<std::string>())
    o.label = *label;
  io::check_name(file, where + "label", o.label, "a row of observations.csv");
  for (auto& q : fit.observations)
    if (q.label == o.label)
      throw key_error(file, where + "label", "'" + o.label + "' names two observations; give "
                                                 "each a label");
  return o;
}

} // namespace

std::size_t Fit::residuals() const
{
  std::size_t m = 0;
  for (auto& o : observations)
    m += o.value.size();
  for (auto& p : parameters)
    m += p.prior;
  return m;
}

namespace
{

/// A patient's priors (replacing the file's) and truths, checked against
/// the parameters; its scene keys must not be fitted ones.
void apply_patient(Fit& fit, const Patient& patient)
{
  auto parameter = [&](const std::string& label, const std::string& column) -> Parameter&
  {
    for (auto& p : fit.parameters)
      if (p.label == label)
        return p;
    throw Error("column '" + column + "': no parameter is labelled '" + label + "'");
  };
  for (const auto& [label, prior] : patient.priors)
  {
    Parameter& p = parameter(label, "prior." + label + ".mean");
    p.prior = true;
    p.prior_mean = prior.first;
    p.prior_sd = prior.second;
  }
  for (const auto& [label, truth] : patient.truths)
  {
    const Parameter& p = parameter(label, "truth." + label);
    if (truth < p.lower || truth > p.upper)
      throw Error(format("column 'truth.%s': %g is outside the parameter's bounds [%g, %g]",
                         label.c_str(), truth, p.lower, p.upper));
  }
  for (const auto& set : patient.sets)
  {
    const std::string key = set.substr(0, set.find('='));
    for (const auto& p : fit.parameters)
      if (std::count(p.keys.begin(), p.keys.end(), key))
        throw Error("column '" + key + "' sets a key the fit varies (parameter '" + p.label
                    + "'): give a measured value as prior." + p.label + ".mean and .sd");
  }
}

/// The keys of a fit on an emulator: the file, the posterior's sampler,
/// the confirming run (the file's content is checked by attach_emulator).
void read_emulator_keys(const toml::table& ft, Fit& fit, io::KeyErrors& errors)
{
  const fs::path& file = fit.file;
  errors.attempt([&] {
    if (ft["emulator"])
      fit.emulator_file = io::file_path(file, "fit.emulator", ft["emulator"].node(),
                                        "emulator file (python/nct/emulator.py's export)");
  });
  errors.attempt([&] {
    if (ft["discrepancy"])
      fit.discrepancy_file = io::file_path(file, "fit.discrepancy", ft["discrepancy"].node(),
                                           "discrepancy file (nct.discrepancy's)");
  });
  errors.attempt([&] {
    fit.posterior = ft["posterior"].value_or(std::string("auto"));
    if (fit.posterior != "auto" && fit.posterior != "mcmc" && fit.posterior != "laplace")
      throw key_error(file, "fit.posterior", "\"auto\" (sampled where two parameters correlate "
                                             "beyond 0.9), \"mcmc\" or \"laplace\", got \""
                                                 + fit.posterior + "\"");
  });
  errors.attempt([&] { fit.walkers = io::integer(ft, "fit", "mcmc_walkers", 32, 8, 1000, file); });
  errors.attempt([&] { fit.steps = io::integer(ft, "fit", "mcmc_steps", 1500, 30, 1000000, file); });
  errors.attempt([&] { fit.seed = io::integer(ft, "fit", "seed", 1, 0, 2147483647, file); });
  errors.attempt([&] {
    fit.corrected_iterations = io::integer(ft, "fit", "corrected_iterations", 5, 1, 1000, file);
  });
  errors.attempt([&] {
    if (auto* c = ft["confirm"].node(); c && !c->is_boolean())
      throw key_error(file, "fit.confirm", "true (a forward run at the answer) or false");
    fit.confirm = ft["confirm"].value_or(true);
  });
  if (!ft.contains("emulator"))
    for (const char* k : {"discrepancy", "posterior", "mcmc_walkers", "mcmc_steps", "seed",
                          "confirm", "corrected_iterations"})
      if (ft.contains(k))
        errors.add(key_error(file, std::string("fit.") + k, "only for a fit on an emulator "
                                                            "(fit.emulator)").what());
}

/// The keys of the [fit] table `ft`; whether its scene and overrides read.
bool read_fit_table(const toml::table& ft, Fit& fit, io::KeyErrors& errors)
{
  const fs::path& file = fit.file;
  std::set<std::string> known = {"scene", "set", "ranks", "jobs", "mpiexec", "max_iterations",
                                 "step", "differences", "tolerance", "emulator", "discrepancy", "posterior",
                                 "mcmc_walkers", "mcmc_steps", "seed", "confirm",
                                 "corrected_iterations"};
  known.insert(jobs::launcher_keys().begin(), jobs::launcher_keys().end());
  io::refuse_unknown_keys(ft, known, file, "fit.", "[fit]", errors);
  bool scene_read = errors.attempt(
      [&] { fit.scene = io::file_path(file, "fit.scene", ft["scene"].node(), "scene file"); });
  scene_read = errors.attempt([&] {
    if (auto* set = ft["set"].node())
      fit.sets = io::string_list(*set, file, "fit.set", false);
  }) && scene_read;

  auto real = [&](const char* key, double def, double lo, double hi)
  {
    auto v = number(ft, key, file, std::string("fit.") + key);
    if (v && (*v <= lo || *v >= hi))
      throw key_error(file, std::string("fit.") + key,
                      format("a number in (%g, %g), got %g", lo, hi, *v));
    return v ? *v : def;
  };
  const jobs::RunKeys runs = jobs::read_run_keys(ft, "fit", file, errors);
  fit.ranks = runs.ranks;
  fit.jobs = runs.jobs;
  fit.mpiexec = runs.mpiexec;
  fit.launcher = jobs::read_launcher(ft, "fit", file, errors);
  errors.attempt([&] {
    fit.max_iterations = io::integer(ft, "fit", "max_iterations", 20, 1, 1000, file);
  });
  errors.attempt([&] { fit.step = real("step", 0.01, 0, 0.5); });
  errors.attempt([&] { fit.tolerance = real("tolerance", 1e-4, 0, 1); });
  errors.attempt([&] {
    const std::string differences = ft["differences"].value_or(std::string("forward"));
    if (differences != "forward" && differences != "central")
      throw key_error(file, "fit.differences", "\"forward\" (one run per parameter) or "
                                               "\"central\" (two), got \"" + differences + "\"");
    fit.central = differences == "central";
  });
  read_emulator_keys(ft, fit, errors);
  return scene_read;
}

/// The base scene with the fit's overrides (and a patient's columns on
/// top, which join the overrides) must load and simulate a puff on the
/// eye: its duration, which bounds the readings' times.
double puff_duration(Fit& fit, const Patient* patient)
{
  scene::Scene base = [&]
  {
    try
    {
      return scene::Scene::load(fit.scene, fit.sets);
    }
    catch (const Error& e)
    {
      throw key_error(fit.file, "fit.set", e.what());
    }
  }();
  // A patient's columns (geometry, measured IOP...) on top.
  if (patient && !patient->sets.empty())
  {
    fit.sets.insert(fit.sets.end(), patient->sets.begin(), patient->sets.end());
    try
    {
      base = scene::Scene::load(fit.scene, fit.sets);
    }
    catch (const Error& e)
    {
      throw Error(std::string("its columns of scene keys: ") + e.what());
    }
  }
  scene::Reader reader(base);
  PuffSettings puff;
  visit(reader, puff);
  if (!puff.prescribed() && puff.load != PuffSettings::Load::fsi)
    throw key_error(fit.file, "fit.scene", fit.scene.string() + " simulates no puff on the eye: "
                                                                "there are no readings to compare");
  return puff.duration;
}

/// The fit of a fit file's toml `t`, for `patient` (a cohort's row) if not null.
Fit load_one(const toml::table& t, const fs::path& file, const Patient* patient)
{
  io::KeyErrors errors(file, t);
  io::refuse_unknown_keys(t, {"fit", "parameter", "observation", "cohort"}, file, "", "a fit file",
                          errors);
  const toml::table* ft = t["fit"].as_table();
  if (!ft)
  {
    errors.add(key_error(file, "fit", "missing: a [fit] table names the base scene").what());
    errors.raise();
  }
  Fit fit;
  fit.file = file;
  if (patient)
    fit.patient = *patient;
  bool scene_read = read_fit_table(*ft, fit, errors);
  std::optional<double> duration;
  if (scene_read)
    scene_read = errors.attempt([&] { duration = puff_duration(fit, patient); });

  errors.attempt([&] {
    const toml::array* ps = t["parameter"].as_array();
    if (!ps || ps->empty() || !ps->is_array_of_tables())
      throw key_error(file, "parameter", "missing: one [[parameter]] table per fitted key "
                                         "(key, start, bounds)");
    for (std::size_t i = 0; scene_read && i < ps->size(); ++i) // their checks need the scene
      errors.attempt([&] {
        fit.parameters.push_back(read_parameter(*ps->get(i)->as_table(), i, fit, errors));
      });
  });

  errors.attempt([&] {
    const toml::array* os = t["observation"].as_array();
    if (!os || os->empty() || !os->is_array_of_tables())
      throw key_error(file, "observation", "missing: one [[observation]] table per reading "
                                           "(biomarker, curve or profile)");
    for (std::size_t i = 0; i < os->size(); ++i)
      errors.attempt([&] {
        fit.observations.push_back(
            read_observation(*os->get(i)->as_table(), i, fit, duration, errors));
      });
  });

  if (patient && errors.empty())
    errors.attempt([&] { apply_patient(fit, *patient); });
  if (!fit.emulator_file.empty() && errors.empty())
    errors.attempt([&] { attach_emulator(fit, scene::Scene::load(fit.scene, fit.sets)); });
  if (errors.empty() && fit.residuals() < fit.parameters.size())
    errors.add(key_error(file, "observation", format("%zu measured values (with priors) cannot "
                                                     "determine %zu parameters",
                                                     fit.residuals(), fit.parameters.size()))
                   .what());
  errors.raise();
  return fit;
}

} // namespace

Fit Fit::load(const fs::path& file, const std::string& patient)
{
  const toml::table t = io::parse_toml(file, "fit file");
  const toml::table* ct = t["cohort"].as_table();
  if (t.contains("cohort") && !ct)
    throw key_error(file, "cohort", "expected a table ([cohort], table = \"patients.csv\")");
  if (!ct)
  {
    if (!patient.empty())
      throw Error(file.string() + ": --patient " + patient + ": the fit file has no [cohort] "
                                  "table of patients");
    return load_one(t, file, nullptr);
  }
  Cohort cohort = read_cohort(*ct, file);
  auto where = [&](const Patient& p)
  {
    return format("%s row %zu (patient %s): ", cohort.table.string().c_str(), p.row,
                  p.id.c_str());
  };
  if (!patient.empty())
  {
    auto p = std::find_if(cohort.patients.begin(), cohort.patients.end(),
                          [&](const Patient& q) { return q.id == patient; });
    if (p == cohort.patients.end())
      throw Error(file.string() + ": --patient " + patient + ": no such patient in "
                  + cohort.table.string());
    try
    {
      return load_one(t, file, &*p);
    }
    catch (const Error& e)
    {
      throw Error(where(*p) + e.what());
    }
  }
  // Every patient's fit is checked before any runs; every row's problem told.
  std::string problems;
  std::optional<Fit> first;
  for (const Patient& p : cohort.patients)
    try
    {
      Fit f = load_one(t, file, &p);
      if (!first)
        first = std::move(f);
    }
    catch (const Error& e)
    {
      problems += (problems.empty() ? "" : "\n") + where(p) + e.what();
    }
  if (!problems.empty())
    throw Error(problems);
  first->patient.reset();
  first->sets.resize(first->sets.size() - cohort.patients[0].sets.size());
  first->cohort = std::move(cohort);
  return *first;
}

} // namespace nct::fit
