// The phases of a run (docs/physics.md sections 6-9): zero pressure,
// inflate, close, press, rest, and the puff: prescribed on the solid, the
// air alone about a rigid eye, or the air and the eye coupled.
#include <cmath>
#include <limits>
#include <utility>

#include <dolfinx/io/XDMFFile.h>

#include "biomarkers/registry.h"
#include "io/format.h"
#include "run/air_block.h"
#include "run/coupling_block.h"
#include "run/mesh_motion_block.h"
#include "run/run.h"
#include "run/solid_block.h"
#include "run/timeline.h"
#include "zero_pressure/zero_pressure.h"

namespace nct
{
namespace
{

constexpr double mmHg = 1.333224e-4; // MPa
using io::format;

/// Each cavity's volume of the current geometry at u = 0, under `label`.
void report_volumes(RunState& s, const SolidBlock& solid, const std::string& label)
{
  auto volumes = solid.problem.cavity_volumes();
  for (std::size_t c = 0; c < volumes.size(); ++c)
    s.summary[solid.mesh.cavity_names[c] + "_volume_" + label + "_mm3"] = volumes[c];
}

/// Write the mesh with the node coordinates `x` (geometry layout) to name.xdmf.
void write_geometry(const io::RunFolder& folder, const dolfinx::mesh::Mesh& mesh,
                    const std::vector<double>& x, const std::string& name)
{
  zero_pressure::SwappedGeometry swapped(mesh, x);
  dolfinx::io::XDMFFile file(mesh.comm(), folder.dir() / (name + ".xdmf"), "w");
  file.write_mesh(mesh);
}

/// The solid in dynamics from now on (once: its kept factorisation is
/// dropped), its record open.
void start_dynamics(RunState& s, SolidBlock& solid, double t)
{
  if (!solid.dynamic())
  {
    solid.start_dynamics(s.settings.dynamics);
    s.solid_newton().reset();
  }
  solid.open_output(s.folder, s.summary, t);
}

/// A solid's converged step: the phase's keys and the blocks' columns
/// (`columns`) into the summary's steps and the log (with `text`); a
/// dynamic step's state into the frames (the log line adds their apex
/// displacement, from the start of the dynamics). Returns the first
/// probe's axial displacement [mm] (0 without probes).
double record_solid_step(RunState& s, SolidBlock& solid, nlohmann::json step, double t,
                         std::optional<double> dt, const solver::NewtonReport& report,
                         const biomarkers::Columns& columns = {}, std::string text = "")
{
  if (dt)
    step["dt_ms"] = *dt;
  for (const auto& [name, value] : columns)
    step[name] = value;
  std::string line;
  const biomarkers::Columns cavities = solid.record(step, line, t);
  const std::string probe = solid.mesh.probe_names.empty()
                                ? ""
                                : solid.mesh.probe_names[0] + "_displacement_mm";
  const double axial = probe.empty() ? 0.0 : step[probe][1].get<double>();
  if (dt)
  {
    solid.add_frame(t, *dt, report, columns, cavities);
    if (solid.frames)
      text = format("  (frames %+.5f mm)", solid.frames->last_apex()) + text;
  }
  s.record_step(std::move(step), t, report, line + text);
  return axial;
}

/// The device's air pressure at the apex at time t [mmHg]: what its own
/// pressure curve says, whatever the cornea does (SP-A1 takes it). A
/// prescribed load's apex pressure; for the computed air, the history the
/// inlet was calibrated to: the measured pulse, or the Gaussian.
double device_pressure(const Settings& settings, const biomarkers::Record& frames, double t)
{
  const PuffSettings& p = settings.puff;
  if (p.prescribed())
    return frames.at("apex_air_pressure_mmHg", t);
  if (settings.air.inlet.pulse)
    return p.peak
           * puff::PulseShape::from_descriptors(p.rise_rate / p.peak, p.fall_rate / p.peak,
                                                p.pulse_duration)(t);
  return p.peak * std::exp(-0.5 * std::pow((t - p.peak_time) / p.width_t, 2));
}

/// The puff's biomarkers (docs/physics.md sections 9-10) into the summary.
void summarise_puff(RunState& s, const SolidBlock& solid)
{
  const auto& frames = *solid.frames;
  const PuffSettings& puff = s.settings.puff;
  nlohmann::json& summary = s.summary;
  using biomarkers::put;
  const auto r = frames.analyse(puff.definitions);
  summary["frames"] = frames.frames();
  put(summary, "hc_time_ms", r.hc_time);
  put(summary, "deformation_amplitude_mm", r.deformation_amplitude);
  put(summary, "deflection_amplitude_mm", r.deflection_amplitude);
  put(summary, "whole_eye_motion_hc_mm", r.deflection_amplitude - r.deformation_amplitude);
  put(summary, "peak_distance_mm", r.peak_distance);
  if (r.hc_radius)
    put(summary, "hc_radius_mm", *r.hc_radius);
  put(summary, "max_inverse_radius_per_mm", r.max_inverse_radius);
  put(summary, "whole_eye_movement_max_mm", r.whole_eye_movement_max);
  if (r.whole_eye_movement_time)
    put(summary, "whole_eye_movement_time_ms", *r.whole_eye_movement_time);
  if (r.applanated)
  {
    for (auto [name, a] : {std::pair{"a1", &r.a1}, {"a2", &r.a2}})
    {
      put(summary, std::string(name) + "_time_ms", a->time);
      put(summary, std::string(name) + "_length_mm", a->length);
      put(summary, std::string(name) + "_velocity_m_s", a->apex_velocity);
      put(summary, std::string(name) + "_deflection_mm", a->deflection);
    }
    put(summary, "a1_a2_interval_ms", r.a1_a2_interval());
    put(summary, "a1_hc_interval_ms", r.a1_hc_interval());
    put(summary, "integrated_radius_per_mm", *r.integrated_radius);
  }
  for (auto [key, ratio] :
       {std::pair{"da_ratio_1mm", &r.da_ratio_1mm}, {"da_ratio_2mm", &r.da_ratio_2mm}})
    if (*ratio)
      put(summary, key, **ratio);
  put(summary, "apex_pressure_hc_mmHg", frames.at("apex_air_pressure_mmHg", r.hc_time));
  put(summary, "apex_pressure_max_mmHg", frames.max("apex_air_pressure_mmHg"));
  const auto& cavities = solid.mesh.cavity_names;
  std::optional<double> sp_a1;
  if (!cavities.empty())
  {
    put(summary, "iop_max_mmHg", frames.max(cavities[0] + "_pressure_mmHg"));
    put(summary, "iop_hc_mmHg", frames.at(cavities[0] + "_pressure_mmHg", r.hc_time));
    if (r.applanated)
      sp_a1 = biomarkers::stiffness_parameter_a1(
          device_pressure(s.settings, frames, r.a1.time),
          frames.at(cavities[0] + "_pressure_mmHg", 0.0), r.a1.deflection);
  }
  if (sp_a1)
    put(summary, "sp_a1_mmHg_per_mm", *sp_a1);
  std::string text = format("biomarkers: HC %.3f ms, deformation %.4f mm, deflection %.4f "
                            "mm, peak distance %.3f mm, whole eye %.4f mm",
                            r.hc_time, r.deformation_amplitude, r.deflection_amplitude,
                            r.peak_distance, r.whole_eye_movement_max);
  if (r.hc_radius)
    text += format(", HC radius %.3f mm", *r.hc_radius);
  if (r.applanated)
    text += format("; A1 %.3f ms %.3f mm %+.3f m/s; A2 %.3f ms %.3f mm %+.3f m/s; "
                   "A1 deflection %.4f mm; integrated radius %.3f /mm",
                   r.a1.time, r.a1.length, r.a1.apex_velocity, r.a2.time, r.a2.length,
                   r.a2.apex_velocity, r.a1.deflection, *r.integrated_radius);
  else
    text += "; the cornea did not applanate twice (no A1/A2)";
  if (r.da_ratio_2mm)
    text += format("; DA ratio 2 mm %.3f", *r.da_ratio_2mm);
  if (sp_a1)
    text += format("; SP-A1 %.1f mmHg/mm", *sp_a1);
  s.folder.log(text);
}

/// Phase 1 (zero_pressure.enabled): the mesh is the eye imaged at the
/// IOP; find the stress-free geometry whose inflation gives it back.
class ZeroPressure : public Phase
{
public:
  explicit ZeroPressure(SolidBlock& solid) : _solid(solid) {}
  const char* name() const override { return "zero_pressure"; }
  void run(RunState& s) override
  {
    auto& problem = _solid.problem;
    auto& mesh = *_solid.mesh.mesh.mesh;
    _solid.x_imaged.assign(mesh.geometry().x().begin(), mesh.geometry().x().end());
    report_volumes(s, _solid, "imaged");
    const ZeroPressureSettings& zs = s.settings.solid.zero_pressure;
    const zero_pressure::Settings& zp = zs.fixed_point;
    const double t = MPI_Wtime();
    // Newton solves the pressurised shapes to a hundredth of the geometric
    // tolerance (the increment test, mm): what the fixed point needs of
    // them, where the residual test alone would ask for 1e-9 N at each.
    SolverSettings solver = s.settings.solver;
    solver.newton.increment_tol = 0.01 * zp.tolerance;
    Stepper stepper = make_stepper(solver, s.folder);
    auto& newton = s.solid_newton();
    const std::size_t n_cavities = problem.cavities();
    const double iop = s.settings.solid.cavity.iop * mmHg;
    bool first = true;
    // Inflate the current geometry to the IOP: one Newton solve from the
    // last solution (the geometry moved little, and a kept factorisation
    // of the last geometry's Jacobian serves), else a ramp from rest.
    auto pressurise = [&]
    {
      if (!first)
      {
        auto report = newton.solve(_solid.system(), solver.newton);
        stepper.newton_iterations += report.iterations;
        if (report.converged)
          return;
        s.folder.log(format("  zero-pressure: Newton from the last solution failed (%s); "
                            "inflating from rest",
                            report.reason.c_str()));
      }
      first = false;
      problem.u->x()->set(0.0);
      stepper.ramp(newton, "zero-pressure inflation", s.settings.solid.cavity.inflate_steps,
                   _solid.system(),
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
    _solid.probes = zero_pressure::points_on_current(mesh, _solid.x_imaged, _solid.mesh.probes);
    // The last pressurised state is the inflated stress-free geometry: the
    // inflate phase may start from it (with the kept factorisation).
    if (zs.reuse)
    {
      const auto u = problem.u->x()->array();
      _solid.inflated.assign(u.begin(), u.end());
    }
    else
      newton.reset();
    problem.u->x()->set(0.0);
    if (s.settings.output.fields)
    {
      write_geometry(s.folder, mesh, _solid.x_imaged, "geometry_imaged");
      write_geometry(s.folder, mesh,
                     std::vector<double>(mesh.geometry().x().begin(), mesh.geometry().x().end()),
                     "geometry_stress_free");
    }
  }

private:
  SolidBlock& _solid;
};

/// A quasi-static phase's converged step at load fraction f.
void record_quasi_static(RunState& s, SolidBlock& solid, const char* phase, double t0, double f,
                         const solver::NewtonReport& report)
{
  record_solid_step(
      s, solid, {{"phase", phase}, {"load_fraction", f}, {"press_mmHg", solid.press_now() / mmHg}},
      t0 + f, std::nullopt, report);
}

/// Phase 2: the cavities inflated by a pressure ramp to the IOP; after
/// zero pressure, in one step from its last pressurised state.
class Inflate : public Phase
{
public:
  Inflate(SolidBlock& solid, double t0) : _solid(solid), _t0(t0) {}
  const char* name() const override { return "inflate"; }
  void run(RunState& s) override
  {
    _solid.open_output(s.folder, s.summary, _t0);
    if (!from_zero_pressure(s))
      s.stepper.ramp(s.solid_newton(), "inflate", s.settings.solid.cavity.inflate_steps,
                     _solid.system(), [&](double f) { _solid.inflate(f); },
                     [&](double f, const auto& report)
                     { record_quasi_static(s, _solid, "inflate", _t0, f, report); });
    if (_solid.x_imaged.empty())
      return;
    // The round trip: the inflated stress-free geometry against the imaged one.
    const auto [max, rms] = zero_pressure::mismatch(_solid.problem, _solid.x_imaged);
    s.summary["zero_pressure_round_trip_max_mm"] = max;
    s.summary["zero_pressure_round_trip_rms_mm"] = rms;
    s.folder.log(format("round trip: the inflated stress-free geometry is %.3e mm (max), "
                        "%.3e mm (rms) from the imaged one",
                        max, rms));
  }

private:
  /// Zero pressure's last inflation of the stress-free geometry is this
  /// phase's end: one Newton solve from it at the run's tolerance (the
  /// ramp's states in between are not recomputed). False (state back at
  /// rest) if there is none or it does not converge.
  bool from_zero_pressure(RunState& s)
  {
    if (_solid.inflated.empty())
      return false;
    auto& problem = _solid.problem;
    auto u = problem.u->x()->mutable_array();
    std::copy(_solid.inflated.begin(), _solid.inflated.end(), u.begin());
    _solid.inflated.clear();
    _solid.inflate(1.0);
    auto& newton = s.solid_newton();
    const auto report = newton.solve(_solid.system(), s.settings.solver.newton);
    s.stepper.newton_iterations += report.iterations;
    if (report.converged)
    {
      record_quasi_static(s, _solid, "inflate", _t0, 1.0, report);
      return true;
    }
    s.folder.log(format("  inflate: Newton from zero pressure's last state failed (%s); "
                        "ramping from rest",
                        report.reason.c_str()));
    problem.u->x()->set(0.0);
    newton.reset();
    return false;
  }

  SolidBlock& _solid;
  double _t0; ///< the phase's start in pseudo-time
};

/// Phase 3 (cavity.model = "closed"): each cavity keeps the volume it has now.
class Close : public Phase
{
public:
  explicit Close(SolidBlock& solid) : _solid(solid) {}
  const char* name() const override { return "close"; }
  void run(RunState& s) override
  {
    _solid.close();
    std::string text;
    const auto& names = _solid.mesh.cavity_names;
    for (std::size_t c = 0; c < names.size(); ++c)
    {
      s.summary[names[c] + "_volume_closed_mm3"] = _solid.closed()->targets()[c];
      text += format("  %s %.4f mm3", names[c].c_str(), _solid.closed()->targets()[c]);
    }
    s.folder.log("close: volumes held at" + text);
  }

private:
  SolidBlock& _solid;
};

/// Phase 4 (press.pressure != 0): a follower pressure ramped on the pressed surface.
class Press : public Phase
{
public:
  Press(SolidBlock& solid, double t0) : _solid(solid), _t0(t0) {}
  const char* name() const override { return "press"; }
  void run(RunState& s) override
  {
    _solid.open_output(s.folder, s.summary, _t0);
    _solid.start_press();
    s.stepper.ramp(s.solid_newton(), "press", s.settings.solid.press.steps, _solid.system(),
                   [&](double f) { _solid.press(f); },
                   [&](double f, const auto& report)
                   { record_quasi_static(s, _solid, "press", _t0, f, report); });
  }

private:
  SolidBlock& _solid;
  double _t0; ///< the phase's start in pseudo-time
};

/// Phase 5 (rest.duration > 0): dynamics from rest with the loads held;
/// the eye should not move.
class Rest : public Phase
{
public:
  /// `columns`: the puff's state columns, at rest (the frames' columns
  /// are the same at every step).
  Rest(SolidBlock& solid, biomarkers::Columns columns)
      : _solid(solid), _columns(std::move(columns))
  {
  }
  const char* name() const override { return "rest"; }
  void run(RunState& s) override
  {
    const double rest = s.settings.solid.rest_duration;
    start_dynamics(s, _solid, -rest);
    _solid.set_load(-rest);
    if (!_resumed)
      _apex_rest = _solid.probes.empty() ? 0.0 : _solid.probe_displacement()[0][1];
    nlohmann::json keys{{"phase", "rest"}};
    if (_columns.empty())
      keys["apex_air_pressure_mmHg"] = 0.0;
    s.stepper.march(s.solid_newton(), "rest", -rest, rest, s.settings.dynamics,
                    _solid.dynamics(), _solid.system(), [](double) {},
                    [&](double t, double dt, const auto& report)
                    {
                      const double u = record_solid_step(s, _solid, keys, t, dt, report, _columns);
                      _drift = std::max(_drift, std::abs(u - _apex_rest));
                    });
    if (!_solid.probes.empty())
      s.summary["rest_drift_mm"] = _drift;
  }
  nlohmann::json save() const override { return {_apex_rest, _drift}; }
  void restore(const nlohmann::json& j) override
  {
    _apex_rest = j[0], _drift = j[1], _resumed = true;
  }

private:
  SolidBlock& _solid;
  biomarkers::Columns _columns;
  double _apex_rest = 0, _drift = 0; ///< the apex at rest, its largest drift [mm]
  bool _resumed = false;
};

/// Phase 6, the puff: every kind marches its blocks' system from t = 0 for
/// puff.duration and records each converged step the same way (the
/// summary's steps, the log, the frames of a puff on the eye); the kinds
/// differ in what they march and sample.
class Puff : public Phase
{
public:
  const char* name() const override { return "puff"; }
  void run(RunState& s) override
  {
    const bool resumed = s.stepper.resume.has_value();
    start(s, resumed);
    auto& newton = this->newton(s);
    try
    {
      s.stepper.march(newton, march_name(), 0, s.settings.puff.duration, s.settings.dynamics,
                      dynamics(),
                      system(), [&](double t) { load(t); },
                      [&](double t, double dt, const solver::NewtonReport& report)
                      { record(s, t, dt, report); });
    }
    catch (...)
    {
      s.write_tables();
      throw;
    }
    s.write_tables();
    finish(s);
  }

protected:
  /// Get ready to march: the dynamics started, the records opened, the
  /// state at t = 0 recorded (unless `resumed` from a checkpoint).
  virtual void start(RunState& s, bool resumed) = 0;
  virtual solver::Newton& newton(RunState& s) = 0;
  virtual solver::System system() = 0;
  virtual Stepper::Dynamics dynamics() = 0;
  virtual const char* march_name() const { return "puff"; }
  /// The loads at time t.
  virtual void load(double t) = 0;
  /// A converged step into the record.
  virtual void record(RunState& s, double t, double dt, const solver::NewtonReport& report) = 0;
  /// After the march: the summary's results.
  virtual void finish(RunState& s) = 0;
};

/// The puff on the solid (prescribed, or coupled): the frames' first state
/// at t = 0, the biomarkers at the end.
class SolidPuff : public Puff
{
public:
  explicit SolidPuff(SolidBlock& solid) : _solid(solid) {}

protected:
  void start_solid(RunState& s, bool resumed, const biomarkers::Columns& first = {})
  {
    start_dynamics(s, _solid, 0);
    if (!resumed && _solid.frames && _solid.frames->frames() == 0)
      _solid.add_frame(0, 0, solver::NewtonReport{true, 0, {0.0}, ""}, first,
                       _solid.cavity_state());
  }
  void finish_solid(RunState& s)
  {
    if (_solid.frames)
      summarise_puff(s, _solid);
  }
  SolidBlock& _solid;
};

/// puff.load = "gaussian", "pulse" or "table": the air as a follower
/// pressure p(r, t) on the anterior cornea.
class PrescribedPuff : public SolidPuff
{
public:
  using SolidPuff::SolidPuff;

protected:
  void start(RunState& s, bool resumed) override
  {
    if (!_solid.eye)
      s.folder.log("puff: the biomarkers need the idealised eye's cornea; this file mesh "
                   "gets the puff's load and its steps, no frames");
    start_solid(s, resumed);
  }
  solver::Newton& newton(RunState& s) override { return s.solid_newton(); }
  solver::System system() override { return _solid.system(); }
  Stepper::Dynamics dynamics() override { return _solid.dynamics(); }
  void load(double t) override { _solid.set_load(t); }
  void record(RunState& s, double t, double dt, const solver::NewtonReport& report) override
  {
    record_solid_step(s, _solid, {{"phase", "puff"}, {"apex_air_pressure_mmHg", _solid.apex_load(t)}},
                      t, dt, report);
  }
  void finish(RunState& s) override { finish_solid(s); }
};

/// puff.load = "air": the air alone, the Corvis jet on a rigid eye or a
/// free jet, or a file mesh's fluid; no solid phase runs.
class AirPuff : public Puff
{
public:
  explicit AirPuff(AirBlock& air) : _air(air) {}

protected:
  void start(RunState& s, bool resumed) override
  {
    if (_air.with_eye)
      s.folder.log("air: the eye is a rigid wall; the solid phases (zero pressure, inflation, "
                   "rest) are not run");
    // Full Newton steps: the energy line search has no energy to follow here.
    s.stepper.settings.line_search = false;
    _air.open_record(s.folder, nullptr);
    // From rest, the inlet at its t = 0 value; resumed, at the checkpoint's.
    _air.set_inlet(resumed ? s.stepper.resume->t : 0);
    if (!resumed)
    {
      nlohmann::json step;
      std::string text;
      _air.record_step(step, text, 0, 0, solver::NewtonReport{true, 0, {0.0}, ""});
    }
  }
  solver::Newton& newton(RunState& s) override
  {
    auto& n = s.newton("air", [&] { return _air.problem.create_matrix(); });
    _air.set_fieldsplit(n.ksp());
    return n;
  }
  solver::System system() override { return _air.system(); }
  Stepper::Dynamics dynamics() override { return _air.dynamics(); }
  const char* march_name() const override { return "air"; }
  void load(double t) override { _air.set_inlet(t); }
  void record(RunState& s, double t, double dt, const solver::NewtonReport& report) override
  {
    nlohmann::json step{{"phase", "puff"}, {"dt_ms", dt}};
    std::string text;
    _air.record_step(step, text, t, dt, report);
    s.record_step(std::move(step), t, report, text);
  }
  void finish(RunState& s) override { _air.summarise_record(s.summary, s.folder); }

private:
  AirBlock& _air;
};

/// puff.load = "fsi": the air and the eye in one Newton system per step
/// (cpp/fsi), from the solid's state at the end of the rest; the air
/// starts at rest.
class CoupledPuff : public SolidPuff
{
public:
  CoupledPuff(SolidBlock& solid, AirBlock& air, MeshMotionBlock& motion, CouplingBlock& coupling)
      : SolidPuff(solid), _air(air), _motion(motion), _coupling(coupling)
  {
  }

protected:
  void start(RunState& s, bool resumed) override
  {
    start_dynamics(s, _solid, 0);
    auto& coupled = _coupling.coupled;
    if (!resumed) // else RunState::resume restored the coupling
    {
      coupled.start();
      _coupling.start_energy();
    }
    _air.open_record(s.folder, &_motion.problem);
    _air.set_inlet(resumed ? s.stepper.resume->t : 0);
    coupled.unknowns().pack();
    _coupling.set_solver_options();
    std::string text;
    start_solid(s, resumed, resumed ? biomarkers::Columns{} : _coupling.sample(0, text));
  }
  solver::Newton& newton(RunState& s) override
  {
    auto& n = s.newton("coupled", [&] { return _coupling.coupled.create_matrix(); }, "fsi_");
    _coupling.set_fieldsplit(n.ksp());
    return n;
  }
  solver::System system() override { return _coupling.coupled.system(_solid.closed()); }
  Stepper::Dynamics dynamics() override { return _coupling.dynamics(); }
  void load(double t) override
  {
    // The inlet's values into the air's unknowns (x holds the state).
    auto& unknowns = _coupling.coupled.unknowns();
    unknowns.unpack();
    _air.set_inlet(t);
    unknowns.pack();
  }
  void record(RunState& s, double t, double dt, const solver::NewtonReport& report) override
  {
    std::string text;
    const auto columns = _coupling.sample(t, text);
    record_solid_step(s, _solid, {{"phase", "puff"}}, t, dt, report, columns, text);
  }
  void finish(RunState& s) override
  {
    _air.summarise_record(s.summary, s.folder);
    finish_solid(s);
  }

private:
  AirBlock& _air;
  MeshMotionBlock& _motion;
  CouplingBlock& _coupling;
};

} // namespace

std::vector<std::unique_ptr<Phase>> timeline(const Settings& s, Model& model)
{
  std::vector<std::unique_ptr<Phase>> phases;
  using Load = PuffSettings::Load;
  const Load load = s.puff.load;
  if (load == Load::air)
  {
    phases.push_back(std::make_unique<AirPuff>(*model.air));
    return phases;
  }
  SolidBlock& solid = *model.solid;
  const bool cavities = solid.problem.cavities() > 0, press = s.solid.press.pressure != 0;
  // Pseudo-time: each quasi-static phase spans one unit before the rest.
  double t = -s.solid.rest_duration - (int(cavities) + int(press));
  if (s.solid.zero_pressure.enabled)
    phases.push_back(std::make_unique<ZeroPressure>(solid));
  if (cavities)
    phases.push_back(std::make_unique<Inflate>(solid, t)), t += 1;
  if (cavities && s.solid.cavity.closed)
    phases.push_back(std::make_unique<Close>(solid));
  if (press)
    phases.push_back(std::make_unique<Press>(solid, t)), t += 1;
  if (s.solid.rest_duration > 0)
    phases.push_back(std::make_unique<Rest>(
        solid, load == Load::fsi ? CouplingBlock::at_rest() : biomarkers::Columns{}));
  if (s.puff.prescribed())
    phases.push_back(std::make_unique<PrescribedPuff>(solid));
  if (load == Load::fsi)
    phases.push_back(std::make_unique<CoupledPuff>(solid, *model.air, *model.mesh_motion,
                                                   *model.coupling));
  return phases;
}

} // namespace nct
