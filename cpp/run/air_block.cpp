#include "run/air_block.h"

#include <algorithm>
#include <cmath>

#include "air/inlet.h"
#include "io/format.h"
#include "run/solid_block.h"

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
  return {[this, order](double dt) { problem.set_time_step(dt, order); }, [] { return 1.0; },
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

// The coupling.

CouplingBlock::CouplingBlock(SolidBlock& solid, AirBlock& air, MeshMotionBlock& motion,
                             const fsi::Interface& interface, const FsiSettings& s)
    : settings(s),
      coupled(solid.problem, air.problem, motion.problem, solid.mesh.mesh, air.mesh.mesh,
              interface, s.shape_derivative, solid.humor->joined()),
      _solid(solid), _air(air)
{
}

void CouplingBlock::describe(nlohmann::json& summary, io::RunFolder& folder) const
{
  const std::int64_t dofs = coupled.unknowns().size_global();
  summary["coupled_dofs"] = dofs;
  summary["interface_nodes"] = coupled.interface_nodes();
  folder.log(format("coupled: %lld dofs, %zu interface nodes", (long long)dofs,
                    coupled.interface_nodes()));
}

void CouplingBlock::set_solver_options() const
{
  // MUMPS LU on the whole; or FGMRES preconditioned by block Gauss-Seidel
  // over the solid and the air with its mesh motion, each block by MUMPS
  // LU; under the prefix "fsi_" unless given (e.g. by --petsc).
  std::vector<std::pair<std::string, std::string>> options;
  if (!settings.fieldsplit)
    options = {{"ksp_type", "preonly"},
               {"pc_type", "lu"},
               {"pc_factor_mat_solver_type", "mumps"},
               {"mat_mumps_icntl_7", "4"}};
  else
  {
    options = {{"ksp_type", "fgmres"},       {"ksp_rtol", "1e-10"},
               {"ksp_atol", "1e-14"},        {"ksp_max_it", "200"},
               {"ksp_gmres_restart", "200"}, {"pc_type", "fieldsplit"},
               {"pc_fieldsplit_type", "multiplicative"}};
    for (const char* split : {"solid", "air"})
      for (auto [key, value] :
           {std::pair{"ksp_type", "preonly"}, std::pair{"pc_type", "lu"},
            std::pair{"pc_factor_mat_solver_type", "mumps"}, std::pair{"mat_mumps_icntl_7", "4"}})
        options.push_back({std::string("fieldsplit_") + split + "_" + key, value});
  }
  for (auto& [key, value] : options)
  {
    const std::string name = "-fsi_" + key;
    PetscBool given = PETSC_FALSE;
    PetscOptionsHasName(nullptr, nullptr, name.c_str(), &given);
    if (!given)
      PetscOptionsSetValue(nullptr, name.c_str(), value.c_str());
  }
}

void CouplingBlock::set_fieldsplit(KSP ksp)
{
  // The solid's rows, and the air's with the mesh motion's.
  PC pc;
  KSPGetPC(ksp, &pc);
  PetscBool fieldsplit = PETSC_FALSE;
  PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCFIELDSPLIT, &fieldsplit);
  if (!fieldsplit)
    return;
  // The humors' flow, if any, with the solid.
  auto& unknowns = coupled.unknowns();
  IS solid = unknowns.index_set(0), air = unknowns.index_set(1), mesh = unknowns.index_set(2),
     air_and_mesh;
  ISExpand(air, mesh, &air_and_mesh);
  if (unknowns.fields() > 3)
  {
    IS humor = unknowns.index_set(3), solid_only = solid;
    ISExpand(solid_only, humor, &solid);
    ISDestroy(&humor);
    ISDestroy(&solid_only);
  }
  PCFieldSplitSetIS(pc, "solid", solid);
  PCFieldSplitSetIS(pc, "air", air_and_mesh);
  for (IS* is : {&solid, &air, &mesh, &air_and_mesh})
    ISDestroy(is);
}

Stepper::Dynamics CouplingBlock::dynamics()
{
  const double symmetry = _solid.problem.symmetry_factor();
  return {[this](double dt)
          {
            _step = dt;
            coupled.set_time_step(_solid.settings.time_step.with_dt(dt),
                                  _air.settings.air.bdf_order);
          },
          [] { return 1.0; }, // the air balances at t_{n+1}, where its inlet is set
          [this, symmetry]
          {
            _power = coupled.power();
            _jacobian = _air.problem.smallest_mesh_jacobian().first;
            _air.record().measure();
            if (_air.eye)
              _force = -symmetry * _air.problem.interface_force()[1]; // along -y, into the eye
            const double power = symmetry * _air.problem.traction_power();
            const double dt = _step;
            coupled.advance();
            account(dt, power);
          }};
}

biomarkers::Columns CouplingBlock::sample(double t, std::string& text)
{
  biomarkers::Columns c;
  const auto p = _air.record().sample(t);
  if (_air.eye)
  {
    c = {{"apex_air_pressure_mmHg", p.apex_pressure},
         {"max_air_velocity_m_s", p.max_speed},
         {"air_force_N", _force}};
    text += format("  air apex %.3f mmHg  |u| %.1f m/s", p.apex_pressure, p.max_speed);
  }
  else
  {
    c = {{"max_air_velocity_m_s", p.max_speed},
         {"air_force_x_N", p.force[0]},
         {"air_force_y_N", p.force[1]},
         {"air_force_z_N", p.force[2]}};
    text += format("  air |u| %.4g m/s  force %+.6e %+.6e %+.6e N", p.max_speed, p.force[0],
                   p.force[1], p.force[2]);
  }
  c.insert(c.end(), {{"air_mesh_jacobian_min", _jacobian},
                     {"interface_power_air_W", _power.air},
                     {"interface_power_solid_W", _power.solid}});
  text += format("  mesh J %.3f  power %.4e/%.4e W", _jacobian, _power.air, _power.solid);
  _worst_jacobian = std::min(_worst_jacobian, _jacobian);
  _worst_power = std::max(_worst_power, std::abs(_power.air - _power.solid));
  _largest_power = std::max({_largest_power, std::abs(_power.air), std::abs(_power.solid)});
  return c;
}

biomarkers::Columns CouplingBlock::at_rest()
{
  return {{"apex_air_pressure_mmHg", 0.0}, {"max_air_velocity_m_s", 0.0},
          {"air_force_N", 0.0},            {"air_mesh_jacobian_min", 1.0},
          {"interface_power_air_W", 0.0},  {"interface_power_solid_W", 0.0}};
}

double CouplingBlock::symmetry() const { return _solid.problem.symmetry_factor(); }

CouplingBlock::Energy::State CouplingBlock::energy_state() const
{
  const auto& solid = _solid.problem;
  const double kinetic = solid.kinetic_energy();
  // The humors' kinetic energy is the work their inertial pressure took
  // (translating), or from their Euler velocity (flowing).
  const double humor_kinetic = _solid.humor->kinetic_energy() * solid.symmetry_factor();
  return {kinetic, kinetic + humor_kinetic + solid.strain_energy(), solid.cavity_volumes(),
          _solid.cavity_pressures()};
}

void CouplingBlock::start_energy()
{
  _energy.last = energy_state();
  _energy.start = _energy.last.total;
  _energy.power = symmetry() * _air.problem.traction_power();
}

void CouplingBlock::account(double dt, double power)
{
  auto& e = _energy;
  const Energy::State now = energy_state();
  const double reaction_power = symmetry() * _power.solid;
  e.traction += 0.5 * dt * (e.power + power);
  e.reaction += 0.5 * dt * (e.reaction_power + reaction_power);
  e.damping += dt * _solid.settings.time_step.damping * (e.last.kinetic + now.kinetic);
  for (std::size_t c = 0; c < now.volumes.size(); ++c)
    e.cavities += 0.5 * (e.last.pressures[c] + now.pressures[c])
                  * (now.volumes[c] - e.last.volumes[c]);
  e.change = now.total - e.start;
  e.power = power, e.reaction_power = reaction_power, e.last = now;
}

void CouplingBlock::summarise(nlohmann::json& summary) const
{
  const auto& e = _energy;
  const double solid = e.change + e.damping - e.cavities; // the work the solid took
  auto mismatch = [&](double work) { return std::abs(work - solid) / std::abs(solid); };
  summary["energy_balance"] = {{"solid_energy_change_mJ", e.change},
                               {"damping_dissipation_mJ", e.damping},
                               {"cavity_work_mJ", e.cavities},
                               {"air_traction_work_mJ", e.traction},
                               {"reaction_work_mJ", e.reaction},
                               {"traction_mismatch_relative", mismatch(e.traction)},
                               {"reaction_mismatch_relative", mismatch(e.reaction)}};
  summary["coupled_timings_s"] = coupled.timings();
  summary["air_mesh_jacobian_min"] = _worst_jacobian;
  summary["interface_power_mismatch_max_W"] = _worst_power;
  summary["interface_power_max_W"] = _largest_power;
}

nlohmann::json CouplingBlock::save(io::CheckpointWriter& writer) const
{
  if (!coupled.started())
    return nullptr;
  const auto& e = _energy;
  return {{"coupled", coupled.save(writer)},
          {"energy",
           {e.traction, e.reaction, e.change, e.damping, e.cavities, e.start, e.power,
            e.reaction_power, e.last.kinetic, e.last.total, e.last.volumes, e.last.pressures}},
          {"worst_jacobian", _worst_jacobian},
          {"worst_power", _worst_power},
          {"largest_power", _largest_power}};
}

void CouplingBlock::restore(const io::CheckpointReader& checkpoint, const nlohmann::json& state,
                            io::RunFolder&)
{
  if (state.is_null())
    return;
  coupled.restore(checkpoint, state.at("coupled"));
  const auto& e = state.at("energy");
  _energy = {e[0], e[1], e[2], e[3], e[4], e[5], e[6], e[7],
             {e[8], e[9], e[10].get<std::vector<double>>(), e[11].get<std::vector<double>>()}};
  _worst_jacobian = state.at("worst_jacobian");
  _worst_power = state.at("worst_power");
  _largest_power = state.at("largest_power");
}

} // namespace nct
