#include "run/air.h"

#include <algorithm>
#include <cmath>
#include <limits>

#include <dolfinx/la/petsc.h>
#include <dolfinx/mesh/utils.h>
#include <petscksp.h>

#include "air/problem.h"
#include "io/format.h"
#include "run/model.h"
#include "run/stepper.h"
#include "solver/newton.h"

namespace nct
{
namespace
{

constexpr double mmHg = 1.333224e-4; // MPa
using io::format;

/// Surface group tag by name (the air mesh always has these groups).
std::int32_t group(const meshio::Tagged& m, const std::string& name)
{
  return m.groups.surfaces.at(name);
}

/// The nodes of the anterior cornea on the plane z = 0, by increasing x
/// (= r): where the corneal pressure table is sampled. Collective.
std::vector<std::array<double, 3>> corneal_section(const meshio::Tagged& m)
{
  const auto& mesh = *m.mesh;
  const auto facets = m.facets->find(group(m, "anterior_cornea"));
  const auto nodes = dolfinx::mesh::entities_to_geometry(mesh, 2, facets, false);
  const auto& x = mesh.geometry().x();
  std::vector<double> local;
  for (auto n : nodes)
    if (std::abs(x[3 * n + 2]) < 1e-9)
      local.insert(local.end(), {x[3 * n], x[3 * n + 1]});
  int ranks = 1, count = static_cast<int>(local.size());
  MPI_Comm_size(mesh.comm(), &ranks);
  std::vector<int> counts(ranks), offsets(ranks + 1, 0);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, mesh.comm());
  for (int r = 0; r < ranks; ++r)
    offsets[r + 1] = offsets[r] + counts[r];
  std::vector<double> all(offsets[ranks]);
  MPI_Allgatherv(local.data(), count, MPI_DOUBLE, all.data(), counts.data(), offsets.data(),
                 MPI_DOUBLE, mesh.comm());
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
  double m = 0;
  for (std::int32_t i = 0; i < map.size_local(); ++i)
    m = std::max(m, std::hypot(x[3 * i], x[3 * i + 1], x[3 * i + 2]));
  MPI_Allreduce(MPI_IN_PLACE, &m, 1, MPI_DOUBLE, MPI_MAX, map.comm());
  return m;
}

/// Velocity and pressure blocks for a fieldsplit preconditioner, as index
/// sets of the owned global rows of (u, p).
void set_fieldsplit(KSP ksp, const air::Problem& problem)
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

} // namespace

nlohmann::json run_air(MPI_Comm comm, const scene::Scene& s, io::RunFolder& folder)
{
  const double t_start = MPI_Wtime();
  int ranks = 1;
  MPI_Comm_size(comm, &ranks);
  AirMesh a = make_air_mesh(comm, s);
  const bool with_eye = s.string("air.eye") == "rigid";
  const meshio::Tagged& m = a.mesh;

  // Air properties and conditions (design.md section 8).
  const air::Fluid fluid = air_fluid(s);
  const double U = s.real("air.inlet_velocity");
  double t = MPI_Wtime();
  air::Problem problem(m, fluid, air_boundaries(m, true), std::max(U, 1.0));
  set_air_inlet(problem, s, a.domain);
  const double t_setup = MPI_Wtime() - t;
  const std::int64_t cells = m.mesh->topology().index_map(3)->size_global();
  folder.log(format("air mesh: %lld tetrahedra (%lld air, %lld eye in the gmsh model), "
                    "P1/P1, %lld dofs (%.2f s); setup %.2f s",
                    (long long)cells, (long long)a.air_cells, (long long)a.eye_cells,
                    (long long)problem.dofs(), a.t_mesh, t_setup));
  if (with_eye)
    folder.log("air: the eye is a rigid wall; the solid phases (zero pressure, inflation, "
               "rest) are not run");

  dolfinx::la::petsc::Matrix A(problem.create_matrix(), false);
  solver::Newton newton(comm, A.mat());
  set_fieldsplit(newton.ksp(), problem);
  // Full Newton steps: the energy line search has no energy to follow here.
  const solver::NewtonSettings settings{s.integer("solver.max_iterations"),
                                        s.real("solver.rtol"), s.real("solver.atol"), false,
                                        s.string("solver.jacobian") == "reuse",
                                        s.real("solver.max_growth")};
  Stepper stepper(newton, settings, s.integer("solver.max_step_cuts"), folder);
  std::vector<double> no_border;
  const solver::System system{problem.up->x().get(), &no_border,
                              [&](auto& b, auto&) { problem.residual(b); },
                              [&](Mat J) { problem.jacobian(J); }, nullptr, nullptr, nullptr};

  // Probes: the centreline, the apex and the anterior cornea's section.
  const double y_exit = a.eye.apex_y + a.domain.nozzle_distance;
  std::vector<std::array<double, 3>> line;
  for (double d : centreline_distances)
    line.push_back({0, y_exit - d, 0});
  const meshio::Probes centreline(*m.mesh, line);
  const meshio::Probes apex(*m.mesh, {{0, a.eye.apex_y, 0}});
  const std::vector<std::array<double, 3>> section
      = with_eye ? corneal_section(m) : std::vector<std::array<double, 3>>{};
  const meshio::Probes cornea(*m.mesh, section);

  const double peak_time = s.real("puff.peak_time"), width_t = s.real("puff.width_t");
  auto inlet = [&](double time)
  { return U * std::exp(-(time - peak_time) * (time - peak_time) / (2 * width_t * width_t)); };

  nlohmann::json summary;
  summary["scene"] = s.file().string();
  summary["ranks"] = ranks;
  summary["cells"] = cells;
  summary["dofs"] = problem.dofs();
  summary["air_eye"] = s.string("air.eye");
  const double stagnation = 0.5 * fluid.density * U * U / mmHg;
  summary["stagnation_pressure_mmHg"] = stagnation;
  std::string steps_csv = "t_ms,dt_ms,newton_iterations,residual_N,inlet_velocity_m_s,"
                          "apex_pressure_mmHg,max_velocity_m_s,wall_s\n";
  std::string centreline_csv = "t_ms";
  for (double d : centreline_distances)
    centreline_csv += format(",u_%gmm_m_s", d);
  centreline_csv += "\n";
  std::string table_csv = "t_ms,r_mm,p_mmHg\n";
  std::vector<double> centreline_peak(std::size(centreline_distances), 0.0);
  double apex_max = -std::numeric_limits<double>::infinity(), apex_max_time = 0,
         speed_max = 0, t_output = 0;
  int steps = 0;

  io::Fields fields(folder, m.mesh, problem.w->function_space());
  const double interval = s.real("air.output_interval");
  double next_output = 0;
  // One state into the tables and fields; returns (apex pressure [mmHg], max |u|).
  auto sample = [&](double time, double dt, const solver::NewtonReport& report, double wall)
  {
    // Every value first (collective; may throw), then the tables' rows.
    problem.update_fields();
    const auto u = centreline.values(*problem.velocity);
    const double p_apex = apex.values(*problem.pressure)[0][0] / mmHg;
    const double speed = max_speed(*problem.velocity);
    const auto p = with_eye ? cornea.values(*problem.pressure)
                            : std::vector<std::array<double, 3>>{};
    centreline_csv += format("%.6g", time);
    for (std::size_t i = 0; i < u.size(); ++i)
    {
      centreline_csv += format(",%.6g", -u[i][1]);
      centreline_peak[i] = std::max(centreline_peak[i], -u[i][1]);
    }
    centreline_csv += "\n";
    for (std::size_t i = 0; i < p.size(); ++i)
      table_csv += format("%.6g,%.6g,%.6g\n", time, section[i][0], p[i][0] / mmHg);
    if (with_eye && p_apex > apex_max)
      apex_max = p_apex, apex_max_time = time;
    speed_max = std::max(speed_max, speed);
    steps_csv += format("%.6g,%.6g,%d,%.6e,%.6g,%.6g,%.6g,%.3f\n", time, dt, report.iterations,
                        report.residuals.back(), inlet(time), p_apex, speed, wall);
    if (s.boolean("output.fields") && time >= next_output - 1e-9 * interval)
    {
      const double t0 = MPI_Wtime();
      fields.write(*problem.velocity, time);
      fields.write(*problem.pressure, time);
      while (next_output <= time + 1e-9 * interval)
        next_output += interval;
      t_output += MPI_Wtime() - t0;
    }
    return std::pair{p_apex, speed};
  };
  auto write_tables = [&]
  {
    folder.write_text("steps.csv", steps_csv);
    folder.write_text("centreline.csv", centreline_csv);
    if (with_eye)
      folder.write_text("corneal_pressure.csv", table_csv);
  };
  auto finish = [&](const std::string& status)
  {
    summary["status"] = status;
    summary["steps"] = steps;
    summary["newton_iterations"] = stepper.newton_iterations;
    summary["linear_solves"] = newton.timings.linear_solves;
    summary["jacobians"] = newton.timings.jacobians;
    summary["step_cuts"] = stepper.cuts;
    summary["wall_s"] = MPI_Wtime() - t_start;
    summary["timings_s"] = {{"mesh", a.t_mesh},
                            {"setup", t_setup},
                            {"assemble", newton.timings.assemble},
                            {"linear_solve", newton.timings.solve},
                            {"output", t_output}};
    folder.write_text("summary.json", summary.dump(2) + "\n");
  };

  try
  {
    // From rest, the inlet at its t = 0 value.
    problem.up->x()->set(0.0);
    problem.up_n->x()->set(0.0);
    problem.up_nm1->x()->set(0.0);
    problem.set_inlet_scale(inlet(0));
    sample(0, 0, solver::NewtonReport{true, 0, {0.0}, ""}, 0);
    const int order = s.integer("air.bdf_order");
    const Stepper::Dynamics dynamics{[&](double dt) { problem.set_time_step(dt, order); },
                                     [] { return 1.0; }, [&] { problem.advance(); }};
    double t_step = MPI_Wtime();
    stepper.march("air", 0, s.real("puff.duration"), s.real("air.dt"), dynamics, system,
                  [&](double time) { problem.set_inlet_scale(inlet(time)); },
                  [&](double time, double dt, const solver::NewtonReport& report)
                  {
                    const double wall = MPI_Wtime() - t_step;
                    t_step = MPI_Wtime();
                    ++steps;
                    const auto [p_apex, speed] = sample(time, dt, report, wall);
                    folder.log(format("air t = %7.3f ms  dt %.3g  inlet %6.2f m/s  Newton %2d  "
                                      "residual %.2e N  apex %7.3f mmHg  max |u| %6.2f m/s  "
                                      "wall %.2f s",
                                      time, dt, inlet(time), report.iterations,
                                      report.residuals.back(), p_apex, speed, wall));
                  });
  }
  catch (const std::exception& e)
  {
    summary["error"] = e.what();
    try
    {
      write_tables();
    }
    catch (const std::exception& w)
    {
      summary["error"] = std::string(e.what()) + "; writing the tables failed too: " + w.what();
    }
    finish("failed");
    throw;
  }
  write_tables();
  for (std::size_t i = 0; i < centreline_peak.size(); ++i)
    summary["centreline_peak_m_s"][format("%gmm", centreline_distances[i])] = centreline_peak[i];
  summary["max_velocity_m_s"] = speed_max;
  if (with_eye)
  {
    summary["apex_pressure_max_mmHg"] = apex_max;
    summary["apex_pressure_max_time_ms"] = apex_max_time;
    summary["corneal_pressure_table"] = "corneal_pressure.csv";
  }
  finish("converged");
  folder.log(format("done: %d steps, %d Newton iterations, %d step cuts; assemble %.2f s, "
                    "linear solve %.2f s, output %.2f s, total %.2f s",
                    steps, stepper.newton_iterations, stepper.cuts, newton.timings.assemble,
                    newton.timings.solve, t_output, summary["wall_s"].get<double>()));
  if (with_eye)
    folder.log(format("apex pressure: max %.3f mmHg at %.3f ms (stagnation 0.5 rho U^2 = "
                      "%.3f mmHg)",
                      apex_max, apex_max_time, stagnation));
  std::string peaks = "centreline peaks:";
  for (std::size_t i = 0; i < centreline_peak.size(); ++i)
    peaks += format(" %g mm %.2f m/s;", centreline_distances[i], centreline_peak[i]);
  folder.log(peaks);
  return summary;
}

} // namespace nct
