#include "run/run.h"

#include <cmath>
#include <cstdio>
#include <optional>

#include <dolfinx/common/log.h>
#include <dolfinx/io/XDMFFile.h>
#include <dolfinx/la/petsc.h>

#include "cavity/cavity.h"
#include "io/output.h"
#include "run/model.h"
#include "solver/newton.h"
#include "zero_pressure/zero_pressure.h"

namespace nct
{
namespace
{

constexpr double mmHg = 1.333224e-4; // MPa

std::string format(const char* fmt, auto... args)
{
  char buf[512];
  std::snprintf(buf, sizeof buf, fmt, args...);
  return buf;
}

std::string history(const std::vector<double>& residuals)
{
  std::string s;
  for (double r : residuals)
    s += format(" %.3e", r);
  return s;
}

nlohmann::json vec(const std::array<double, 3>& v) { return {v[0], v[1], v[2]}; }

/// Quasi-static load ramps with step cutting: a failed step is retried at
/// half the increment, down to a floor; after two successes the increment
/// doubles back.
class Stepper
{
public:
  Stepper(solver::Newton& newton, const solver::NewtonSettings& settings, int max_cuts,
          io::RunFolder& folder)
      : _newton(newton), _settings(settings), _max_cuts(max_cuts), _folder(folder)
  {
  }

  /// Take the loads from fraction 0 (the current state) to 1 in `steps`
  /// steps: `load(f)` sets them, `done(f, report)` sees every converged
  /// step. Throws Diverged, naming the phase, when cutting cannot help.
  void ramp(const std::string& phase, int steps, const solver::System& system,
            const std::function<void(double)>& load,
            const std::function<void(double, const solver::NewtonReport&)>& done)
  {
    dolfinx::la::Vector<double> saved_x(*system.x);
    std::vector<double> saved_y = *system.y;
    // The increment never falls below 2^-max_cuts of the nominal one.
    const double nominal = 1.0 / steps, floor = std::ldexp(nominal, -_max_cuts);
    double reached = 0, increment = nominal;
    int successes = 0;
    while (reached < 1.0 - 1e-12)
    {
      const double target = std::min(1.0, reached + increment);
      load(target);
      auto report = _newton.solve(system, _settings);
      newton_iterations += report.iterations;
      if (!report.converged)
      {
        _folder.log(format("  %s %.4f: Newton failed after %d iterations: %s; residuals:%s",
                           phase.c_str(), target, report.iterations,
                           report.reason.c_str(), history(report.residuals).c_str()));
        std::copy(saved_x.array().begin(), saved_x.array().end(),
                  system.x->mutable_array().begin());
        *system.y = saved_y;
        if (increment / 2 < floor * (1 - 1e-12))
          throw Diverged(format("phase '%s' diverged: load fraction %.6f (from %.6f) failed "
                                "with the increment cut %d times (solver.max_step_cuts); "
                                "last Newton: %s; residuals:%s",
                                phase.c_str(), target, reached, _max_cuts,
                                report.reason.c_str(), history(report.residuals).c_str()));
        ++cuts;
        increment /= 2;
        successes = 0;
        continue;
      }
      reached = target;
      std::copy(system.x->array().begin(), system.x->array().end(),
                saved_x.mutable_array().begin());
      saved_y = *system.y;
      if (++successes >= 2 && increment < nominal)
        increment = std::min(2 * increment, nominal), successes = 0;
      done(reached, report);
    }
  }

  int newton_iterations = 0;
  int cuts = 0;

private:
  solver::Newton& _newton;
  solver::NewtonSettings _settings;
  int _max_cuts;
  io::RunFolder& _folder;
};

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
      s.string("solver.line_search") == "energy", s.string("solver.jacobian") == "reuse"};
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

    // Output of one state; time is the phase's count plus its load fraction.
    io::Fields fields(folder, mesh, problem.coordinate_space());
    auto write_fields = [&](double time)
    {
      if (!s.boolean("output.fields"))
        return;
      double t0 = MPI_Wtime();
      problem.update_von_mises();
      fields.write(*problem.u, time);
      fields.write(*problem.von_mises, time);
      t_output += MPI_Wtime() - t0;
    };
    if (s.boolean("output.fields"))
    {
      fields.write(*problem.fields.at("fibre_1"), 0.0);
      fields.write(*problem.fields.at("fibre_2"), 0.0);
    }
    write_fields(0.0);

    double t_step = MPI_Wtime();
    auto record = [&](const std::string& phase, double time, double fraction,
                      const solver::NewtonReport& report)
    {
      const auto volumes = problem.cavity_volumes();
      const auto& pressures = closed ? closed->pressures() : open_pressures;
      const auto u = problem.displacement_at(probes);
      nlohmann::json step = {{"phase", phase},
                             {"load_fraction", fraction},
                             {"surface_pressure_mmHg", surface_pressure / mmHg},
                             {"newton_iterations", report.iterations},
                             {"residual_N", report.residuals.back()},
                             {"newton_residuals", report.residuals}};
      std::string text;
      for (std::size_t c = 0; c < n_cavities; ++c)
      {
        step[m.cavity_names[c] + "_volume_mm3"] = volumes[c];
        step[m.cavity_names[c] + "_pressure_mmHg"] = pressures[c] / mmHg;
        text += format("  %s %.3f mmHg %.4f mm3", m.cavity_names[c].c_str(),
                       pressures[c] / mmHg, volumes[c]);
      }
      for (std::size_t i = 0; i < u.size(); ++i)
        step[m.probe_names[i] + "_displacement_mm"] = vec(u[i]);
      steps.push_back(step);
      write_fields(time);
      if (!u.empty())
        text = format("  %s u %+.5f %+.5f %+.5f mm", m.probe_names[0].c_str(), u[0][0],
                      u[0][1], u[0][2])
               + text;
      folder.log(format("step %3zu  %-7s %.4f  newton %2d  |R| %.2e%s  wall %.2f s",
                        steps.size(), phase.c_str(), fraction, report.iterations,
                        report.residuals.back(), text.c_str(), MPI_Wtime() - t_step));
      t_step = MPI_Wtime();
    };

    // Phase: inflate the cavities by a pressure ramp to the IOP.
    if (n_cavities > 0)
      stepper.ramp(
          "inflate", s.integer("inflate.steps"), open.system(),
          [&](double f)
          {
            open_pressures.assign(n_cavities, f * iop);
            problem.set_cavity_pressures(open_pressures);
          },
          [&](double f, const auto& report) { record("inflate", f, f, report); });
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

    // Phase: press the loaded surface.
    if (const double peak = s.real("press.pressure") * mmHg; peak != 0)
    {
      if (s.string("press.profile") == "gaussian")
      {
        const double w = s.real("press.width");
        problem.set_surface_profile([w](const std::array<double, 3>& x)
                                    { return std::exp(-(x[0] * x[0] + x[2] * x[2]) / (2 * w * w)); });
      }
      stepper.ramp(
          "press", s.integer("press.steps"), closed ? closed->system() : open.system(),
          [&](double f)
          {
            surface_pressure = f * peak;
            problem.set_surface_pressure(surface_pressure);
          },
          [&](double f, const auto& report) { record("press", 1 + f, f, report); });
    }
  }
  catch (const Diverged& e)
  {
    summary["error"] = e.what();
    finish("failed");
    throw;
  }
  if (steps.empty())
    throw std::runtime_error("the scene loads nothing: no cavity to inflate and no "
                             "press.pressure");

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
