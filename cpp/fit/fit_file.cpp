// Reading and validating a fit file (cpp/fit/fit.h).
#include <algorithm>
#include <cmath>
#include <fstream>
#include <set>
#include <thread>

#include "fit/fit.h"
#include "jobs/launcher_input.h"
#include "io/csv.h"
#include "io/format.h"
#include "io/toml_input.h"
#include "scene/scene.h"
#include "settings/settings.h"
#include "study/study.h"

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

/// The biomarkers a fit may compare: a puff run's summary.json values
/// (the study's responses without the solver's counts and times).
const std::vector<std::string>& biomarkers()
{
  static const std::vector<std::string> list = []
  {
    std::vector<std::string> out;
    for (auto& [name, unit] : study::known_responses())
      if (name != "newton_iterations" && name != "step_cuts" && name != "wall_s")
        out.push_back(name);
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

Parameter read_parameter(const toml::table& pt, std::size_t i, const Fit& fit,
                         io::KeyErrors& errors)
{
  const fs::path& file = fit.file;
  const std::string where = "parameter[" + std::to_string(i + 1) + "].";
  io::only(pt, {"key", "label", "start", "bounds", "log", "prior"}, file, where, "[[parameter]]",
           errors);
  Parameter p;
  if (!pt["key"])
    throw key_error(file, where + "key", "missing: the scene key (or keys) the parameter sets");
  p.keys = io::string_list(*pt["key"].node(), file, where + "key", true);
  if (p.keys.empty())
    throw key_error(file, where + "key", "name at least one scene key");
  const auto& declared = scene::keys();
  for (auto& k : p.keys)
  {
    // The key must be a real scene key (a "*" declaration matches a part name).
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
    if (d == declared.end())
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
    io::only(*t, {"mean", "sd"}, file, where + "prior.", "a prior", errors);
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
  Observation o;
  auto sd_key = [&]() -> double
  {
    auto sd = number(ot, "sd", file, where + "sd");
    if (sd && !(*sd > 0))
      throw key_error(file, where + "sd", format("must be above 0, got %g", *sd));
    return sd ? *sd : NAN;
  };
  if (ot.contains("biomarker"))
  {
    io::only(ot, {"biomarker", "value", "sd", "label"}, file, where, "a biomarker observation",
             errors);
    o.kind = Kind::biomarker;
    o.quantity = ot["biomarker"].value_or(std::string());
    if (std::find(biomarkers().begin(), biomarkers().end(), o.quantity) == biomarkers().end())
      throw key_error(file, where + "biomarker", "'" + o.quantity + "' is not a biomarker a "
                                                 "puff run gives; one of " + join(biomarkers()));
    o.value = {required(ot, "value", file, where + "value", "the measured value")};
    const double sd = sd_key();
    if (std::isnan(sd))
      throw key_error(file, where + "sd", "missing: the measurement's SD (its weight)");
    o.sd = {sd};
    o.t = {NAN};
    o.x = {NAN};
    o.label = o.quantity;
  }
  else
  {
    const bool curve = ot.contains("curve");
    o.kind = curve ? Kind::curve : Kind::profile;
    const std::string name = curve ? "curve" : "profile";
    if (curve)
      io::only(ot, {"curve", "quantity", "sd", "label"}, file, where, "a curve observation",
               errors);
    else
      io::only(ot, {"profile", "surface", "reference", "sd", "label"}, file, where,
               "a profile observation", errors);
    o.file = io::file_path(file, where + name, ot[name].node(), "CSV file");
    const double sd = sd_key();
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
  }
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

Fit Fit::load(const fs::path& file)
{
  const toml::table t = io::parse_toml(file, "fit file");
  io::KeyErrors errors(file, t);
  io::only(t, {"fit", "parameter", "observation"}, file, "", "a fit file", errors);
  const toml::table* ft = t["fit"].as_table();
  if (!ft)
  {
    errors.add(key_error(file, "fit", "missing: a [fit] table names the base scene").what());
    errors.raise();
  }
  io::only(*ft, {"scene", "set", "ranks", "jobs", "mpiexec", "launcher", "slurm", "max_iterations",
                 "step", "differences", "tolerance"},
           file, "fit.", "[fit]", errors);
  Fit fit;
  fit.file = file;
  bool scene_read = errors.attempt(
      [&] { fit.scene = io::file_path(file, "fit.scene", (*ft)["scene"].node(), "scene file"); });
  scene_read = errors.attempt([&] {
    if (auto* set = (*ft)["set"].node())
      fit.sets = io::string_list(*set, file, "fit.set", false);
  }) && scene_read;

  auto integer = [&](const char* key, long def, long lo, long hi)
  { return io::integer(*ft, "fit", key, def, lo, hi, file); };
  auto real = [&](const char* key, double def, double lo, double hi)
  {
    auto v = number(*ft, key, file, std::string("fit.") + key);
    if (v && (*v <= lo || *v >= hi))
      throw key_error(file, std::string("fit.") + key,
                      format("a number in (%g, %g), got %g", lo, hi, *v));
    return v ? *v : def;
  };
  fit.ranks = 1;
  errors.attempt([&] { fit.ranks = integer("ranks", 1, 1, 4096); });
  errors.attempt([&] {
    const long cores = std::max(1u, std::thread::hardware_concurrency());
    fit.jobs = integer("jobs", std::max(1L, cores / fit.ranks), 1, 4096);
  });
  errors.attempt([&] {
    fit.mpiexec = (*ft)["mpiexec"].value_or<std::string>("mpiexec --bind-to none");
    if (fit.mpiexec.find_first_not_of(" \t") == std::string::npos)
      throw key_error(file, "fit.mpiexec",
                      "empty: the MPI launcher, e.g. \"mpiexec --bind-to none\"");
  });
  fit.launcher = jobs::read_launcher(*ft, "fit", file, errors);
  errors.attempt([&] { fit.max_iterations = integer("max_iterations", 20, 1, 1000); });
  errors.attempt([&] { fit.step = real("step", 0.01, 0, 0.5); });
  errors.attempt([&] { fit.tolerance = real("tolerance", 1e-4, 0, 1); });
  errors.attempt([&] {
    const std::string differences = (*ft)["differences"].value_or(std::string("forward"));
    if (differences != "forward" && differences != "central")
      throw key_error(file, "fit.differences", "\"forward\" (one run per parameter) or "
                                               "\"central\" (two), got \"" + differences + "\"");
    fit.central = differences == "central";
  });

  // The base scene with the fit's overrides must load, and simulate a puff
  // on the eye (its duration bounds the readings' times).
  std::optional<double> duration;
  if (scene_read)
    scene_read = errors.attempt([&] {
      scene::Scene base = [&]
      {
        try
        {
          return scene::Scene::load(fit.scene, fit.sets);
        }
        catch (const Error& e)
        {
          throw key_error(file, "fit.set", e.what());
        }
      }();
      scene::Reader reader(base);
      PuffSettings puff;
      visit(reader, puff);
      if (!puff.prescribed() && puff.load != PuffSettings::Load::fsi)
        throw key_error(file, "fit.scene", fit.scene.string() + " simulates no puff on the eye: "
                                           "there are no readings to compare");
      duration = puff.duration;
    });

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

  if (errors.empty() && fit.residuals() < fit.parameters.size())
    errors.add(key_error(file, "observation", format("%zu measured values (with priors) cannot "
                                                     "determine %zu parameters",
                                                     fit.residuals(), fit.parameters.size()))
                   .what());
  errors.raise();
  return fit;
}

} // namespace nct::fit
