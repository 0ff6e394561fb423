#include "biomarkers/record.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>

namespace nct::biomarkers
{
namespace
{

std::vector<std::string> names(const Columns& c)
{
  std::vector<std::string> n;
  for (auto& [name, v] : c)
    n.push_back(name);
  return n;
}

std::vector<double> values(const Columns& c)
{
  std::vector<double> v;
  for (auto& [name, x] : c)
    v.push_back(x);
  return v;
}

std::vector<double> blend(const std::vector<double>& a, const std::vector<double>& b, double s)
{
  std::vector<double> c(a.size());
  for (std::size_t i = 0; i < a.size(); ++i)
    c[i] = (1 - s) * a[i] + s * b[i];
  return c;
}

void row(std::ostringstream& out, const std::vector<double>& v)
{
  for (std::size_t i = 0; i < v.size(); ++i)
    out << (i ? "," : "") << v[i];
  out << "\n";
}

void header(std::ostringstream& out, const std::vector<std::string>& names)
{
  for (std::size_t i = 0; i < names.size(); ++i)
    out << (i ? "," : "") << names[i];
  out << "\n";
}

} // namespace

SectionState hermite(const SectionState& a, const SectionState& b, double s, double h)
{
  // The cubic Hermite basis on [0, 1]
  const double h00 = (1 + 2 * s) * (1 - s) * (1 - s), h10 = s * (1 - s) * (1 - s),
               h01 = s * s * (3 - 2 * s), h11 = -s * s * (1 - s);
  // d/ds of the above, over h: the velocity
  const double d00 = -6 * s * (1 - s) / h, d10 = (1 - s) * (1 - 3 * s) / h,
               d01 = 6 * s * (1 - s) / h, d11 = s * (3 * s - 2) / h;
  SectionState c{a.X, a.x, a.y, a.uy, a.vx, a.vy};
  for (std::size_t i = 0; i < a.X.size(); ++i)
  {
    for (auto [p, v, out] : {std::tuple{&SectionState::x, &SectionState::vx, &c.x},
                             {&SectionState::y, &SectionState::vy, &c.y},
                             {&SectionState::uy, &SectionState::vy, &c.uy}})
      (*out)[i] = h00 * (a.*p)[i] + h10 * h * (a.*v)[i] + h01 * (b.*p)[i] + h11 * h * (b.*v)[i];
    for (auto [p, v, out] : {std::tuple{&SectionState::x, &SectionState::vx, &c.vx},
                             {&SectionState::uy, &SectionState::vy, &c.vy}})
      (*out)[i] = d00 * (a.*p)[i] + d10 * h * (a.*v)[i] + d01 * (b.*p)[i] + d11 * h * (b.*v)[i];
  }
  return c;
}

Record::Record(Section anterior, Section posterior, double frame_rate, double whole_eye_x,
               std::vector<std::pair<std::string, std::function<double(double)>>> known)
    : _anterior(std::move(anterior)), _posterior(std::move(posterior)),
      _frame_interval(1e3 / frame_rate), _whole_eye_x(whole_eye_x), _known(std::move(known))
{
}

void Record::add(double t, const Columns& given, const Columns& solver)
{
  Columns state;
  for (auto& [name, f] : _known)
    state.push_back({name, f(t)});
  state.insert(state.end(), given.begin(), given.end());
  if (_steps.empty())
    _state_names = names(state), _solver_names = names(solver);
  else if (names(state) != _state_names || names(solver) != _solver_names)
    throw std::logic_error("Record::add: the columns changed between steps");
  Instant now{t, _anterior.sample(), _posterior.sample(), values(state)};
  if (_steps.empty())
    _origin = {now.anterior.uy.front(), now.anterior.displacement_at(_whole_eye_x)};
  std::vector<double> step{t};
  for (double v : values(solver))
    step.push_back(v);
  step.insert(step.end(), now.state.begin(), now.state.end());
  step.push_back(apex(now));
  step.push_back(whole_eye(now));
  _steps.push_back(step);
  if (t < -1e-12)
    return;
  // The frames in (last, t]; the first state at t >= 0 opens them.
  for (double tf = _frames.size() * _frame_interval;; tf = _frames.size() * _frame_interval)
  {
    if (!_last)
    {
      if (std::abs(t - tf) > 1e-9)
        throw std::logic_error("Record::add: the frames must start at the puff's start");
      _frames.push_back(now);
      break;
    }
    if (tf > t + 1e-9)
      break;
    const double s = std::clamp((tf - _last->t) / (t - _last->t), 0.0, 1.0);
    const double h = t - _last->t;
    Instant frame{tf, hermite(_last->anterior, now.anterior, s, h),
                  hermite(_last->posterior, now.posterior, s, h),
                  blend(_last->state, now.state, s)};
    for (std::size_t i = 0; i < _known.size(); ++i)
      frame.state[i] = _known[i].second(tf);
    _frames.push_back(std::move(frame));
  }
  _last = std::move(now);
}

namespace
{
nlohmann::json to_json(const SectionState& s)
{
  return {{"X", s.X}, {"x", s.x}, {"y", s.y}, {"uy", s.uy}, {"vx", s.vx}, {"vy", s.vy}};
}
SectionState section_state(const nlohmann::json& j)
{
  SectionState s;
  j.at("X").get_to(s.X), j.at("x").get_to(s.x), j.at("y").get_to(s.y);
  j.at("uy").get_to(s.uy), j.at("vx").get_to(s.vx), j.at("vy").get_to(s.vy);
  return s;
}
} // namespace

nlohmann::json Record::state() const
{
  auto instant = [](const Instant& i) -> nlohmann::json
  {
    return {{"t", i.t},
            {"anterior", to_json(i.anterior)},
            {"posterior", to_json(i.posterior)},
            {"state", i.state}};
  };
  nlohmann::json j{{"origin", _origin},
                   {"state_names", _state_names},
                   {"solver_names", _solver_names},
                   {"steps", _steps},
                   {"frames", nlohmann::json::array()}};
  for (const auto& f : _frames)
    j["frames"].push_back(instant(f));
  if (_last)
    j["last"] = instant(*_last);
  return j;
}

void Record::restore(const nlohmann::json& j)
{
  auto instant = [](const nlohmann::json& i)
  {
    return Instant{i.at("t"), section_state(i.at("anterior")), section_state(i.at("posterior")),
                   i.at("state").get<std::vector<double>>()};
  };
  j.at("origin").get_to(_origin);
  j.at("state_names").get_to(_state_names);
  j.at("solver_names").get_to(_solver_names);
  j.at("steps").get_to(_steps);
  _frames.clear();
  for (const auto& f : j.at("frames"))
    _frames.push_back(instant(f));
  _last.reset();
  if (j.contains("last"))
    _last = instant(j.at("last"));
}

std::string Record::steps_csv() const
{
  std::ostringstream out;
  out.precision(10);
  std::vector<std::string> n{"t_ms"};
  n.insert(n.end(), _solver_names.begin(), _solver_names.end());
  n.insert(n.end(), _state_names.begin(), _state_names.end());
  n.insert(n.end(), {"apex_displacement_mm", "whole_eye_motion_mm"});
  header(out, n);
  for (const auto& s : _steps)
    row(out, s);
  return out.str();
}

std::string Record::frames_csv() const
{
  std::ostringstream out;
  out.precision(10);
  std::vector<std::string> n{"t_ms", "apex_displacement_mm", "whole_eye_motion_mm"};
  n.insert(n.end(), _state_names.begin(), _state_names.end());
  header(out, n);
  for (const auto& f : _frames)
  {
    std::vector<double> v{f.t, apex(f), whole_eye(f)};
    v.insert(v.end(), f.state.begin(), f.state.end());
    row(out, v);
  }
  return out.str();
}

std::string Record::profiles_csv() const
{
  std::ostringstream out;
  out.precision(10);
  out << "frame,t_ms,surface,x_mm,y_mm\n";
  for (std::size_t k = 0; k < _frames.size(); ++k)
    for (const auto& [surface, section] :
         {std::pair{"anterior", &_frames[k].anterior}, {"posterior", &_frames[k].posterior}})
    {
      const Profile p = section->profile();
      for (std::size_t i = 0; i < p.x.size(); ++i)
        out << k << "," << _frames[k].t << "," << surface << "," << p.x[i] << "," << p.y[i]
            << "\n";
    }
  return out.str();
}

Result Record::analyse(Definitions d) const
{
  d.frame_interval = _frame_interval;
  std::vector<double> t, apex_u, whole;
  std::vector<Profile> anterior;
  for (const auto& f : _frames)
  {
    t.push_back(f.t);
    anterior.push_back(f.anterior.profile());
    apex_u.push_back(apex(f));
    whole.push_back(whole_eye(f));
  }
  return biomarkers::analyse(t, anterior, apex_u, whole, d);
}

std::vector<double> Record::column(const std::string& name) const
{
  auto it = std::find(_state_names.begin(), _state_names.end(), name);
  if (it == _state_names.end())
    throw std::logic_error("Record: no state column '" + name + "'");
  std::vector<double> c;
  for (const auto& f : _frames)
    c.push_back(f.state[it - _state_names.begin()]);
  return c;
}

double Record::at(const std::string& name, double t) const
{
  std::vector<double> times;
  for (const auto& f : _frames)
    times.push_back(f.t);
  return at_time(times, column(name), t);
}

double Record::max(const std::string& name) const
{
  const auto c = column(name);
  return *std::max_element(c.begin(), c.end());
}

} // namespace nct::biomarkers
