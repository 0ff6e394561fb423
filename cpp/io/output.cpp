#include "io/output.h"

#include <iostream>

#include <dolfinx/io/xdmf_function.h>
#include <dolfinx/io/xdmf_mesh.h>

namespace nct::io
{

void write_atomic(const std::filesystem::path& file, const std::string& text)
{
  auto tmp = file;
  tmp += ".tmp";
  {
    std::ofstream f(tmp);
    f << text;
    if (!f.good())
      throw std::runtime_error("cannot write " + tmp.string());
  }
  std::filesystem::rename(tmp, file);
}

RunFolder::RunFolder(MPI_Comm comm, std::filesystem::path dir, bool append)
    : _comm(comm), _dir(std::move(dir))
{
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  int ok = 1;
  if (rank == 0)
  {
    std::error_code ec;
    std::filesystem::create_directories(_dir, ec);
    _log.open(_dir / "run.log", append ? std::ios::app : std::ios::out);
    ok = !ec && _log.good();
  }
  MPI_Bcast(&ok, 1, MPI_INT, 0, comm);
  if (!ok)
    throw std::runtime_error("cannot create the run folder " + _dir.string());
}

void RunFolder::write_text(const std::string& name, const std::string& text) const
{
  int rank = 0;
  MPI_Comm_rank(_comm, &rank);
  if (rank != 0)
    return;
  write_atomic(_dir / name, text);
}

void RunFolder::log(const std::string& line)
{
  int rank = 0;
  MPI_Comm_rank(_comm, &rank);
  if (rank != 0)
    return;
  std::cout << line << std::endl;
  _log << line << std::endl;
}

Fields::Fields(const RunFolder& folder, std::shared_ptr<const dolfinx::mesh::Mesh> mesh,
               std::shared_ptr<const dolfinx::fem::FunctionSpace> coordinate_space)
    : _mesh(mesh), _coordinate_space(std::move(coordinate_space)), _files(folder.dir(), mesh)
{
}

void Fields::write(const dolfinx::fem::Function<double>& f, double time)
{
  XdmfSeries& series = _files[f.name];
  MPI_Comm comm = _mesh->comm();
  if (series.mesh.empty() && series.steps() == 0)
  {
    // The first step's mesh: a Grid of its own, as dolfinx's XDMFFile writes it.
    pugi::xml_node domain = series.domain();
    dolfinx::io::xdmf_mesh::add_mesh(comm, domain, series.h5(), *_mesh, "mesh");
    series.mesh = "/Xdmf/Domain/Grid[@Name='mesh'][1]";
  }
  pugi::xml_node grid = series.add_step(time);
  if (series.mesh.empty()) // resumed on a partition that lays the mesh out otherwise
    series.add_mesh_to_step(grid, *_mesh, true);
  else
    series.include_mesh(grid, "*[self::Topology or self::Geometry]");

  // Scalar or vector, on the coordinate element's nodes (P1) or not.
  const auto& element = *f.function_space()->element();
  const auto& coordinates = *_coordinate_space->element();
  const bool dg0 = element.space_dimension() / element.block_size() == 1;
  const bool on_coordinates
      = element.family() == coordinates.family()
        && element.space_dimension() / element.block_size()
               == coordinates.space_dimension() / coordinates.block_size();
  if (dg0 || on_coordinates)
    dolfinx::io::xdmf_function::add_function(comm, f, time, grid, series.h5());
  else
  {
    if (element.value_size() == 1 && !_scalar_space)
      _scalar_space = std::make_shared<dolfinx::fem::FunctionSpace>(
          _coordinate_space->sub({0})->collapse().first);
    dolfinx::fem::Function<double> g(element.value_size() == 1 ? _scalar_space
                                                                : _coordinate_space);
    g.name = f.name;
    g.interpolate(f);
    dolfinx::io::xdmf_function::add_function(comm, g, time, grid, series.h5());
  }
  series.commit();
}

nlohmann::json Fields::state() const { return _files.state(); }

void Fields::resume(const nlohmann::json& state) { _files.resume(state); }

} // namespace nct::io
