// What a fit's forward run reads at the observation points
// (cpp/fit/readings.h).
#include "fit/readings.h"

#include <algorithm>
#include <cmath>
#include <map>
#include <memory>
#include <sstream>

#include <nlohmann/json.hpp>

#include "io/format.h"
#include "io/text.h"
#include "jobs/jobs.h"
#include "scene/scene.h"

namespace nct::fit
{
namespace fs = std::filesystem;
using io::format;
using io::nan;

namespace
{

/// A column of a CSV table with a header, by name.
std::map<std::string, std::vector<double>> read_table(const fs::path& file,
                                                      const std::vector<std::string>& wanted)
{
  std::istringstream in(io::read_text(file));
  std::string line;
  std::getline(in, line);
  std::vector<std::string> names;
  {
    std::istringstream h(line);
    for (std::string c; std::getline(h, c, ',');)
      names.push_back(c);
  }
  std::map<std::string, std::vector<double>> out;
  std::vector<int> index;
  for (auto& w : wanted)
  {
    auto it = std::find(names.begin(), names.end(), w);
    if (it == names.end())
      throw std::runtime_error(file.string() + " has no column " + w);
    index.push_back(int(it - names.begin()));
    out[w];
  }
  while (std::getline(in, line))
  {
    std::vector<std::string> cells;
    std::istringstream row(line);
    for (std::string c; std::getline(row, c, ',');)
      cells.push_back(c);
    for (std::size_t k = 0; k < wanted.size(); ++k)
    {
      const auto i = std::size_t(index[k]);
      out[wanted[k]].push_back(i < cells.size() && !cells[i].empty() && cells[i] != "nan"
                                   ? std::stod(cells[i]) // non-numeric cells: profiles' surface
                                   : nan);
    }
  }
  return out;
}

/// Linear interpolation of y(x) on ascending x; NaN outside, beyond 1e-3
/// (ms or mm: the rounding of measured data in a CSV).
double interpolate(const std::vector<double>& x, const std::vector<double>& y, double at)
{
  if (x.empty())
    return nan;
  const double slack = 1e-3;
  if (at < x.front() - slack || at > x.back() + slack)
    return nan;
  at = std::clamp(at, x.front(), x.back());
  auto hi = std::lower_bound(x.begin(), x.end(), at);
  const std::size_t j = std::size_t(hi - x.begin());
  if (j == 0)
    return y[0];
  const double w = (at - x[j - 1]) / (x[j] - x[j - 1]);
  return (1 - w) * y[j - 1] + w * y[j];
}

/// A run's corneal profiles: per frame, the surface's x (ascending) and y.
struct Profiles
{
  std::vector<double> t;
  std::map<std::string, std::vector<std::pair<std::vector<double>, std::vector<double>>>> surface;
};

Profiles read_profiles(const fs::path& file)
{
  std::istringstream in(io::read_text(file));
  std::string line;
  std::getline(in, line);
  if (line != "frame,t_ms,surface,x_mm,y_mm")
    throw std::runtime_error(file.string() + ": unexpected header " + line);
  Profiles p;
  while (std::getline(in, line))
  {
    std::istringstream row(line);
    std::string frame, t, surface, x, y;
    std::getline(row, frame, ',');
    std::getline(row, t, ',');
    std::getline(row, surface, ',');
    std::getline(row, x, ',');
    std::getline(row, y, ',');
    const std::size_t f = std::stoul(frame);
    if (f >= p.t.size())
      p.t.resize(f + 1, std::stod(t));
    auto& frames = p.surface[surface];
    frames.resize(p.t.size());
    frames[f].first.push_back(std::stod(x));
    frames[f].second.push_back(std::stod(y));
  }
  for (auto& [name, frames] : p.surface)
    for (auto& [x, y] : frames)
    {
      std::vector<std::size_t> order(x.size());
      for (std::size_t i = 0; i < order.size(); ++i)
        order[i] = i;
      std::sort(order.begin(), order.end(), [&](auto a, auto b) { return x[a] < x[b]; });
      std::vector<double> xs, ys;
      for (auto i : order)
        xs.push_back(x[i]), ys.push_back(y[i]);
      x = xs, y = ys;
    }
  return p;
}

/// A profile observation's model values: at each point (t, x), the
/// surface's height at x interpolated between the frames around t (less
/// the t = 0 profile's where the observation is relative to it).
void profile_values(const Observation& o, const Profiles& profiles, const std::string& where,
                    std::vector<double>& out)
{
  const auto& frames = profiles.surface.at(o.quantity);
  const auto& ts = profiles.t;
  for (std::size_t i = 0; i < o.t.size(); ++i)
  {
    auto y_at = [&](std::size_t f)
    {
      const double y = interpolate(frames[f].first, frames[f].second, o.x[i]);
      if (std::isnan(y))
        throw scene::Error(where + format("x = %g mm is outside the model's %s profile "
                                          "[%g, %g] mm",
                                          o.x[i], o.quantity.c_str(), frames[f].first.front(),
                                          frames[f].first.back()));
      return o.relative ? y - interpolate(frames[0].first, frames[0].second, o.x[i]) : y;
    };
    auto hi = std::lower_bound(ts.begin(), ts.end(), o.t[i] - 1e-3);
    if (hi == ts.end())
      throw scene::Error(where + format("t = %g ms is after the run's last frame", o.t[i]));
    const std::size_t j = std::size_t(hi - ts.begin());
    if (j == 0)
      out.push_back(y_at(0));
    else
    {
      const double w = std::clamp((o.t[i] - ts[j - 1]) / (ts[j] - ts[j - 1]), 0.0, 1.0);
      out.push_back((1 - w) * y_at(j - 1) + w * y_at(j));
    }
  }
}

} // namespace

std::vector<double> model_values(const Fit& fit, const fs::path& run)
{
  std::vector<double> out;
  const auto summary = nlohmann::json::parse(io::read_text(run / "summary.json"));
  std::map<std::string, std::vector<double>> frames;
  std::unique_ptr<Profiles> profiles;
  for (std::size_t k = 0; k < fit.observations.size(); ++k)
  {
    const Observation& o = fit.observations[k];
    const std::string where = fit.file.string() + ": observation[" + std::to_string(k + 1)
                              + "] (" + o.label + "): ";
    if (o.kind == Kind::biomarker)
    {
      if (!summary.contains(o.quantity) || !summary[o.quantity].is_number())
        throw scene::Error(where + "the run " + run.string() + " gives no " + o.quantity
                           + " (the puff did not reach it: e.g. no second applanation)");
      out.push_back(summary[o.quantity].get<double>());
    }
    else if (o.kind == Kind::curve)
    {
      if (frames.empty())
        frames = read_table(run / "frames.csv", {"t_ms", "apex_displacement_mm",
                                                 "whole_eye_motion_mm"});
      for (double t : o.t)
      {
        out.push_back(interpolate(frames["t_ms"], frames[o.quantity], t));
        if (std::isnan(out.back()))
          throw scene::Error(where + format("t = %g ms is outside the run's frames [%g, %g] ms",
                                            t, frames["t_ms"].front(), frames["t_ms"].back()));
      }
    }
    else
    {
      if (!profiles)
        profiles = std::make_unique<Profiles>(read_profiles(run / "profiles.csv"));
      profile_values(o, *profiles, where, out);
    }
  }
  return out;
}

} // namespace nct::fit
