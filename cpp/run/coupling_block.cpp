#include "run/coupling_block.h"

#include <algorithm>
#include <cmath>

#include "io/format.h"
#include "run/solid_block.h"

namespace nct
{

using io::format;

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
  return {[this](const dynamics::TimeStep& step)
          {
            _step = step;
            coupled.set_time_step(step, _air.settings.air.bdf_order);
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
            const double dt = _step.dt;
            coupled.advance();
            account(dt, power);
          },
          nullptr,
          [this] { return _solid.problem.local_error(); }};
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
  e.damping += dt * _step.damping * (e.last.kinetic + now.kinetic);
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
