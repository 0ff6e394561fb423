#include "run/solid_block.h"

#include <cmath>
#include <set>

#include "biomarkers/registry.h"
#include "io/format.h"

namespace nct
{
namespace
{

constexpr double mmHg = 1.333224e-4; // MPa
using io::format;

nlohmann::json vec(const std::array<double, 3>& v) { return {v[0], v[1], v[2]}; }

/// The solid parts' materials.
std::map<std::string, solid::Material>
solid_materials(const MeshSetup& mesh, const std::map<std::string, solid::Material>& all)
{
  std::map<std::string, solid::Material> materials;
  for (auto& [tag, part] : mesh.parts)
    materials[part] = all.at(part);
  return materials;
}

} // namespace

SolidBlock::SolidBlock(MeshSetup mesh_setup, SolidBlockSettings s, bool is_eye)
    : mesh(std::move(mesh_setup)), settings(std::move(s)),
      problem(mesh.mesh, settings.solid.element, mesh.parts,
              solid_materials(mesh, settings.materials), mesh.fibres, mesh.boundaries,
              mesh.volume_origin),
      eye(is_eye), probes(mesh.probes), _open_pressures(problem.cavities(), 0.0),
      _press_peak(settings.solid.press.pressure * mmHg)
{
  _open.emplace(problem);
  std::vector<std::int32_t> walls;
  for (const auto& groups : mesh.boundaries.cavities)
    walls.insert(walls.end(), groups.begin(), groups.end());
  humor = humor::make(problem, {mesh.mesh, walls, mesh.humor, mesh.humor_boundaries},
                      settings.solid.cavity, settings.humor_stabilisation_time);
  _press_profile = [](const auto&) { return 1.0; };
  if (settings.solid.press.gaussian)
  {
    const double w = settings.solid.press.width;
    _press_profile = [w](const std::array<double, 3>& x)
    { return std::exp(-(x[0] * x[0] + x[2] * x[2]) / (2 * w * w)); };
  }
}

void SolidBlock::describe(nlohmann::json& summary, io::RunFolder& folder) const
{
  const auto& topology = mesh.mesh.mesh->topology();
  const std::int64_t cells = topology.index_map(topology.dim())->size_global();
  summary["cells"] = cells;
  summary["dofs"] = problem.dofs();
  summary["degree"] = settings.solid.element.degree;
  summary["symmetry_factor"] = problem.symmetry_factor();
  const section::Dimension d = problem.dimension();
  if (d != section::Dimension::three)
    summary["dimension"] = section::name(d);
  folder.log(format("mesh: %lld %s, degree %d, %lld dofs", (long long)cells,
                    d == section::Dimension::three ? "tetrahedra"
                    : d == section::Dimension::plane
                        ? "triangles (plane strain)"
                        : "triangles (an axisymmetric section: whole-body results)",
                    settings.solid.element.degree, (long long)problem.dofs()));
  humor->describe(summary, folder);
  if (!mesh.probe_names.empty())
    folder.log("step lines: '" + mesh.probe_names[0]
               + " u' is the displacement from the reference (stress-free) geometry [mm], as in "
                 "summary.json and probes.csv; '(frames ...)' is frames.csv's "
                 "apex_displacement_mm, axial, from the start of the dynamics");
}

std::string SolidBlock::identity() const
{
  return problem.forms_signature() + "; " + io::mesh_fingerprint(*mesh.mesh.mesh);
}

// The cavities.

void SolidBlock::inflate(double f)
{
  _open_pressures.assign(problem.cavities(), f * (settings.solid.cavity.iop * mmHg));
  problem.set_cavity_pressures(_open_pressures);
}

void SolidBlock::close() { _closed.emplace(problem, _open_pressures); }

solver::System SolidBlock::system()
{
  if (_dynamic)
    return humor->system(closed(), *_open);
  return _closed ? _closed->system() : _open->system();
}

biomarkers::Columns SolidBlock::cavity_state() const
{
  const auto volumes = problem.cavity_volumes();
  const auto pressures = cavity_pressures();
  // The humor's mean pressure is reported.
  biomarkers::Columns state;
  for (std::size_t c = 0; c < volumes.size(); ++c)
  {
    const double p = pressures[c] + humor->pressure_shift(c);
    state.push_back({mesh.cavity_names[c] + "_pressure_mmHg", p / mmHg});
    state.push_back({mesh.cavity_names[c] + "_volume_mm3", volumes[c]});
  }
  humor->state(mesh.cavity_names, state);
  return state;
}

// The follower pressure on the pressed surface.

void SolidBlock::start_press() { problem.set_press_profile(_press_profile); }

void SolidBlock::press(double f)
{
  _press = f * _press_peak;
  problem.set_press(_press);
}

void SolidBlock::set_load(double t)
{
  problem.set_press(mmHg);
  const double press = _press_peak / mmHg;
  const puff::Load* air = settings.prescribed.get();
  problem.set_press_profile(
      [this, t, press, air](const std::array<double, 3>& X)
      {
        const double p = t < 0 || !air ? 0.0 : (*air)(std::hypot(X[0], X[2]), t);
        return press * _press_profile(X) + p;
      });
}

double SolidBlock::apex_load(double t) const
{
  const puff::Load* air = settings.prescribed.get();
  return t < 0 || !air ? 0.0 : (*air)(0, t);
}

// Dynamics.

void SolidBlock::start_dynamics(const dynamics::TimeStep& step)
{
  if (_dynamic)
    return;
  _dynamic = true;
  problem.start_dynamics(step);
  humor->start();
  open_frames();
}

Stepper::Dynamics SolidBlock::dynamics()
{
  // x holds the solid's u and the humor's unknowns, if any.
  Stepper::Dynamics d{[this](const dynamics::TimeStep& step) { humor->set_time_step(step); },
                      [this] { return problem.load_level(); }, [this] { humor->advance(); }};
  if (humor->predicts())
    d.predict = [this] { humor->predict(); };
  d.error = [this] { return problem.local_error(); };
  return d;
}

void SolidBlock::open_frames()
{
  // The frames of a puff on the eye; a prescribed apex pressure is known
  // at every instant, a computed one is a state column.
  if (!eye || settings.puff == PuffSettings::Load::none)
    return;
  std::vector<std::pair<std::string, std::function<double(double)>>> known;
  if (settings.prescribed)
    known.push_back({"apex_air_pressure_mmHg", [this](double t) { return apex_load(t); }});
  std::vector<std::int32_t> anterior, posterior;
  auto& m = *mesh.mesh.mesh;
  for (auto g : mesh.boundaries.press)
  {
    auto f = mesh.mesh.facets->find(g);
    anterior.insert(anterior.end(), f.begin(), f.end());
  }
  // The posterior cornea: the cavities' wall facets that bound cornea cells.
  const int tdim = m.topology().dim();
  m.topology_mutable().create_connectivity(tdim - 1, tdim);
  const auto f2c = m.topology().connectivity(tdim - 1, tdim);
  std::set<std::int32_t> cornea;
  for (auto& [tag, part] : mesh.parts)
    if (part == "cornea")
      for (auto c : mesh.mesh.cells->find(tag))
        cornea.insert(c);
  for (const auto& walls : mesh.boundaries.cavities)
    for (auto g : walls)
      for (auto f : mesh.mesh.facets->find(g))
        if (cornea.count(f2c->links(f)[0]))
          posterior.push_back(f);
  // Whole-eye motion: the anterior surface's axial displacement at this
  // distance from the axis (docs/physics.md section 9) [mm].
  constexpr double whole_eye_x = 4.0;
  frames.emplace(biomarkers::Section(problem, anterior, "anterior cornea"),
                 biomarkers::Section(problem, posterior, "posterior cornea"),
                 settings.frame_rate, whole_eye_x, known);
}

// The record.

void SolidBlock::open_output(io::RunFolder& folder, nlohmann::json& summary, double t)
{
  if (_output)
    return;
  const auto volumes = problem.cavity_volumes();
  for (std::size_t c = 0; c < volumes.size(); ++c)
    summary[mesh.cavity_names[c] + "_volume_reference_mm3"] = volumes[c];
  for (std::size_t i = 0; i < probes.size(); ++i)
    summary["probe_reference_mm"][mesh.probe_names[i]] = vec(probes[i]);
  _output.emplace(folder, mesh, problem, probes);
  if (settings.fields)
  {
    _output->fields.write(*problem.fields.at("fibre_1"), t);
    _output->fields.write(*problem.fields.at("fibre_2"), t);
  }
  write_fields(t);
}

void SolidBlock::write_fields(double time)
{
  if (!settings.fields)
    return;
  const double t = MPI_Wtime();
  problem.update_von_mises();
  _output->fields.write(*problem.u, time);
  _output->fields.write(*problem.von_mises, time);
  if (_dynamic && _output->humor)
    humor->write(*_output->humor, time);
  _output->t_output += MPI_Wtime() - t;
}

std::vector<std::array<double, 3>> SolidBlock::probe_displacement() const
{
  return _output->probes.displacement();
}

biomarkers::Columns SolidBlock::record(nlohmann::json& step, std::string& text, double time)
{
  const auto cavities = cavity_state();
  const auto u = probe_displacement();
  const auto& names = mesh.probe_names;
  if (!u.empty())
    text += format("  %s u %+.5f %+.5f %+.5f mm", names[0].c_str(), u[0][0], u[0][1], u[0][2]);
  for (std::size_t c = 0; c < mesh.cavity_names.size(); ++c)
    text += format("  %s %.3f mmHg %.4f mm3", mesh.cavity_names[c].c_str(),
                   cavities[2 * c].second, cavities[2 * c + 1].second);
  for (const auto& [name, value] : cavities)
    step[name] = value;
  _probes_csv += format("%.10g,%s", time, step.at("phase").get<std::string>().c_str());
  for (std::size_t i = 0; i < u.size(); ++i)
  {
    step[names[i] + "_displacement_mm"] = vec(u[i]);
    _probes_csv += format(",%.10g,%.10g,%.10g", u[i][0], u[i][1], u[i][2]);
  }
  _probes_csv += "\n";
  write_fields(time);
  return cavities;
}

void SolidBlock::summarise(nlohmann::json& summary) const
{
  const nlohmann::json& steps = summary["steps"];
  const auto& last = steps.back();
  if (eye)
    summary["apex_displacement_mm"] = last["apex_displacement_mm"][1];
  const auto u = probe_displacement();
  for (std::size_t i = 0; i < u.size(); ++i)
    summary["probe_displacement_mm"][mesh.probe_names[i]] = vec(u[i]);
  summary["iop_mmHg"] = settings.solid.cavity.iop;
  summary["cavity_model"] = problem.cavities() == 0      ? "none"
                            : settings.solid.cavity.closed ? "closed"
                                                           : "constant_pressure";
  for (const auto& name : mesh.cavity_names)
  {
    summary[name + "_volume_mm3"] = last[name + "_volume_mm3"];
    summary[name + "_pressure_mmHg"] = last[name + "_pressure_mmHg"];
    double max = 0;
    for (const auto& step : steps)
      max = std::max(max, step[name + "_pressure_mmHg"].get<double>());
    biomarkers::put(summary, name + "_pressure_max_mmHg", max);
  }
  humor->summarise(summary);
}

void SolidBlock::add_frame(double t, double dt, const solver::NewtonReport& report,
                           const biomarkers::Columns& columns, const biomarkers::Columns& cavities)
{
  if (!frames)
    return;
  auto state = cavities;
  state.insert(state.end(), columns.begin(), columns.end());
  state.push_back({"strain_energy_mJ", problem.strain_energy()});
  state.push_back({"kinetic_energy_mJ", problem.kinetic_energy()});
  if (problem.viscoelastic())
    state.push_back({"viscous_work_mJ", problem.viscous_work()});
  humor->energies(state);
  frames->add(t, state,
              {{"dt_ms", dt},
               {"newton_iterations", double(report.iterations)},
               {"residual_N", report.residuals.back()}});
}

void SolidBlock::write_tables() const
{
  if (!_output)
    return;
  auto& folder = _output->folder;
  if (!probes.empty())
  {
    std::string header = "t,phase";
    for (const auto& name : mesh.probe_names)
      header += "," + name + "_ux_mm," + name + "_uy_mm," + name + "_uz_mm";
    folder.write_text("probes.csv", header + "\n" + _probes_csv);
  }
  if (!frames)
    return;
  folder.write_text("steps.csv", frames->steps_csv());
  folder.write_text("frames.csv", frames->frames_csv());
  folder.write_text("profiles.csv", frames->profiles_csv());
}

// Checkpoints.

nlohmann::json SolidBlock::save(io::CheckpointWriter& writer) const
{
  problem.save(writer);
  nlohmann::json state{{"open_pressures", _open_pressures},
                       {"probes_csv", _probes_csv},
                       {"press", _press},
                       {"probes", probes},
                       {"dynamic", _dynamic},
                       {"t_output", t_output()},
                       {"fields", _output ? _output->fields.state() : nlohmann::json()},
                       {"humor_fields", _output && _output->humor ? _output->humor->state()
                                                                  : nlohmann::json()},
                       {"frames", frames ? frames->state() : nlohmann::json()}};
  if (_dynamic)
    state["humor"] = humor->save(writer);
  if (_closed)
    state["closed"] = {{"pressures", _closed->pressures()},
                       {"targets", _closed->targets()},
                       {"forces", _closed->forces()}};
  return state;
}

void SolidBlock::restore(const io::CheckpointReader& checkpoint, const nlohmann::json& state,
                         io::RunFolder& folder)
{
  state.at("open_pressures").get_to(_open_pressures);
  _probes_csv = state.at("probes_csv");
  _press = state.at("press");
  state.at("probes").get_to(probes);
  _dynamic = state.at("dynamic");
  x_imaged.clear();
  inflated.clear();
  problem.restore(checkpoint, _dynamic);
  if (state.contains("closed"))
    _closed.emplace(problem, state["closed"].at("pressures").get<std::vector<double>>(),
                    state["closed"].at("targets").get<std::vector<double>>(),
                    state["closed"].value("forces", std::vector<double>()));
  else if (problem.cavities() > 0)
    problem.set_cavity_pressures(_open_pressures);
  if (_dynamic) // a meshed humor onto the restored wall
    humor->restore(checkpoint, state.value("humor", nlohmann::json()));
  _output.emplace(folder, mesh, problem, probes);
  if (const auto& fields = state.at("fields"); !fields.is_null())
    _output->fields.resume(fields);
  if (const auto humor = state.value("humor_fields", nlohmann::json()); !humor.is_null()
                                                                         && _output->humor)
    _output->humor->resume(humor);
  _output->t_output = state.at("t_output");
  if (_dynamic)
  {
    open_frames();
    if (frames)
      frames->restore(state.at("frames"));
  }
}

} // namespace nct
