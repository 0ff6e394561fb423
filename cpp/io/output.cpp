#include "io/output.h"

#include <iostream>
#include <numeric>

#include <dolfinx/common/IndexMap.h>
#include <dolfinx/io/xdmf_function.h>
#include <dolfinx/io/xdmf_mesh.h>

#include "io/xdmf_series.h"

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

/// A function's series and the Grid holding the mesh its steps include.
struct Fields::File
{
  std::unique_ptr<XdmfSeries> series;
  std::string mesh; ///< the Grid's XPath; empty: none yet with this partition's layout
};

Fields::Fields(const RunFolder& folder, std::shared_ptr<const dolfinx::mesh::Mesh> mesh,
               std::shared_ptr<const dolfinx::fem::FunctionSpace> coordinate_space)
    : _folder(folder), _mesh(std::move(mesh)),
      _coordinate_space(std::move(coordinate_space))
{
}

Fields::~Fields() = default;

Fields::File& Fields::open(const std::string& name, int keep)
{
  auto& file = _files[name];
  file = std::make_unique<File>();
  file->series = std::make_unique<XdmfSeries>(_mesh->comm(), _folder.dir() / (name + ".xdmf"),
                                              name, keep);
  return *file;
}

void Fields::write(const dolfinx::fem::Function<double>& f, double time)
{
  auto it = _files.find(f.name);
  File& file = it == _files.end() ? open(f.name) : *it->second;
  XdmfSeries& series = *file.series;
  MPI_Comm comm = _mesh->comm();
  if (file.mesh.empty() && series.steps() == 0)
  {
    // The first step's mesh: a Grid of its own, as dolfinx's XDMFFile writes it.
    pugi::xml_node domain = series.domain();
    dolfinx::io::xdmf_mesh::add_mesh(comm, domain, series.h5(), *_mesh, "mesh");
    file.mesh = "/Xdmf/Domain/Grid[@Name='mesh'][1]";
  }
  pugi::xml_node grid = series.add_step(time);
  if (file.mesh.empty())
  {
    // Resumed on a partition that lays the mesh out otherwise: in this step.
    const std::string path = "/Mesh/mesh_" + std::to_string(series.steps());
    const int tdim = _mesh->topology().dim();
    std::vector<std::int32_t> cells(_mesh->topology().index_map(tdim)->size_local());
    std::iota(cells.begin(), cells.end(), 0);
    dolfinx::io::xdmf_mesh::add_topology_data(comm, grid, series.h5(), path, _mesh->topology(),
                                              _mesh->geometry(), tdim, cells);
    dolfinx::io::xdmf_mesh::add_geometry_data(comm, grid, series.h5(), path, _mesh->geometry());
    file.mesh = "/Xdmf/Domain/Grid[@CollectionType='Temporal']/Grid["
                + std::to_string(series.steps() + 1) + "]";
  }
  else
    grid.append_child("xi:include").append_attribute("xpointer")
        = ("xpointer(" + file.mesh + "/*[self::Topology or self::Geometry])").c_str();

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

nlohmann::json Fields::state() const
{
  nlohmann::json files = nlohmann::json::object();
  for (const auto& [name, file] : _files)
    files[name] = file->series->steps();
  return {{"layout", layout_fingerprint(*_mesh)}, {"files", files}};
}

void Fields::resume(const nlohmann::json& state)
{
  const bool same_layout = state.at("layout").get<std::uint64_t>() == layout_fingerprint(*_mesh);
  for (const auto& [name, steps] : state.at("files").items())
  {
    File& file = open(name, steps.get<int>());
    // The mesh the last step holds or includes, if this partition lays it out alike.
    if (const int k = file.series->steps(); same_layout && k > 0)
    {
      const std::string pointer
          = file.series->step(k - 1).child("xi:include").attribute("xpointer").value();
      file.mesh = pointer.empty()
                      ? "/Xdmf/Domain/Grid[@CollectionType='Temporal']/Grid["
                            + std::to_string(k) + "]"
                      : pointer.substr(9, pointer.find("/*[") - 9); // xpointer(<mesh>/*[...])
    }
  }
}

} // namespace nct::io
