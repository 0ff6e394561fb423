#include "run/air_output.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <dolfinx/mesh/utils.h>

#include "io/format.h"
#include "run/air_block.h"

namespace nct
{
namespace
{

constexpr double mmHg = 1.333224e-4; // MPa
using io::format;

/// The nodes of the anterior cornea on the plane z = 0, by increasing x
/// (= r): where the corneal pressure table is sampled. Collective.
std::vector<std::array<double, 3>> corneal_section(const meshio::Tagged& m)
{
  const auto& mesh = *m.mesh;
  const auto facets = m.facets->find(m.groups.surfaces.at("anterior_cornea"));
  const auto nodes
      = dolfinx::mesh::entities_to_geometry(mesh, mesh.topology().dim() - 1, facets, false);
  const auto& x = mesh.geometry().x();
  std::vector<double> local;
  for (auto n : nodes)
    if (std::abs(x[3 * n + 2]) < 1e-9)
      local.insert(local.end(), {x[3 * n], x[3 * n + 1]});
  const std::vector<double> all = meshio::all_gather(mesh.comm(), local);
  std::vector<std::array<double, 3>> points;
  for (std::size_t i = 0; i < all.size(); i += 2)
    points.push_back({all[i], all[i + 1], 0.0});
  std::sort(points.begin(), points.end());
  points.erase(std::unique(points.begin(), points.end(),
                           [](const auto& a, const auto& b) { return std::abs(a[0] - b[0]) < 1e-9; }),
               points.end());
  return points;
}

/// The largest |u| over the mesh [mm/ms]. Collective.
double max_speed(const dolfinx::fem::Function<double>& u)
{
  const auto& map = *u.function_space()->dofmap()->index_map;
  auto x = u.x()->array();
  const int bs = u.x()->bs();
  double m = 0;
  for (std::int32_t i = 0; i < map.size_local(); ++i)
    m = std::max(m, std::hypot(x[bs * i], x[bs * i + 1], bs == 3 ? x[bs * i + 2] : 0.0));
  MPI_Allreduce(MPI_IN_PLACE, &m, 1, MPI_DOUBLE, MPI_MAX, map.comm());
  return m;
}

/// The centreline's points: 2-10 mm from the nozzle's exit.
std::vector<std::array<double, 3>> centreline_points(const AirMesh& a)
{
  const double y_exit = a.eye.apex_y + a.domain.nozzle_distance;
  std::vector<std::array<double, 3>> line;
  for (double d : centreline_distances)
    line.push_back({0, y_exit - d, 0});
  return line;
}

} // namespace

AirFields::AirFields(const AirBlockSettings& settings, io::RunFolder& folder, const meshio::Tagged& mesh,
                     air::Problem& air, const mesh_motion::Problem* motion)
    : _write(settings.fields), _interval(settings.air.output_interval), _air(air),
      _motion(motion), _fields(folder, mesh.mesh, air.w->function_space()),
      _moving(motion ? std::make_unique<io::MovingFields>(folder, mesh.mesh) : nullptr)
{
}

void AirFields::sample(double time)
{
  const double interval = _interval;
  if (!_write || time < _next_output - 1e-9 * interval)
    return;
  const double t0 = MPI_Wtime();
  if (_moving)
    for (const auto* f : {_air.velocity.get(), _air.pressure.get(), _motion->d.get()})
      _moving->write(*f, *_motion->d, time);
  else
  {
    _fields.write(*_air.velocity, time);
    _fields.write(*_air.pressure, time);
  }
  while (_next_output <= time + 1e-9 * interval)
    _next_output += interval;
  t_output += MPI_Wtime() - t0;
}

nlohmann::json AirFields::state() const
{
  return {{"next_output", _next_output},
          {"t_output", t_output},
          {"files", _moving ? _moving->state() : _fields.state()}};
}

void AirFields::restore(const nlohmann::json& state)
{
  _next_output = state.at("next_output");
  t_output = state.at("t_output");
  if (_moving)
    _moving->resume(state.at("files"));
  else
    _fields.resume(state.at("files"));
}

AirOutput::AirOutput(const AirBlockSettings& settings, io::RunFolder& folder, const AirMesh& a,
                     air::Problem& air, bool with_eye, const mesh_motion::Problem* motion)
    : _folder(folder), _air(air), _motion(motion), _with_eye(with_eye),
      _centreline(*a.mesh.mesh, centreline_points(a)),
      _cornea(*a.mesh.mesh, with_eye ? corneal_section(a.mesh)
                                     : std::vector<std::array<double, 3>>{}),
      // The apex: the section's node on the axis (where the eye would be
      // without it), a node of the mesh wherever the mesh was moved to.
      _apex(*a.mesh.mesh, {with_eye ? _cornea.points().front()
                                    : std::array<double, 3>{0, a.eye.apex_y, 0}}),
      _fields(settings, folder, a.mesh, air, motion), _centreline_peak(std::size(centreline_distances), 0.0),
      _apex_max(-std::numeric_limits<double>::infinity())
{
  _centreline_csv = "t_ms";
  for (double d : centreline_distances)
    _centreline_csv += format(",u_%gmm_m_s", d);
  _centreline_csv += "\n";
  _table_csv = "t_ms,r_mm,p_mmHg\n";
}

AirOutput::Sample AirOutput::sample(double time)
{
  _air.update_fields();
  const auto u = _centreline.values(*_air.velocity);
  const double p_apex = _apex.values(*_air.pressure)[0][0] / mmHg;
  const double speed = max_speed(*_air.velocity);
  const auto p = _with_eye ? _cornea.values(*_air.pressure) : std::vector<std::array<double, 3>>{};
  const auto d = _with_eye && _motion ? _cornea.values(*_motion->d)
                                      : std::vector<std::array<double, 3>>(p.size(), {0, 0, 0});
  _centreline_csv += format("%.6g", time);
  for (std::size_t i = 0; i < u.size(); ++i)
  {
    _centreline_csv += format(",%.6g", -u[i][1]);
    _centreline_peak[i] = std::max(_centreline_peak[i], -u[i][1]);
  }
  _centreline_csv += "\n";
  const auto& section = _cornea.points();
  for (std::size_t i = 0; i < p.size(); ++i)
    _table_csv += format("%.6g,%.6g,%.6g\n", time,
                         std::hypot(section[i][0] + d[i][0], section[i][2] + d[i][2]),
                         p[i][0] / mmHg);
  if (_with_eye && p_apex > _apex_max)
    _apex_max = p_apex, _apex_max_time = time;
  _speed_max = std::max(_speed_max, speed);
  _fields.sample(time);
  return {p_apex, speed};
}

void AirOutput::write_tables() const
{
  _folder.write_text("centreline.csv", _centreline_csv);
  if (_with_eye)
    _folder.write_text("corneal_pressure.csv", _table_csv);
}

void AirOutput::summarise(nlohmann::json& summary) const
{
  for (std::size_t i = 0; i < _centreline_peak.size(); ++i)
    summary["centreline_peak_m_s"][format("%gmm", centreline_distances[i])] = _centreline_peak[i];
  summary["max_velocity_m_s"] = _speed_max;
  if (_with_eye)
  {
    summary["apex_pressure_max_mmHg"] = _apex_max;
    summary["apex_pressure_max_time_ms"] = _apex_max_time;
    summary["corneal_pressure_table"] = "corneal_pressure.csv";
  }
}

FlowOutput::FlowOutput(const AirBlockSettings& settings, io::RunFolder& folder,
                       const meshio::Tagged& mesh, air::Problem& air,
                       const mesh_motion::Problem* motion)
    : _folder(folder), _air(air), _fields(settings, folder, mesh, air, motion),
      _forces_csv("t_ms,fx_N,fy_N,fz_N\n")
{
  std::vector<std::int32_t> groups;
  for (auto& name : settings.air.force_on)
    groups.push_back(mesh.groups.surfaces.at(name));
  _forces = !groups.empty();
  if (_forces)
    _wall_dofs = air.wall_dofs(groups);
  _axisymmetric = settings.dimension == section::Dimension::axisymmetric;
}

void FlowOutput::measure()
{
  if (_forces)
  {
    _force = _air.force_on(_wall_dofs);
    if (_axisymmetric)
      // The forms are per radian and the radial components of a body of
      // revolution cancel: its resultant is 2 pi times the axial one.
      _force = {0.0, 2 * M_PI * _force[1], 0.0};
  }
}

FlowOutput::Sample FlowOutput::sample(double time)
{
  _air.update_fields();
  Sample s;
  s.force = _force;
  s.max_speed = max_speed(*_air.velocity);
  _forces_csv += format("%.8g,%.10g,%.10g,%.10g\n", time, s.force[0], s.force[1], s.force[2]);
  _speed_max = std::max(_speed_max, s.max_speed);
  _last = s;
  _fields.sample(time);
  return s;
}

void FlowOutput::write_tables() const { _folder.write_text("forces.csv", _forces_csv); }

void FlowOutput::summarise(nlohmann::json& summary) const
{
  summary["max_velocity_m_s"] = _speed_max;
  if (_forces)
    summary["force_N"] = {_last.force[0], _last.force[1], _last.force[2]};
}

AirRecord::AirRecord(const AirBlockSettings& settings, io::RunFolder& folder, const AirMesh& mesh,
                     air::Problem& air, bool eye, bool with_eye,
                     const mesh_motion::Problem* motion)
{
  if (eye)
    _eye.emplace(settings, folder, mesh, air, with_eye, motion);
  else
    _flow.emplace(settings, folder, mesh.mesh, air, motion);
}

void AirRecord::measure()
{
  if (_flow)
    _flow->measure();
}

AirRecord::Sample AirRecord::sample(double time)
{
  Sample p;
  if (_eye)
  {
    const auto e = _eye->sample(time);
    p.apex_pressure = e.apex_pressure, p.max_speed = e.max_speed;
  }
  else
  {
    const auto f = _flow->sample(time);
    p.force = f.force, p.max_speed = f.max_speed;
  }
  return p;
}

void AirRecord::write_tables() const
{
  if (_eye)
    _eye->write_tables();
  else
    _flow->write_tables();
}

void AirRecord::summarise(nlohmann::json& summary) const
{
  if (_eye)
    _eye->summarise(summary);
  else
    _flow->summarise(summary);
}

nlohmann::json AirOutput::state() const
{
  return {{"fields", _fields.state()},       {"centreline_csv", _centreline_csv},
          {"table_csv", _table_csv},         {"centreline_peak", _centreline_peak},
          {"apex_max", _apex_max},           {"apex_max_time", _apex_max_time},
          {"speed_max", _speed_max}};
}

void AirOutput::restore(const nlohmann::json& j)
{
  _fields.restore(j.at("fields"));
  _centreline_csv = j.at("centreline_csv");
  _table_csv = j.at("table_csv");
  j.at("centreline_peak").get_to(_centreline_peak);
  _apex_max = j.at("apex_max"), _apex_max_time = j.at("apex_max_time");
  _speed_max = j.at("speed_max");
}

nlohmann::json FlowOutput::state() const
{
  return {{"fields", _fields.state()}, {"forces_csv", _forces_csv},
          {"last_force", _last.force}, {"last_speed", _last.max_speed},
          {"force", _force},           {"speed_max", _speed_max}};
}

void FlowOutput::restore(const nlohmann::json& j)
{
  _fields.restore(j.at("fields"));
  _forces_csv = j.at("forces_csv");
  j.at("last_force").get_to(_last.force);
  _last.max_speed = j.at("last_speed");
  j.at("force").get_to(_force);
  _speed_max = j.at("speed_max");
}

nlohmann::json AirRecord::state() const { return _eye ? _eye->state() : _flow->state(); }

void AirRecord::restore(const nlohmann::json& j)
{
  if (_eye)
    _eye->restore(j);
  else
    _flow->restore(j);
}

} // namespace nct
