#include "run/air_block.h"

#include <algorithm>
#include <cmath>

#include "air/inlet.h"
#include "io/format.h"

namespace nct
{
namespace
{

constexpr double mmHg = 1.333224e-4; // MPa
using io::format;

/// The inlet's shape across the section, at unit speed: the nozzle's bore
/// (uniform, or parabolic 1 - (r / bore radius)^2) on the eye; a file
/// mesh's inlet groups (inlet.*).
std::function<std::array<double, 3>(const std::array<double, 3>&)>
inlet_shape(const InletSettings& s, const std::vector<std::array<double, 4>>& table,
            const AirMesh& a, const air::Boundaries& b, bool eye)
{
  using P = InletSettings::Profile;
  if (eye)
  {
    const double bore = a.domain.nozzle_diameter / 2;
    if (s.profile == P::uniform)
      return [](const auto&) { return std::array<double, 3>{0, -1, 0}; };
    return [bore](const auto& x)
    {
      const double r2 = (x[0] * x[0] + x[2] * x[2]) / (bore * bore);
      return std::array<double, 3>{0, -std::max(0.0, 1 - r2), 0};
    };
  }
  air::Inlet in;
  auto unit = [](std::array<double, 3> v)
  {
    const double n = std::hypot(v[0], v[1], v[2]);
    return std::array<double, 3>{v[0] / n, v[1] / n, v[2] / n};
  };
  if (!s.direction.empty())
    in.direction = unit(s.direction.at(0));
  else
  {
    auto n = meshio::outward_normal(*a.mesh.mesh, *a.mesh.facets, b.inlet);
    in.direction = unit({-n[0], -n[1], -n[2]});
  }
  in.speed = 1;
  in.ramp_time = s.ramp_time;
  if (s.profile == P::table)
  {
    in.profile = air::Inlet::Profile::table;
    in.points = table;
  }
  else if (s.profile == P::parabolic)
  {
    in.center = s.center.at(0);
    if (s.circle)
    {
      in.profile = air::Inlet::Profile::circle;
      in.radius = s.radius;
    }
    else
    {
      in.profile = air::Inlet::Profile::rectangle;
      in.axes = {unit(s.axes[0]), unit(s.axes[1])};
      in.half_widths = {s.half_width_1, s.half_width_2};
    }
  }
  return [in](const auto& x) { return in.velocity(x); };
}

/// The inlet's speed [mm/ms] at time t: on the eye, the puff's Gaussian in
/// time or the square root of the measured pulse's shape (inlet.history);
/// on a file mesh, inlet.velocity ramped over inlet.ramp_time.
std::function<double(double)> inlet_speed(const AirBlockSettings& s, bool eye)
{
  const InletSettings& in = s.air.inlet;
  if (!eye)
  {
    // The profile holds the speeds (a table's, or the unit shape times inlet.velocity).
    air::Inlet ramp;
    ramp.ramp_time = in.ramp_time;
    const double U = in.profile == InletSettings::Profile::table ? 1.0 : in.velocity;
    return [=](double t) { return U * ramp.ramp(t); };
  }
  const double U = in.velocity;
  if (in.pulse)
    return [U, shape = *s.pulse](double t) { return U * std::sqrt(shape(t)); };
  const double peak_time = s.peak_time, width_t = s.width_t;
  return [=](double t)
  { return U * std::exp(-(t - peak_time) * (t - peak_time) / (2 * width_t * width_t)); };
}

} // namespace

AirBlock::AirBlock(AirMesh air_mesh, AirBlockSettings s, const air::Fluid& fluid,
                   const air::Boundaries& boundaries, double velocity_scale,
                   std::shared_ptr<dolfinx::fem::Function<double>> motion, bool is_eye,
                   bool eye_in_air)
    : mesh(std::move(air_mesh)), settings(std::move(s)),
      problem(mesh.mesh, fluid, boundaries, velocity_scale, std::move(motion),
              settings.dimension),
      eye(is_eye), with_eye(eye_in_air), _inlet(inlet_speed(settings, is_eye))
{
  problem.set_inlet(inlet_shape(settings.air.inlet, settings.inlet_table, mesh, boundaries,
                                is_eye));
}

void AirBlock::describe(nlohmann::json& summary, io::RunFolder& folder) const
{
  const auto& topology = mesh.mesh.mesh->topology();
  const std::int64_t cells = topology.index_map(topology.dim())->size_global();
  const bool alone = !summary.contains("dofs");
  summary[alone ? "cells" : "air_cells"] = cells;
  summary[alone ? "dofs" : "air_dofs"] = problem.dofs();
  if (eye)
  {
    const double U = settings.air.inlet.velocity, rho = settings.air.fluid.density;
    summary["stagnation_pressure_mmHg"] = 0.5 * rho * U * U / mmHg;
    if (!problem.moving())
      summary["air_eye"] = settings.air.rigid_eye ? "rigid" : "none";
  }
  folder.log(format("air mesh: %lld %s (%lld air, %lld eye in the gmsh model), P1/P1, "
                    "%lld dofs",
                    (long long)cells, topology.dim() == 3 ? "tetrahedra" : "triangles", (long long)mesh.air_cells, (long long)mesh.eye_cells,
                    (long long)problem.dofs()));
}

std::string AirBlock::identity() const
{
  return problem.forms_signature() + "; " + io::mesh_fingerprint(*mesh.mesh.mesh);
}

Stepper::Dynamics AirBlock::dynamics()
{
  const int order = settings.air.bdf_order;
  return {[this, order](const dynamics::TimeStep& step) { problem.set_time_step(step.dt, order); }, [] { return 1.0; },
          [this]
          {
            _record->measure();
            problem.advance();
          }};
}

solver::System AirBlock::system()
{
  return {problem.up->x().get(), &_no_border, [this](auto& b, auto&) { problem.residual(b); },
          [this](Mat J) { problem.jacobian(J); }, nullptr, nullptr, nullptr};
}

void AirBlock::set_fieldsplit(KSP ksp) const
{
  PC pc;
  KSPGetPC(ksp, &pc);
  const auto& map = *problem.up->function_space()->dofmap()->index_map;
  const std::int64_t first = map.local_range()[0];
  for (auto [name, dofs] : {std::pair{"u", &problem.velocity_dofs()},
                            std::pair{"p", &problem.pressure_dofs()}})
  {
    std::vector<PetscInt> rows;
    for (auto d : *dofs)
      if (d < map.size_local())
        rows.push_back(static_cast<PetscInt>(first + d));
    std::sort(rows.begin(), rows.end());
    IS is;
    ISCreateGeneral(map.comm(), static_cast<PetscInt>(rows.size()), rows.data(),
                    PETSC_COPY_VALUES, &is);
    PCFieldSplitSetIS(pc, name, is);
    ISDestroy(&is);
  }
}

void AirBlock::open_record(io::RunFolder& folder, const mesh_motion::Problem* motion)
{
  if (_record)
    return;
  _folder = &folder;
  _record.emplace(settings, folder, mesh, problem, eye, with_eye, motion);
  _t_step = MPI_Wtime();
  if (!_resumed.is_null())
  {
    _record->restore(_resumed.at("record"));
    _steps_csv = _resumed.at("steps_csv");
    _resumed = nullptr;
  }
}

void AirBlock::record_step(nlohmann::json& step, std::string& text, double time, double dt,
                           const solver::NewtonReport& report)
{
  const double wall = MPI_Wtime() - _t_step;
  _t_step = MPI_Wtime();
  const auto p = _record->sample(time);
  if (_steps_csv.empty())
    _steps_csv = "t_ms,dt_ms,newton_iterations,residual_N,inlet_velocity_m_s,"
                 "apex_pressure_mmHg,max_velocity_m_s,fx_N,fy_N,fz_N,wall_s\n";
  _steps_csv += format("%.6g,%.6g,%d,%.6e,%.6g,%.6g,%.6g,%.10g,%.10g,%.10g,%.3f\n", time, dt,
                       report.iterations, report.residuals.back(), inlet(time), p.apex_pressure,
                       p.max_speed, p.force[0], p.force[1], p.force[2], wall);
  step["inlet_velocity_m_s"] = inlet(time);
  step["max_air_velocity_m_s"] = p.max_speed;
  if (eye)
  {
    step["apex_air_pressure_mmHg"] = p.apex_pressure;
    text += format("  inlet %6.2f m/s  apex %7.3f mmHg  max |u| %6.2f m/s", inlet(time),
                   p.apex_pressure, p.max_speed);
  }
  else
  {
    step["air_force_N"] = {p.force[0], p.force[1], p.force[2]};
    text += format("  inlet %6.2f m/s  force %+.6e %+.6e %+.6e N  max |u| %6.2f m/s",
                   inlet(time), p.force[0], p.force[1], p.force[2], p.max_speed);
  }
}

void AirBlock::write_tables() const
{
  if (!_record)
    return;
  if (!_steps_csv.empty())
    _folder->write_text("steps.csv", _steps_csv);
  _record->write_tables();
}

void AirBlock::summarise_record(nlohmann::json& summary, io::RunFolder& folder) const
{
  const bool alone = !problem.moving() && eye;
  nlohmann::json air_summary;
  _record->summarise(alone ? summary : air_summary);
  if (!alone)
  {
    summary["air"] = air_summary;
    return;
  }
  const AirOutput& out = *_record->eye();
  if (with_eye)
    folder.log(format("apex pressure: max %.3f mmHg at %.3f ms (stagnation 0.5 rho U^2 = "
                      "%.3f mmHg)",
                      out.apex_max(), out.apex_max_time(),
                      summary["stagnation_pressure_mmHg"].get<double>()));
  std::string peaks = "centreline peaks:";
  for (auto& [d, v] : summary["centreline_peak_m_s"].items())
    peaks += format(" %s %.2f m/s;", d.c_str(), v.get<double>());
  folder.log(peaks);
}

nlohmann::json AirBlock::save(io::CheckpointWriter& writer) const
{
  nlohmann::json state{{"record", _record ? _record->state() : nlohmann::json()},
                       {"steps_csv", _steps_csv}};
  if (!problem.moving()) // moving, the coupling saves it
    state["problem"] = problem.save(writer);
  return state;
}

void AirBlock::restore(const io::CheckpointReader& checkpoint, const nlohmann::json& state,
                       io::RunFolder&)
{
  if (!problem.moving())
    problem.restore(checkpoint, state.at("problem"));
  if (!state.at("record").is_null())
    _resumed = state;
}

} // namespace nct
