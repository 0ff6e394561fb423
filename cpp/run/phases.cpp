// The phases of a run (design.md sections 6-9): zero pressure, inflate,
// close, press, rest, and the puff: prescribed on the solid, the air
// alone about a rigid eye, or the air and the eye coupled.
#include <cmath>
#include <limits>
#include <utility>

#include <dolfinx/io/XDMFFile.h>
#include <petscksp.h>

#include "air/inlet.h"
#include "io/format.h"
#include "run/air_output.h"
#include "run/run.h"
#include "run/timeline.h"
#include "zero_pressure/zero_pressure.h"

namespace nct
{
namespace
{

constexpr double mmHg = 1.333224e-4; // MPa
using io::format;

/// Each cavity's volume of the current geometry at u = 0, under `label`.
void report_volumes(RunState& s, const std::string& label)
{
  auto volumes = s.model.problem->cavity_volumes();
  for (std::size_t c = 0; c < volumes.size(); ++c)
    s.summary[s.model.setup.cavity_names[c] + "_volume_" + label + "_mm3"] = volumes[c];
}

/// Write the mesh with the node coordinates `x` (geometry layout) to name.xdmf.
void write_geometry(const io::RunFolder& folder, const dolfinx::mesh::Mesh& mesh,
                    const std::vector<double>& x, const std::string& name)
{
  zero_pressure::SwappedGeometry swapped(mesh, x);
  dolfinx::io::XDMFFile file(mesh.comm(), folder.dir() / (name + ".xdmf"), "w");
  file.write_mesh(mesh);
}

/// The puff's biomarkers (design.md sections 9-10) into the summary.
void summarise_puff(RunState& s)
{
  const auto& frames = *s.frames;
  nlohmann::json& summary = s.summary;
  const auto r = frames.analyse(s.scene.real("puff.apex_window"),
                                s.scene.real("puff.radius_window"), s.scene.real("puff.flatness"));
  summary["frames"] = frames.frames();
  summary["hc_time_ms"] = r.hc_time;
  summary["deformation_amplitude_mm"] = r.deformation_amplitude;
  summary["deflection_amplitude_mm"] = r.deflection_amplitude;
  summary["whole_eye_motion_hc_mm"] = r.deflection_amplitude - r.deformation_amplitude;
  summary["peak_distance_mm"] = r.peak_distance;
  if (r.hc_radius)
    summary["hc_radius_mm"] = *r.hc_radius;
  summary["max_inverse_radius_per_mm"] = r.max_inverse_radius;
  summary["whole_eye_movement_max_mm"] = r.whole_eye_movement_max;
  if (r.whole_eye_movement_time)
    summary["whole_eye_movement_time_ms"] = *r.whole_eye_movement_time;
  if (r.applanated)
  {
    for (auto [name, a] : {std::pair{"a1", &r.a1}, {"a2", &r.a2}})
    {
      summary[std::string(name) + "_time_ms"] = a->time;
      summary[std::string(name) + "_length_mm"] = a->length;
      summary[std::string(name) + "_velocity_m_s"] = a->apex_velocity;
      summary[std::string(name) + "_deflection_mm"] = a->deflection;
    }
    summary["a1_a2_interval_ms"] = r.a1_a2_interval();
    summary["a1_hc_interval_ms"] = r.a1_hc_interval();
    summary["integrated_inverse_radius_ms_per_mm"] = *r.integrated_inverse_radius;
  }
  for (auto [key, ratio] :
       {std::pair{"da_ratio_1mm", &r.da_ratio_1mm}, {"da_ratio_2mm", &r.da_ratio_2mm}})
    if (*ratio)
      summary[key] = **ratio;
  summary["apex_pressure_hc_mmHg"] = frames.at("apex_air_pressure_mmHg", r.hc_time);
  summary["apex_pressure_max_mmHg"] = frames.max("apex_air_pressure_mmHg");
  const auto& cavities = s.model.setup.cavity_names;
  std::optional<double> sp_a1;
  if (!cavities.empty())
  {
    summary["iop_max_mmHg"] = frames.max(cavities[0] + "_pressure_mmHg");
    summary["iop_hc_mmHg"] = frames.at(cavities[0] + "_pressure_mmHg", r.hc_time);
    if (r.applanated)
      sp_a1 = biomarkers::stiffness_parameter_a1(
          frames.at("apex_air_pressure_mmHg", r.a1.time),
          frames.at(cavities[0] + "_pressure_mmHg", 0.0), r.a1.deflection);
  }
  if (sp_a1)
    summary["sp_a1_mmHg_per_mm"] = *sp_a1;
  std::string text = format("biomarkers: HC %.3f ms, deformation %.4f mm, deflection %.4f "
                            "mm, peak distance %.3f mm, whole eye %.4f mm",
                            r.hc_time, r.deformation_amplitude, r.deflection_amplitude,
                            r.peak_distance, r.whole_eye_movement_max);
  if (r.hc_radius)
    text += format(", HC radius %.3f mm", *r.hc_radius);
  if (r.applanated)
    text += format("; A1 %.3f ms %.3f mm %+.3f m/s; A2 %.3f ms %.3f mm %+.3f m/s; "
                   "A1 deflection %.4f mm; integrated 1/R %.3f ms/mm",
                   r.a1.time, r.a1.length, r.a1.apex_velocity, r.a2.time, r.a2.length,
                   r.a2.apex_velocity, r.a1.deflection, *r.integrated_inverse_radius);
  else
    text += "; the cornea did not applanate twice (no A1/A2)";
  if (r.da_ratio_2mm)
    text += format("; DA ratio 2 mm %.3f", *r.da_ratio_2mm);
  if (sp_a1)
    text += format("; SP-A1 %.1f mmHg/mm", *sp_a1);
  s.folder.log(text);
}

/// The inlet's speed [mm/ms] at time t: on the eye, the puff's Gaussian in
/// time or the square root of the measured pulse's shape (air.inlet_history);
/// on a file mesh, inlet.velocity ramped over inlet.ramp_time.
std::function<double(double)> inlet_velocity(const scene::Scene& s)
{
  if (s.string("mesh.source") == "file")
  {
    // The profile holds the speeds (a table's, or the unit shape times inlet.velocity).
    air::Inlet ramp;
    ramp.ramp_time = s.real("inlet.ramp_time");
    const double U = s.string("inlet.profile") == "table" ? 1.0 : s.real("inlet.velocity");
    return [=](double t) { return U * ramp.ramp(t); };
  }
  const double U = s.real("air.inlet_velocity");
  if (s.string("air.inlet_history") == "pulse")
    return [U, shape = pulse_shape(s)](double t) { return U * std::sqrt(shape(t)); };
  const double peak_time = s.real("puff.peak_time"), width_t = s.real("puff.width_t");
  return [=](double t)
  { return U * std::exp(-(t - peak_time) * (t - peak_time) / (2 * width_t * width_t)); };
}

/// The coupled system's linear solver (fsi.linear_solver), as PETSc
/// options under the prefix "fsi_" unless given (e.g. by --petsc): MUMPS
/// LU on the whole; or FGMRES preconditioned by block Gauss-Seidel over
/// the solid and the air with its mesh motion, each block by MUMPS LU.
void set_coupled_solver_options(const scene::Scene& s)
{
  std::vector<std::pair<std::string, std::string>> options;
  if (s.string("fsi.linear_solver") == "lu")
    options = {{"ksp_type", "preonly"},
               {"pc_type", "lu"},
               {"pc_factor_mat_solver_type", "mumps"},
               {"mat_mumps_icntl_7", "4"}};
  else
  {
    options = {{"ksp_type", "fgmres"},     {"ksp_rtol", "1e-10"},
               {"ksp_atol", "1e-14"},      {"ksp_max_it", "200"},
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

/// The coupled system's fieldsplit blocks: the solid's rows, and the air's
/// with the mesh motion's.
void set_coupled_fieldsplit(KSP ksp, const solver::Monolithic& unknowns)
{
  PC pc;
  KSPGetPC(ksp, &pc);
  PetscBool fieldsplit = PETSC_FALSE;
  PetscObjectTypeCompare(reinterpret_cast<PetscObject>(pc), PCFIELDSPLIT, &fieldsplit);
  if (!fieldsplit)
    return;
  IS solid = unknowns.index_set(0), air = unknowns.index_set(1), mesh = unknowns.index_set(2),
     air_and_mesh;
  ISExpand(air, mesh, &air_and_mesh);
  PCFieldSplitSetIS(pc, "solid", solid);
  PCFieldSplitSetIS(pc, "air", air_and_mesh);
  for (IS* is : {&solid, &air, &mesh, &air_and_mesh})
    ISDestroy(is);
}

/// The solid's time integration for the Stepper.
Stepper::Dynamics solid_dynamics(RunState& s)
{
  auto& problem = *s.model.problem;
  const double rho_inf = s.scene.real("dynamics.rho_inf"), damping = s.scene.real("dynamics.damping");
  return {[&problem, rho_inf, damping](double dt) { problem.set_time_step({dt, rho_inf, damping}); },
          [&problem] { return problem.load_level(); }, [&problem] { problem.advance(); },
          [&problem] { problem.predict(); }};
}

/// Phase 1 (zero_pressure.enabled): the mesh is the eye imaged at the
/// IOP; find the stress-free geometry whose inflation gives it back.
class ZeroPressure : public Phase
{
public:
  const char* name() const override { return "zero_pressure"; }
  void run(RunState& s) override
  {
    auto& problem = *s.model.problem;
    auto& mesh = *s.model.setup.mesh.mesh;
    s.x_imaged.assign(mesh.geometry().x().begin(), mesh.geometry().x().end());
    report_volumes(s, "imaged");
    const zero_pressure::Settings zp{s.scene.real("zero_pressure.tolerance"),
                                     s.scene.integer("zero_pressure.max_iterations"),
                                     s.scene.string("zero_pressure.acceleration") == "aitken"};
    const double t = MPI_Wtime();
    // Newton solves the pressurised shapes to a hundredth of the geometric
    // tolerance (the increment test, mm): what the fixed point needs of
    // them, where the residual test alone would ask for 1e-9 N at each.
    solver::NewtonSettings settings = s.settings;
    settings.increment_tol = 0.01 * zp.tolerance;
    Stepper stepper = make_stepper(s.scene, settings, s.folder);
    auto& newton = s.solid_newton();
    const std::size_t n_cavities = problem.cavities();
    const double iop = s.scene.real("inflate.iop") * mmHg;
    bool first = true;
    // Inflate the current geometry to the IOP: one Newton solve from the
    // last solution (the geometry moved little, and a kept factorisation
    // of the last geometry's Jacobian serves), else a ramp from rest.
    auto pressurise = [&]
    {
      if (!first)
      {
        auto report = newton.solve(s.open->system(), settings);
        stepper.newton_iterations += report.iterations;
        if (report.converged)
          return;
        s.folder.log(format("  zero-pressure: Newton from the last solution failed (%s); "
                            "inflating from rest",
                            report.reason.c_str()));
      }
      first = false;
      problem.u->x()->set(0.0);
      stepper.ramp(newton, "zero-pressure inflation", s.scene.integer("inflate.steps"),
                   s.open->system(),
                   [&](double f)
                   { problem.set_cavity_pressures(std::vector<double>(n_cavities, f * iop)); },
                   [](double, const auto&) {});
    };
    nlohmann::json& its = s.summary["zero_pressure_history"] = nlohmann::json::array();
    auto report = zero_pressure::solve(
        problem, zp, pressurise,
        [&](int k, const zero_pressure::Iteration& it)
        {
          its.push_back(
              {{"residual_max_mm", it.max}, {"residual_rms_mm", it.rms}, {"omega", it.omega}});
          s.folder.log(format("zero-pressure %2d  residual max %.3e mm  rms %.3e mm  "
                              "omega %.3f  wall %.2f s",
                              k, it.max, it.rms, it.omega, it.wall));
        });
    const auto& last = report.iterations.back();
    s.summary["zero_pressure_iterations"] = report.iterations.size();
    s.summary["zero_pressure_residual_max_mm"] = last.max;
    s.summary["zero_pressure_residual_rms_mm"] = last.rms;
    s.summary["zero_pressure_newton_iterations"] = stepper.newton_iterations;
    s.stepper.newton_iterations += stepper.newton_iterations;
    s.stepper.cuts += stepper.cuts;
    s.summary["zero_pressure_wall_s"] = MPI_Wtime() - t;
    if (!report.converged)
      throw Diverged(format("zero-pressure geometry: no convergence in %d iterations "
                            "(zero_pressure.max_iterations); the last residual is "
                            "%.3e mm (max), %.3e mm (rms) against a tolerance of %.3e mm",
                            zp.max_iterations, last.max, last.rms, zp.tolerance));
    s.probes = zero_pressure::carry(mesh, s.x_imaged, s.model.setup.probes);
    // The last pressurised state is the inflated stress-free geometry: the
    // inflate phase may start from it (with the kept factorisation).
    if (s.scene.string("zero_pressure.round_trip") == "reuse")
    {
      const auto u = problem.u->x()->array();
      s.zero_pressure_inflated.assign(u.begin(), u.end());
    }
    else
      newton.reset();
    problem.u->x()->set(0.0);
    if (s.scene.boolean("output.fields"))
    {
      write_geometry(s.folder, mesh, s.x_imaged, "geometry_imaged");
      write_geometry(s.folder, mesh,
                     std::vector<double>(mesh.geometry().x().begin(), mesh.geometry().x().end()),
                     "geometry_stress_free");
    }
  }
};

/// Phase 2: the cavities inflated by a pressure ramp to the IOP; after
/// zero pressure, in one step from its last pressurised state.
class Inflate : public Phase
{
public:
  const char* name() const override { return "inflate"; }
  /// Zero pressure's last inflation of the stress-free geometry is this
  /// phase's end: one Newton solve from it at the run's tolerance (the
  /// ramp's states in between are not recomputed). False (state back at
  /// rest) if there is none or it does not converge.
  static bool inflate_from_zero_pressure(RunState& s, const std::function<void(double)>& load)
  {
    if (s.zero_pressure_inflated.empty())
      return false;
    auto& problem = *s.model.problem;
    auto u = problem.u->x()->mutable_array();
    std::copy(s.zero_pressure_inflated.begin(), s.zero_pressure_inflated.end(), u.begin());
    s.zero_pressure_inflated.clear();
    load(1.0);
    auto& newton = s.solid_newton();
    const auto report = newton.solve(s.open->system(), s.settings);
    s.stepper.newton_iterations += report.iterations;
    if (report.converged)
    {
      s.quasi_static_step("inflate", 1.0, report);
      return true;
    }
    s.folder.log(format("  inflate: Newton from zero pressure's last state failed (%s); "
                        "ramping from rest",
                        report.reason.c_str()));
    problem.u->x()->set(0.0);
    newton.reset();
    return false;
  }
  void run(RunState& s) override
  {
    auto& problem = *s.model.problem;
    const double iop = s.scene.real("inflate.iop") * mmHg;
    auto load = [&](double f)
    {
      s.open_pressures.assign(problem.cavities(), f * iop);
      problem.set_cavity_pressures(s.open_pressures);
    };
    s.output();
    if (!inflate_from_zero_pressure(s, load))
      s.stepper.ramp(s.solid_newton(), "inflate", s.scene.integer("inflate.steps"),
                     s.open->system(), load,
                     [&](double f, const auto& report) { s.quasi_static_step("inflate", f, report); });
    s.t0 += 1;
    if (s.x_imaged.empty())
      return;
    // The round trip: the inflated stress-free geometry against the imaged one.
    const auto [max, rms] = zero_pressure::mismatch(problem, s.x_imaged);
    s.summary["zero_pressure_round_trip_max_mm"] = max;
    s.summary["zero_pressure_round_trip_rms_mm"] = rms;
    s.folder.log(format("round trip: the inflated stress-free geometry is %.3e mm (max), "
                        "%.3e mm (rms) from the imaged one",
                        max, rms));
  }
};

/// Phase 3 (cavity.model = "closed"): each cavity keeps the volume it has now.
class Close : public Phase
{
public:
  const char* name() const override { return "close"; }
  void run(RunState& s) override
  {
    s.closed.emplace(*s.model.problem, s.open_pressures);
    std::string text;
    const auto& names = s.model.setup.cavity_names;
    for (std::size_t c = 0; c < names.size(); ++c)
    {
      s.summary[names[c] + "_volume_closed_mm3"] = s.closed->targets()[c];
      text += format("  %s %.4f mm3", names[c].c_str(), s.closed->targets()[c]);
    }
    s.folder.log("close: volumes held at" + text);
  }
};

/// Phase 4 (press.pressure != 0): a follower pressure ramped on the loaded surface.
class Press : public Phase
{
public:
  const char* name() const override { return "press"; }
  void run(RunState& s) override
  {
    auto& problem = *s.model.problem;
    s.output();
    problem.set_surface_profile(s.press_profile);
    s.stepper.ramp(
        s.solid_newton(), "press", s.scene.integer("press.steps"), s.solid_system(),
        [&](double f)
        {
          s.surface_pressure = f * s.press_peak;
          problem.set_surface_pressure(s.surface_pressure);
        },
        [&](double f, const auto& report) { s.quasi_static_step("press", f, report); });
    s.t0 += 1;
  }
};

/// Phase 5 (rest.duration > 0): dynamics from rest with the loads held;
/// the eye should not move.
class Rest : public Phase
{
public:
  const char* name() const override { return "rest"; }
  /// `columns`: the puff's state columns, at rest (the frames' columns
  /// are the same at every step).
  explicit Rest(biomarkers::Columns columns) : _columns(std::move(columns)) {}
  void run(RunState& s) override
  {
    const double rest = s.scene.real("rest.duration");
    s.start_dynamics();
    s.set_surface_load(-rest);
    if (!_resumed)
      _apex_rest = s.probes.empty() ? 0.0 : s.output().probe_displacement()[0][1];
    nlohmann::json keys{{"phase", "rest"}};
    if (_columns.empty())
      keys["apex_air_pressure_mmHg"] = 0.0;
    s.stepper.march(s.solid_newton(), "rest", -rest, rest, s.scene.real("dynamics.dt"),
                    solid_dynamics(s), s.solid_system(), [](double) {},
                    [&](double t, double dt, const auto& report)
                    {
                      _drift = std::max(_drift, std::abs(s.dynamic_step(keys, t, dt, report,
                                                                        _columns)
                                                         - _apex_rest));
                    });
    if (!s.probes.empty())
      s.summary["rest_drift_mm"] = _drift;
  }
  nlohmann::json save() const override { return {_apex_rest, _drift}; }
  void restore(const nlohmann::json& j) override
  {
    _apex_rest = j[0], _drift = j[1], _resumed = true;
  }

private:
  biomarkers::Columns _columns;
  double _apex_rest = 0, _drift = 0; ///< the apex at rest, its largest drift [mm]
  bool _resumed = false;
};

/// Phase 6, prescribed (puff.load = "gaussian", "pulse" or "table"): the air as a
/// follower pressure p(r, t) on the anterior cornea.
class PrescribedPuff : public Phase
{
public:
  const char* name() const override { return "puff"; }
  void run(RunState& s) override
  {
    s.start_dynamics();
    if (!s.model.eye)
      s.folder.log("puff: the biomarkers need the idealised eye's cornea; this file mesh "
                   "gets the puff's load and its steps, no frames");
    if (s.frames && s.frames->frames() == 0)
      s.add_frame(0, 0, solver::NewtonReport{true, 0, {0.0}, ""}, {});
    auto apex = [&](double t) { return (*s.prescribed)(0, t); };
    s.stepper.march(s.solid_newton(), "puff", 0, s.scene.real("puff.duration"),
                    s.scene.real("dynamics.dt"), solid_dynamics(s), s.solid_system(),
                    [&](double t) { s.set_surface_load(t); },
                    [&](double t, double dt, const auto& report) {
                      s.dynamic_step({{"phase", "puff"}, {"apex_air_pressure_mmHg", apex(t)}},
                                     t, dt, report);
                    });
    if (s.frames)
    {
      s.write_tables();
      summarise_puff(s);
    }
  }
};

/// Phase 6, the air alone (puff.load = "air"): the Corvis jet on a rigid
/// eye or a free jet, or a file mesh's fluid; no solid phase runs.
class AirPuff : public Phase
{
public:
  const char* name() const override { return "puff"; }
  void run(RunState& s) override
  {
    auto& air = *s.model.air;
    const bool file = !s.model.eye;
    const bool with_eye = !file && s.scene.string("air.eye") == "rigid";
    if (with_eye)
      s.folder.log("air: the eye is a rigid wall; the solid phases (zero pressure, inflation, "
                   "rest) are not run");
    AirRecord out(s.scene, s.folder, s.model, air, with_eye, nullptr);
    _out = &out;
    auto& newton = s.newton("air", [&] { return air.create_matrix(); });
    set_fieldsplit(newton.ksp(), air);
    // Full Newton steps: the energy line search has no energy to follow here.
    solver::NewtonSettings settings = s.settings;
    settings.line_search = false;
    Stepper stepper = make_stepper(s.scene, settings, s.folder);
    stepper.boundaries = s.stepper.boundaries;
    stepper.resume = std::exchange(s.stepper.resume, std::nullopt);
    _stepper = &stepper;
    const bool resumed = !_resumed.is_null();
    if (resumed)
    {
      out.restore(_resumed.at("record"));
      _steps = _resumed.at("steps");
      _steps_csv = _resumed.at("steps_csv");
      stepper.newton_iterations = _resumed.at("newton_iterations");
      stepper.cuts = _resumed.at("cuts");
    }
    std::vector<double> no_border;
    const solver::System system{air.up->x().get(), &no_border,
                                [&](auto& b, auto&) { air.residual(b); },
                                [&](Mat J) { air.jacobian(J); }, nullptr, nullptr, nullptr};
    const auto inlet = inlet_velocity(s.scene);
    try
    {
      // From rest, the inlet at its t = 0 value; resumed, at the checkpoint's.
      air.set_inlet_scale(inlet(resumed ? stepper.resume->t : 0));
      if (!resumed)
      {
        const auto first = out.sample(0);
        _steps_csv = "t_ms,dt_ms,newton_iterations,residual_N,inlet_velocity_m_s,"
                     "apex_pressure_mmHg,max_velocity_m_s,fx_N,fy_N,fz_N,wall_s\n"
                     + format("0,0,0,0,%.6g,%.6g,%.6g,0,0,0,0\n", inlet(0),
                              first.apex_pressure, first.max_speed);
      }
      const int order = s.scene.integer("air.bdf_order");
      const Stepper::Dynamics dynamics{[&](double dt) { air.set_time_step(dt, order); },
                                       [] { return 1.0; },
                                       [&]
                                       {
                                         out.measure();
                                         air.advance();
                                       }};
      double t_step = MPI_Wtime();
      stepper.march(newton, "air", 0, s.scene.real("puff.duration"), s.scene.real("air.dt"),
                    dynamics, system, [&](double time) { air.set_inlet_scale(inlet(time)); },
                    [&](double time, double dt, const solver::NewtonReport& report)
                    {
                      const double wall = MPI_Wtime() - t_step;
                      t_step = MPI_Wtime();
                      ++_steps;
                      const auto p = out.sample(time);
                      _steps_csv += format("%.6g,%.6g,%d,%.6e,%.6g,%.6g,%.6g,%.10g,%.10g,%.10g,"
                                          "%.3f\n",
                                          time, dt, report.iterations, report.residuals.back(),
                                          inlet(time), p.apex_pressure, p.max_speed, p.force[0],
                                          p.force[1], p.force[2], wall);
                      const std::string what
                          = file ? format("force %+.6e %+.6e %+.6e N", p.force[0], p.force[1],
                                          p.force[2])
                                 : format("apex %7.3f mmHg", p.apex_pressure);
                      s.folder.log(format("air t = %7.3f ms  dt %.3g  inlet %6.2f m/s  Newton "
                                          "%2d  residual %.2e N  %s  max |u| %6.2f m/s  wall "
                                          "%.2f s",
                                          time, dt, inlet(time), report.iterations,
                                          report.residuals.back(), what.c_str(), p.max_speed,
                                          wall));
                    });
    }
    catch (...)
    {
      finish(s, stepper);
      throw;
    }
    finish(s, stepper);
    s.folder.log(format("done: %d steps, %d Newton iterations, %d step cuts", _steps,
                        stepper.newton_iterations, stepper.cuts));
    if (file)
    {
      nlohmann::json air_summary;
      out.summarise(air_summary);
      s.summary["air"] = air_summary;
      return;
    }
    out.summarise(s.summary);
    const AirOutput& eye = *out.eye();
    if (with_eye)
      s.folder.log(format("apex pressure: max %.3f mmHg at %.3f ms (stagnation 0.5 rho U^2 = "
                          "%.3f mmHg)",
                          eye.apex_max(), eye.apex_max_time(),
                          s.summary["stagnation_pressure_mmHg"].get<double>()));
    std::string peaks = "centreline peaks:";
    for (auto& [d, v] : s.summary["centreline_peak_m_s"].items())
      peaks += format(" %s %.2f m/s;", d.c_str(), v.get<double>());
    s.folder.log(peaks);
  }
  nlohmann::json save() const override
  {
    return {{"record", _out->state()},
            {"steps", _steps},
            {"steps_csv", _steps_csv},
            {"newton_iterations", _stepper->newton_iterations},
            {"cuts", _stepper->cuts}};
  }
  void restore(const nlohmann::json& state) override { _resumed = state; }

private:
  /// The tables so far (whole files) and the stepper's counts.
  void finish(RunState& s, const Stepper& stepper)
  {
    s.summary["steps"] = _steps;
    s.stepper.newton_iterations += stepper.newton_iterations;
    s.stepper.cuts += stepper.cuts;
    s.folder.write_text("steps.csv", _steps_csv);
    _out->write_tables();
  }

  /// Velocity and pressure blocks for a fieldsplit preconditioner, as
  /// index sets of the owned global rows of (u, p).
  static void set_fieldsplit(KSP ksp, const air::Problem& problem)
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

  AirRecord* _out = nullptr;  ///< while run() marches
  Stepper* _stepper = nullptr; ///< its own (full Newton steps), while run() marches
  int _steps = 0;
  std::string _steps_csv; ///< steps.csv so far
  nlohmann::json _resumed; ///< a checkpoint's state of the phase, or null
};

/// Phase 6, coupled (puff.load = "fsi"): the air and the eye in one
/// Newton system per step (cpp/fsi), from the solid's state at the end of
/// the rest; the air starts at rest.
class CoupledPuff : public Phase
{
public:
  const char* name() const override { return "puff"; }
  void run(RunState& s) override
  {
    auto& m = s.model;
    auto& coupled = *m.coupled;
    auto& air = *m.air;
    s.start_dynamics();
    const bool resumed = !_resumed.is_null(); // RunState::resume restored the coupling
    if (!resumed)
      coupled.start();
    AirRecord out(s.scene, s.folder, m, air, true, m.motion.get());
    _out = &out;
    if (resumed)
    {
      out.restore(_resumed.at("record"));
      _worst_jacobian = _resumed.at("worst_jacobian");
      _worst_power = _resumed.at("worst_power");
      _largest_power = _resumed.at("largest_power");
    }
    const auto inlet = inlet_velocity(s.scene);
    auto& unknowns = coupled.unknowns();
    air.set_inlet_scale(inlet(resumed ? s.stepper.resume->t : 0));
    unknowns.pack();
    set_coupled_solver_options(s.scene);
    auto& newton = s.newton("coupled", [&] { return coupled.create_matrix(); }, "fsi_");
    set_coupled_fieldsplit(newton.ksp(), unknowns);
    const auto system = coupled.system(s.closed ? &*s.closed : nullptr);
    const double rho_inf = s.scene.real("dynamics.rho_inf"),
                 damping = s.scene.real("dynamics.damping");
    const int order = s.scene.integer("air.bdf_order");
    fsi::Power power;
    double jacobian = 1, force = 0;
    const int symmetry = m.problem->symmetry_factor();
    const Stepper::Dynamics dynamics{
        [&](double dt) { coupled.set_time_step(dt, rho_inf, damping, order); },
        [] { return 1.0; }, // the air balances at t_{n+1}, where its inlet is set
        [&]
        {
          power = coupled.power();
          jacobian = air.smallest_mesh_jacobian().first;
          out.measure();
          if (m.eye)
            force = -symmetry * air.interface_force()[1]; // along -y, into the eye
          coupled.advance();
        }};
    // The state's columns (collective) and its log line's text.
    std::string text;
    auto sample = [&](double t)
    {
      biomarkers::Columns c;
      const auto p = out.sample(t);
      if (m.eye)
      {
        c = {{"apex_air_pressure_mmHg", p.apex_pressure},
             {"max_air_velocity_m_s", p.max_speed},
             {"air_force_N", force}};
        text = format("  air apex %.3f mmHg  |u| %.1f m/s", p.apex_pressure, p.max_speed);
      }
      else
      {
        c = {{"max_air_velocity_m_s", p.max_speed},
             {"air_force_x_N", p.force[0]},
             {"air_force_y_N", p.force[1]},
             {"air_force_z_N", p.force[2]}};
        text = format("  air |u| %.4g m/s  force %+.6e %+.6e %+.6e N", p.max_speed, p.force[0],
                      p.force[1], p.force[2]);
      }
      c.insert(c.end(), {{"air_mesh_jacobian_min", jacobian},
                         {"interface_power_air_mW", power.air},
                         {"interface_power_solid_mW", power.solid}});
      text += format("  mesh J %.3f  power %.4e/%.4e mW", jacobian, power.air, power.solid);
      return c;
    };
    try
    {
      if (!resumed)
      {
        const auto first = sample(0);
        if (s.frames && s.frames->frames() == 0)
          s.add_frame(0, 0, solver::NewtonReport{true, 0, {0.0}, ""}, first);
      }
      s.stepper.march(
          newton, "puff", 0, s.scene.real("puff.duration"), s.scene.real("dynamics.dt"), dynamics,
          system,
          [&](double t)
          {
            // The inlet's values into the air's unknowns (x holds the state).
            unknowns.unpack();
            air.set_inlet_scale(inlet(t));
            unknowns.pack();
          },
          [&](double t, double dt, const solver::NewtonReport& report)
          {
            const auto columns = sample(t);
            _worst_jacobian = std::min(_worst_jacobian, jacobian);
            _worst_power = std::max(_worst_power, std::abs(power.air - power.solid));
            _largest_power
                = std::max({_largest_power, std::abs(power.air), std::abs(power.solid)});
            s.dynamic_step({{"phase", "puff"}}, t, dt, report, columns, text);
          });
    }
    catch (...)
    {
      out.write_tables();
      throw;
    }
    out.write_tables();
    nlohmann::json air_summary;
    out.summarise(air_summary);
    s.summary["air"] = air_summary;
    s.summary["coupled_timings_s"] = coupled.timings();
    s.summary["air_mesh_jacobian_min"] = _worst_jacobian;
    s.summary["interface_power_mismatch_max_mW"] = _worst_power;
    s.summary["interface_power_max_mW"] = _largest_power;
    _out = nullptr;
    if (s.frames)
    {
      s.write_tables();
      summarise_puff(s);
    }
  }
  nlohmann::json save() const override
  {
    return {{"record", _out->state()},
            {"worst_jacobian", _worst_jacobian},
            {"worst_power", _worst_power},
            {"largest_power", _largest_power}};
  }
  void restore(const nlohmann::json& state) override { _resumed = state; }

private:
  AirRecord* _out = nullptr; ///< while run() marches
  /// The air mesh's smallest Jacobian, the largest interface power
  /// mismatch and power over the steps so far [mW].
  double _worst_jacobian = 1, _worst_power = 0, _largest_power = 0;
  nlohmann::json _resumed; ///< a checkpoint's state of the phase, or null
};

} // namespace

std::vector<std::unique_ptr<Phase>> timeline(const scene::Scene& s, const Model& model)
{
  std::vector<std::unique_ptr<Phase>> phases;
  const std::string load = s.string("puff.load");
  if (load == "air")
  {
    phases.push_back(std::make_unique<AirPuff>());
    return phases;
  }
  const bool cavities = model.problem->cavities() > 0;
  if (s.boolean("zero_pressure.enabled"))
    phases.push_back(std::make_unique<ZeroPressure>());
  if (cavities)
    phases.push_back(std::make_unique<Inflate>());
  if (cavities && s.string("cavity.model") == "closed")
    phases.push_back(std::make_unique<Close>());
  if (s.real("press.pressure") != 0)
    phases.push_back(std::make_unique<Press>());
  if (s.real("rest.duration") > 0)
  {
    biomarkers::Columns at_rest;
    if (load == "fsi")
      at_rest = {{"apex_air_pressure_mmHg", 0.0}, {"max_air_velocity_m_s", 0.0},
                 {"air_force_N", 0.0},            {"air_mesh_jacobian_min", 1.0},
                 {"interface_power_air_mW", 0.0}, {"interface_power_solid_mW", 0.0}};
    phases.push_back(std::make_unique<Rest>(at_rest));
  }
  if (load == "gaussian" || load == "pulse" || load == "table")
    phases.push_back(std::make_unique<PrescribedPuff>());
  if (load == "fsi")
    phases.push_back(std::make_unique<CoupledPuff>());
  return phases;
}

} // namespace nct
