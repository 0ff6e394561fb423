#include "run/run.h"

#include <cmath>
#include <cstdio>
#include <optional>
#include <set>

#include <dolfinx/common/log.h>
#include <dolfinx/io/XDMFFile.h>
#include <dolfinx/la/petsc.h>

#include "biomarkers/record.h"
#include "cavity/cavity.h"
#include "io/format.h"
#include "io/output.h"
#include "run/air.h"
#include "run/model.h"
#include "run/stepper.h"
#include "solver/newton.h"
#include "zero_pressure/zero_pressure.h"

namespace nct
{
namespace
{

constexpr double mmHg = 1.333224e-4; // MPa
/// Whole-eye motion: the anterior surface's axial displacement at this
/// distance from the axis (design.md section 9) [mm].
constexpr double whole_eye_x = 4.0;

using io::format;

nlohmann::json vec(const std::array<double, 3>& v) { return {v[0], v[1], v[2]}; }

/// The facets of the cavities' walls that bound cornea cells: the
/// posterior corneal surface.
std::vector<std::int32_t> posterior_cornea(const MeshSetup& m)
{
  auto& mesh = *m.mesh.mesh;
  mesh.topology_mutable().create_connectivity(2, 3);
  const auto f2c = mesh.topology().connectivity(2, 3);
  std::set<std::int32_t> cornea;
  for (auto& [tag, part] : m.parts)
    if (part == "cornea")
      for (auto c : m.mesh.cells->find(tag))
        cornea.insert(c);
  std::vector<std::int32_t> facets;
  for (const auto& walls : m.boundaries.cavities)
    for (auto g : walls)
      for (auto f : m.mesh.facets->find(g))
        if (cornea.count(f2c->links(f)[0]))
          facets.push_back(f);
  return facets;
}

/// The local facets of the given groups.
std::vector<std::int32_t> mesh_facets(const MeshSetup& m, const std::vector<std::int32_t>& groups)
{
  std::vector<std::int32_t> facets;
  for (auto g : groups)
  {
    auto f = m.mesh.facets->find(g);
    facets.insert(facets.end(), f.begin(), f.end());
  }
  return facets;
}

/// The puff's biomarkers (design.md sections 9-10) into the summary.
void summarise_puff(nlohmann::json& summary, const biomarkers::Record& frames,
                    const scene::Scene& s, const std::vector<std::string>& cavities,
                    io::RunFolder& folder)
{
  const auto r = frames.analyse(s.real("puff.apex_window"), s.real("puff.flatness"));
  summary["frames"] = frames.frames();
  summary["hc_time_ms"] = r.hc_time;
  summary["deformation_amplitude_mm"] = r.deformation_amplitude;
  summary["deflection_amplitude_mm"] = r.deflection_amplitude;
  summary["whole_eye_motion_hc_mm"] = r.deflection_amplitude - r.deformation_amplitude;
  summary["peak_distance_mm"] = r.peak_distance;
  if (r.applanated)
    for (auto [name, a] : {std::pair{"a1", &r.a1}, {"a2", &r.a2}})
    {
      summary[std::string(name) + "_time_ms"] = a->time;
      summary[std::string(name) + "_length_mm"] = a->length;
      summary[std::string(name) + "_velocity_m_s"] = a->apex_velocity;
    }
  summary["apex_pressure_hc_mmHg"] = frames.at("apex_air_pressure_mmHg", r.hc_time);
  summary["apex_pressure_max_mmHg"] = frames.max("apex_air_pressure_mmHg");
  if (!cavities.empty())
  {
    summary["iop_max_mmHg"] = frames.max(cavities[0] + "_pressure_mmHg");
    summary["iop_hc_mmHg"] = frames.at(cavities[0] + "_pressure_mmHg", r.hc_time);
  }
  std::string text = format("biomarkers: HC %.3f ms, deformation %.4f mm, deflection %.4f "
                            "mm, peak distance %.3f mm",
                            r.hc_time, r.deformation_amplitude, r.deflection_amplitude,
                            r.peak_distance);
  if (r.applanated)
    text += format("; A1 %.3f ms %.3f mm %+.3f m/s; A2 %.3f ms %.3f mm %+.3f m/s", r.a1.time,
                   r.a1.length, r.a1.apex_velocity, r.a2.time, r.a2.length,
                   r.a2.apex_velocity);
  else
    text += "; the cornea did not applanate twice (no A1/A2)";
  folder.log(text);
}

/// Write the mesh with the node coordinates `x` (geometry layout) to name.xdmf.
void write_geometry(const io::RunFolder& folder, const dolfinx::mesh::Mesh& mesh,
                    const std::vector<double>& x, const std::string& name)
{
  zero_pressure::SwappedGeometry swapped(mesh, x);
  dolfinx::io::XDMFFile file(mesh.comm(), folder.dir() / (name + ".xdmf"), "w");
  file.write_mesh(mesh);
}

} // namespace

Runtime::Runtime(const char* program)
{
  int argc = 1;
  char* argv[] = {const_cast<char*>(program), nullptr};
  char** pargv = argv;
  PetscInitialize(&argc, &pargv, nullptr, nullptr);
  dolfinx::init_logging(argc, pargv);
}

Runtime::~Runtime() { PetscFinalize(); }

nlohmann::json run(MPI_Comm comm, const scene::Scene& s, const RunOptions& options)
{
  check(comm, s);
  const double t_start = MPI_Wtime();
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  io::RunFolder folder(comm, options.out);
  folder.write_text("scene.toml", s.to_toml());
  folder.log("nct: " + s.file().string() + " on " + std::to_string(ranks)
             + " rank(s) -> " + options.out.string());

  // Linear solver options: defaults, then the scene's, then the command line's.
  auto petsc = s.options("solver.petsc");
  petsc.insert(petsc.end(), options.petsc.begin(), options.petsc.end());
  solver::set_petsc_options(petsc);
  if (s.string("puff.load") == "air")
    return run_air(comm, s, folder);

  Model model = make_model(comm, s);
  MeshSetup& m = model.setup;
  solid::Problem& problem = *model.problem;
  auto mesh = m.mesh.mesh;
  dolfinx::la::petsc::Matrix A(problem.create_matrix(), false);
  solver::Newton newton(comm, A.mat());
  const std::int64_t cells = mesh->topology().index_map(3)->size_global();
  const int degree = s.integer("fem.degree");
  folder.log(format("mesh: %lld tetrahedra, degree %d, %lld dofs (%.2f s); setup %.2f s",
                    (long long)cells, degree, (long long)problem.dofs(), model.t_mesh,
                    model.t_setup));

  const solver::NewtonSettings settings{
      s.integer("solver.max_iterations"), s.real("solver.rtol"), s.real("solver.atol"),
      s.string("solver.line_search") == "energy", s.string("solver.jacobian") == "reuse",
      s.real("solver.max_growth")};
  Stepper stepper(newton, settings, s.integer("solver.max_step_cuts"), folder);
  const std::size_t n_cavities = problem.cavities();
  const double iop = s.real("inflate.iop") * mmHg;
  cavity::Open open(problem);
  std::optional<cavity::Closed> closed;
  std::vector<double> open_pressures(n_cavities, 0.0); // [MPa], while open
  double surface_pressure = 0;                         // [MPa]

  nlohmann::json summary;
  summary["scene"] = s.file().string();
  summary["ranks"] = ranks;
  summary["cells"] = cells;
  summary["dofs"] = problem.dofs();
  summary["degree"] = degree;
  summary["symmetry_factor"] = problem.symmetry_factor();
  // The timeline: the puff starts at t = 0 [ms], the rest spans
  // [-rest, 0], and before it each quasi-static phase takes one unit of
  // pseudo-time (its load fraction).
  const double press_peak = s.real("press.pressure") * mmHg;
  const auto load = puff_load(s);
  const double rest = s.real("rest.duration");
  const bool dynamic = rest > 0 || load;
  const int quasi_static = (n_cavities > 0) + (press_peak != 0);
  if (quasi_static == 0 && !dynamic)
    throw std::runtime_error("the scene loads nothing: no cavity to inflate, no "
                             "press.pressure and no puff");
  double t0 = -rest - quasi_static; // start of the current quasi-static phase

  // Cavity volumes of the current geometry at u = 0, under `label`.
  auto report_volumes = [&](const std::string& label)
  {
    auto volumes = problem.cavity_volumes();
    for (std::size_t c = 0; c < n_cavities; ++c)
      summary[m.cavity_names[c] + "_volume_" + label + "_mm3"] = volumes[c];
  };
  nlohmann::json& steps = summary["steps"] = nlohmann::json::array();
  double t_output = 0;
  auto finish = [&](const std::string& status)
  {
    summary["status"] = status;
    summary["newton_iterations"] = stepper.newton_iterations;
    summary["linear_solves"] = newton.timings.linear_solves;
    summary["jacobians"] = newton.timings.jacobians;
    summary["step_cuts"] = stepper.cuts;
    summary["wall_s"] = MPI_Wtime() - t_start;
    summary["timings_s"] = {{"mesh", model.t_mesh},
                            {"setup", model.t_setup},
                            {"assemble", newton.timings.assemble},
                            {"linear_solve", newton.timings.solve},
                            {"border", newton.timings.border},
                            {"output", t_output}};
    folder.write_text("summary.json", summary.dump(2) + "\n");
  };

  std::optional<biomarkers::Record> frames; // the puff's, on the eye
  // The puff's tables so far (whole files, written at the end or on failure).
  auto write_tables = [&]
  {
    folder.write_text("steps.csv", frames->steps_csv());
    folder.write_text("frames.csv", frames->frames_csv());
    folder.write_text("profiles.csv", frames->profiles_csv());
  };
  try
  {
    // Phase: zero-pressure geometry. The mesh is the eye imaged at the
    // IOP; find the stress-free geometry whose inflation gives it back.
    std::vector<std::array<double, 3>> probes = m.probes;
    const std::vector<double> x_imaged(mesh->geometry().x().begin(),
                                       mesh->geometry().x().end());
    if (s.boolean("zero_pressure.enabled"))
    {
      report_volumes("imaged");
      const zero_pressure::Settings zp{s.real("zero_pressure.tolerance"),
                                       s.integer("zero_pressure.max_iterations"),
                                       s.string("zero_pressure.acceleration") == "aitken"};
      const double t = MPI_Wtime();
      const int newton_before = stepper.newton_iterations;
      bool first = true;
      // Inflate the current geometry to the IOP: one Newton solve from the
      // last solution (the geometry moved little), else a ramp from rest.
      auto pressurise = [&]
      {
        newton.reset();
        if (!first)
        {
          auto report = newton.solve(open.system(), settings);
          stepper.newton_iterations += report.iterations;
          if (report.converged)
            return;
          folder.log(format("  zero-pressure: Newton from the last solution failed (%s); "
                            "inflating from rest",
                            report.reason.c_str()));
        }
        first = false;
        problem.u->x()->set(0.0);
        stepper.ramp("zero-pressure inflation", s.integer("inflate.steps"), open.system(),
                     [&](double f)
                     { problem.set_cavity_pressures(std::vector<double>(n_cavities, f * iop)); },
                     [](double, const auto&) {});
      };
      nlohmann::json& its = summary["zero_pressure_history"] = nlohmann::json::array();
      auto report = zero_pressure::solve(
          problem, zp, pressurise,
          [&](int k, const zero_pressure::Iteration& it)
          {
            its.push_back({{"residual_max_mm", it.max},
                           {"residual_rms_mm", it.rms},
                           {"omega", it.omega}});
            folder.log(format("zero-pressure %2d  residual max %.3e mm  rms %.3e mm  "
                              "omega %.3f  wall %.2f s",
                              k, it.max, it.rms, it.omega, it.wall));
          });
      const auto& last = report.iterations.back();
      summary["zero_pressure_iterations"] = report.iterations.size();
      summary["zero_pressure_residual_max_mm"] = last.max;
      summary["zero_pressure_residual_rms_mm"] = last.rms;
      summary["zero_pressure_newton_iterations"] = stepper.newton_iterations - newton_before;
      summary["zero_pressure_wall_s"] = MPI_Wtime() - t;
      if (!report.converged)
        throw Diverged(format("zero-pressure geometry: no convergence in %d iterations "
                              "(zero_pressure.max_iterations); the last residual is "
                              "%.3e mm (max), %.3e mm (rms) against a tolerance of %.3e mm",
                              zp.max_iterations, last.max, last.rms, zp.tolerance));
      probes = zero_pressure::carry(*mesh, x_imaged, m.probes);
      problem.u->x()->set(0.0);
      newton.reset();
      if (s.boolean("output.fields"))
      {
        write_geometry(folder, *mesh, x_imaged, "geometry_imaged");
        write_geometry(folder, *mesh, std::vector<double>(mesh->geometry().x().begin(),
                                                          mesh->geometry().x().end()),
                       "geometry_stress_free");
      }
    }

    report_volumes("reference");
    for (std::size_t i = 0; i < probes.size(); ++i)
      summary["probe_reference_mm"][m.probe_names[i]] = vec(probes[i]);
    const solid::Probes probe_points(problem, probes); // the geometry is final from here

    // Output of one state at time `time`.
    io::Fields fields(folder, mesh, problem.coordinate_space());
    auto write_fields = [&](double time)
    {
      if (!s.boolean("output.fields"))
        return;
      double t = MPI_Wtime();
      problem.update_von_mises();
      fields.write(*problem.u, time);
      fields.write(*problem.von_mises, time);
      t_output += MPI_Wtime() - t;
    };
    if (s.boolean("output.fields"))
    {
      fields.write(*problem.fields.at("fibre_1"), t0);
      fields.write(*problem.fields.at("fibre_2"), t0);
    }
    write_fields(t0);

    // Every converged step: its line in the log and summary, its fields.
    double t_step = MPI_Wtime();
    // Each cavity's volume [mm^3] and pressure [mmHg] now.
    auto cavity_state = [&]
    {
      const auto volumes = problem.cavity_volumes();
      const auto& pressures = closed ? closed->pressures() : open_pressures;
      biomarkers::Columns state;
      for (std::size_t c = 0; c < n_cavities; ++c)
      {
        state.push_back({m.cavity_names[c] + "_pressure_mmHg", pressures[c] / mmHg});
        state.push_back({m.cavity_names[c] + "_volume_mm3", volumes[c]});
      }
      return state;
    };
    // A converged step into the summary (returned), the log and the fields.
    auto record = [&](nlohmann::json step, double time, const solver::NewtonReport& report,
                      const biomarkers::Columns& cavities) -> const nlohmann::json&
    {
      const auto u = probe_points.displacement();
      step["time"] = time;
      step["newton_iterations"] = report.iterations;
      step["residual_N"] = report.residuals.back();
      step["newton_residuals"] = report.residuals;
      std::string text;
      for (std::size_t c = 0; c < n_cavities; ++c)
        text += format("  %s %.3f mmHg %.4f mm3", m.cavity_names[c].c_str(),
                       cavities[2 * c].second, cavities[2 * c + 1].second);
      for (const auto& [name, value] : cavities)
        step[name] = value;
      for (std::size_t i = 0; i < u.size(); ++i)
        step[m.probe_names[i] + "_displacement_mm"] = vec(u[i]);
      steps.push_back(step);
      write_fields(time);
      if (!u.empty())
        text = format("  %s u %+.5f %+.5f %+.5f mm", m.probe_names[0].c_str(), u[0][0],
                      u[0][1], u[0][2])
               + text;
      folder.log(format("step %3zu  %-7s t %+8.4f  newton %2d  |R| %.2e%s  wall %.2f s",
                        steps.size(), step["phase"].get<std::string>().c_str(), time,
                        report.iterations, report.residuals.back(), text.c_str(),
                        MPI_Wtime() - t_step));
      t_step = MPI_Wtime();
      return steps.back();
    };
    auto quasi_static_step = [&](const char* phase, double f, const auto& report)
    {
      record({{"phase", phase},
              {"load_fraction", f},
              {"surface_pressure_mmHg", surface_pressure / mmHg}},
             t0 + f, report, cavity_state());
    };

    // Phase: inflate the cavities by a pressure ramp to the IOP.
    if (n_cavities > 0)
    {
      stepper.ramp(
          "inflate", s.integer("inflate.steps"), open.system(),
          [&](double f)
          {
            open_pressures.assign(n_cavities, f * iop);
            problem.set_cavity_pressures(open_pressures);
          },
          [&](double f, const auto& report) { quasi_static_step("inflate", f, report); });
      t0 += 1;
    }
    if (s.boolean("zero_pressure.enabled"))
    {
      // The round trip: the inflated stress-free geometry against the imaged one.
      const auto [max, rms] = zero_pressure::mismatch(problem, x_imaged);
      summary["zero_pressure_round_trip_max_mm"] = max;
      summary["zero_pressure_round_trip_rms_mm"] = rms;
      folder.log(format("round trip: the inflated stress-free geometry is %.3e mm (max), "
                        "%.3e mm (rms) from the imaged one",
                        max, rms));
    }

    // Close: each cavity keeps the volume it has now.
    if (n_cavities > 0 && s.string("cavity.model") == "closed")
    {
      closed.emplace(problem, open_pressures);
      std::string text;
      for (std::size_t c = 0; c < n_cavities; ++c)
      {
        summary[m.cavity_names[c] + "_volume_closed_mm3"] = closed->targets()[c];
        text += format("  %s %.4f mm3", m.cavity_names[c].c_str(), closed->targets()[c]);
      }
      folder.log("close: volumes held at" + text);
    }
    const solver::System system = closed ? closed->system() : open.system();

    // Phase: press the loaded surface (quasi-static).
    std::function<double(const std::array<double, 3>&)> press_profile
        = [](const auto&) { return 1.0; };
    if (s.string("press.profile") == "gaussian")
    {
      const double w = s.real("press.width");
      press_profile = [w](const std::array<double, 3>& x)
      { return std::exp(-(x[0] * x[0] + x[2] * x[2]) / (2 * w * w)); };
    }
    if (press_peak != 0)
    {
      problem.set_surface_profile(press_profile);
      stepper.ramp(
          "press", s.integer("press.steps"), system,
          [&](double f)
          {
            surface_pressure = f * press_peak;
            problem.set_surface_pressure(surface_pressure);
          },
          [&](double f, const auto& report) { quasi_static_step("press", f, report); });
    }

    // Phases: rest and puff (dynamic, from rest at the current state).
    if (dynamic)
    {
      const solid::TimeStep step{s.real("dynamics.dt"), s.real("dynamics.rho_inf"),
                                 s.real("dynamics.damping")};
      problem.start_dynamics(step);
      newton.reset();
      const Stepper::Dynamics dynamics{
          [&problem, step](double dt) { problem.set_time_step({dt, step.rho_inf, step.damping}); },
          [&problem] { return problem.load_level(); }, [&problem] { problem.advance(); }};
      // Air pressure [mmHg] at r, t; none before the puff.
      auto air = [&](double r, double t) { return t < 0 || !load ? 0.0 : (*load)(r, t); };
      // The surface load at time t: the press's, held, plus the air's.
      auto surface_load = [&](double t)
      {
        problem.set_surface_pressure(mmHg);
        problem.set_surface_profile(
            [&](const std::array<double, 3>& X)
            { return press_peak / mmHg * press_profile(X) + air(std::hypot(X[0], X[2]), t); });
      };
      if (load && !model.eye)
        folder.log("puff: the biomarkers need the idealised eye's cornea; this file mesh "
                   "gets the puff's load and its steps, no frames");
      if (model.eye && load)
        frames.emplace(biomarkers::Section(problem, mesh_facets(m, m.boundaries.surface_load),
                                           "anterior cornea"),
                       biomarkers::Section(problem, posterior_cornea(m), "posterior cornea"),
                       s.real("puff.frame_rate"), whole_eye_x,
                       std::vector<std::pair<std::string, std::function<double(double)>>>{
                           {"apex_air_pressure_mmHg", [air](double t) { return air(0, t); }}});
      auto add_frame = [&](double t, double dt, const solver::NewtonReport& report,
                           biomarkers::Columns state)
      {
        if (!frames)
          return;
        state.push_back({"strain_energy_mJ", problem.strain_energy()});
        state.push_back({"kinetic_energy_mJ", problem.kinetic_energy()});
        frames->add(t, state,
                    {{"dt_ms", dt},
                     {"newton_iterations", double(report.iterations)},
                     {"residual_N", report.residuals.back()}});
      };
      // Returns the apex's axial displacement (the first probe's), if any.
      auto dynamic_step = [&](const char* phase, double t, double dt, const auto& report)
      {
        const auto cavities = cavity_state();
        const nlohmann::json& step = record(
            {{"phase", phase}, {"dt_ms", dt}, {"apex_air_pressure_mmHg", air(0, t)}}, t,
            report, cavities);
        add_frame(t, dt, report, cavities);
        return probes.empty() ? 0.0
                              : step[m.probe_names[0] + "_displacement_mm"][1].get<double>();
      };
      double apex_rest = 0, drift = 0;
      if (rest > 0)
      {
        surface_load(-rest);
        // The first probe (the eye's apex) should not move.
        apex_rest = probes.empty() ? 0.0 : probe_points.displacement()[0][1];
        stepper.march("rest", -rest, rest, step.dt, dynamics, system, [](double) {},
                      [&](double t, double dt, const auto& report)
                      {
                        drift = std::max(
                            drift, std::abs(dynamic_step("rest", t, dt, report) - apex_rest));
                      });
        if (!probes.empty())
          summary["rest_drift_mm"] = drift;
      }
      if (load)
      {
        if (frames && frames->frames() == 0)
          add_frame(0, 0, solver::NewtonReport{true, 0, {0.0}, ""}, cavity_state());
        stepper.march("puff", 0, s.real("puff.duration"), step.dt, dynamics, system, surface_load,
                      [&](double t, double dt, const auto& report)
                      { dynamic_step("puff", t, dt, report); });
      }
      if (frames)
      {
        write_tables();
        summarise_puff(summary, *frames, s, m.cavity_names, folder);
      }
    }
  }
  catch (const std::exception& e) // Diverged, or a biomarker that cannot be taken
  {
    summary["error"] = e.what();
    if (frames)
      write_tables();
    finish("failed");
    throw;
  }
  const auto& last = steps.back();
  if (model.eye)
    summary["apex_displacement_mm"] = last["apex_displacement_mm"][1];
  summary["iop_mmHg"] = s.real("inflate.iop");
  summary["cavity_model"] = n_cavities > 0 ? s.string("cavity.model") : "none";
  for (const auto& name : m.cavity_names)
  {
    summary[name + "_volume_mm3"] = last[name + "_volume_mm3"];
    summary[name + "_pressure_mmHg"] = last[name + "_pressure_mmHg"];
    double max = 0;
    for (const auto& step : steps)
      max = std::max(max, step[name + "_pressure_mmHg"].get<double>());
    summary[name + "_pressure_max_mmHg"] = max;
  }
  finish("converged");
  folder.log(format("done: %zu steps, %d Newton iterations, %d step cuts; assemble %.2f s, "
                    "linear solve %.2f s (border %.2f s), output %.2f s, total %.2f s",
                    steps.size(), stepper.newton_iterations, stepper.cuts,
                    newton.timings.assemble, newton.timings.solve, newton.timings.border,
                    t_output, summary["wall_s"].get<double>()));
  return summary;
}

} // namespace nct
