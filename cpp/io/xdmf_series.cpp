#include "io/xdmf_series.h"

#include <algorithm>
#include <charconv>
#include <numeric>
#include <set>
#include <sstream>
#include <vector>

#include <dolfinx/common/IndexMap.h>
#include <dolfinx/common/MPI.h>
#include <dolfinx/io/HDF5Interface.h>
#include <dolfinx/io/xdmf_mesh.h>
#include <dolfinx/io/xdmf_utils.h>

#include "io/checkpoint.h"
#include "io/output.h"

namespace nct::io
{

using dolfinx::io::HDF5Interface;

std::uint64_t layout_fingerprint(const dolfinx::mesh::Mesh& mesh)
{
  const auto& geometry = mesh.geometry();
  const auto& nodes = *geometry.index_map();
  const std::int64_t first = nodes.local_range()[0];
  const auto& ghosts = nodes.ghosts();
  const auto& input = geometry.input_global_indices();
  std::uint64_t sum = 0;
  for (std::int32_t i = 0; i < nodes.size_local(); ++i)
  {
    const std::int64_t pair[2] = {first + i, input[i]};
    sum += fnv1a(pair, sizeof(pair));
  }
  const auto& cells = *mesh.topology().index_map(mesh.topology().dim());
  const auto& dofmap = geometry.dofmap();
  std::vector<std::int64_t> cell;
  for (std::int32_t c = 0; c < cells.size_local(); ++c)
  {
    cell.assign(1, cells.local_range()[0] + c);
    for (auto n : dofmap.links(c))
      cell.push_back(n < nodes.size_local() ? first + n : ghosts[n - nodes.size_local()]);
    sum += fnv1a(cell.data(), cell.size() * sizeof(std::int64_t));
  }
  MPI_Allreduce(MPI_IN_PLACE, &sum, 1, MPI_UINT64_T, MPI_SUM, mesh.comm());
  return sum;
}

namespace
{

/// Every dataset in an HDF5 file, by path.
std::vector<std::string> datasets(hid_t file)
{
  std::vector<std::string> all;
  auto visit = [](hid_t group, const char* name, const H5L_info_t*, void* data) -> herr_t
  {
    const hid_t object = H5Oopen(group, name, H5P_DEFAULT);
    if (object < 0)
      return -1;
    if (H5Iget_type(object) == H5I_DATASET)
      static_cast<std::vector<std::string>*>(data)->push_back(std::string("/") + name);
    H5Oclose(object);
    return 0;
  };
  if (H5Lvisit(file, H5_INDEX_NAME, H5_ITER_NATIVE, visit, &all) < 0)
    throw std::runtime_error("cannot list its datasets");
  return all;
}

/// Cut the series `name` in `xdmf` back to its first `keep` steps (see
/// XdmfSeries); returns the XML kept.
std::string cut(const std::filesystem::path& xdmf, const std::string& name, int keep)
{
  pugi::xml_document xml;
  if (!xml.load_file(xdmf.c_str()))
    throw std::runtime_error("cannot read its XML");
  const std::string path = "/Xdmf/Domain/Grid[@CollectionType='Temporal'][@Name='" + name + "']";
  pugi::xml_node series = xml.select_node(path.c_str()).node();
  std::vector<pugi::xml_node> steps;
  for (auto grid : series.children("Grid"))
    steps.push_back(grid);
  if (int(steps.size()) < keep)
    throw std::runtime_error("it holds " + std::to_string(steps.size())
                             + " steps, the checkpoint " + std::to_string(keep));
  for (std::size_t k = keep; k < steps.size(); ++k)
    series.remove_child(steps[k]);

  // The top-level Grids (meshes) that no kept step includes.
  std::vector<std::string> includes;
  for (auto grid : series.children("Grid"))
    for (auto include : grid.children("xi:include"))
      includes.push_back(include.attribute("xpointer").value());
  std::vector<pugi::xml_node> unused;
  for (auto grid : xml.child("Xdmf").child("Domain").children("Grid"))
  {
    const std::string key = "[@Name='" + std::string(grid.attribute("Name").value()) + "']";
    if (grid != series
        && std::none_of(includes.begin(), includes.end(),
                        [&](const std::string& x) { return x.find(key) != std::string::npos; }))
      unused.push_back(grid);
  }
  for (auto grid : unused)
    grid.parent().remove_child(grid);

  // The datasets the kept XML refers to ("file.h5:/path"), and the rest deleted.
  std::set<std::string> referred;
  for (auto item : xml.select_nodes("//DataItem[@Format='HDF']"))
  {
    const std::string text = item.node().child_value();
    referred.insert(text.substr(text.rfind(':') + 1));
  }
  const auto h5 = dolfinx::io::xdmf_utils::get_hdf5_filename(xdmf);
  const hid_t file = H5Fopen(h5.c_str(), H5F_ACC_RDWR, H5P_DEFAULT);
  if (file < 0)
    throw std::runtime_error("cannot open " + h5.string()
                             + " (damaged by the interruption? move both files aside "
                               "to resume with this series starting anew)");
  try
  {
    for (const auto& dataset : datasets(file))
      if (!referred.count(dataset) && H5Ldelete(file, dataset.c_str(), H5P_DEFAULT) < 0)
        throw std::runtime_error("cannot delete " + dataset + " from " + h5.string());
  }
  catch (...)
  {
    H5Fclose(file);
    throw;
  }
  if (H5Fclose(file) < 0)
    throw std::runtime_error("cannot write " + h5.string());
  std::ostringstream text;
  xml.save(text, "  ");
  write_atomic(xdmf, text.str());
  return text.str();
}

} // namespace

XdmfSeries::XdmfSeries(MPI_Comm comm, std::filesystem::path xdmf, const std::string& name,
                       int keep)
    : _comm(comm), _xdmf(std::move(xdmf)), _name(name)
{
  const int rank = dolfinx::MPI::rank(comm);
  // Rank 0 cuts a resumed series; every rank gets its XML.
  std::string text, error;
  if (keep >= 0 && rank == 0 && std::filesystem::exists(_xdmf))
  {
    try
    {
      text = cut(_xdmf, name, keep);
    }
    catch (const std::exception& e)
    {
      error = "cannot continue the fields file " + _xdmf.string() + ": " + e.what();
    }
  }
  std::int64_t sizes[2] = {std::int64_t(text.size()), std::int64_t(error.size())};
  MPI_Bcast(sizes, 2, MPI_INT64_T, 0, comm);
  text.resize(sizes[0]);
  error.resize(sizes[1]);
  MPI_Bcast(text.data(), sizes[0], MPI_CHAR, 0, comm);
  MPI_Bcast(error.data(), sizes[1], MPI_CHAR, 0, comm);
  if (!error.empty())
    throw CheckpointError(error);

  const bool fresh = text.empty();
  if (fresh)
  {
    _xml.append_child(pugi::node_doctype).set_value("Xdmf SYSTEM \"Xdmf.dtd\" []");
    pugi::xml_node root = _xml.append_child("Xdmf");
    root.append_attribute("Version") = "3.0";
    root.append_attribute("xmlns:xi") = "http://www.w3.org/2001/XInclude";
    root.append_child("Domain");
  }
  else
    _xml.load_string(text.c_str());
  const std::string path = "/Xdmf/Domain/Grid[@CollectionType='Temporal'][@Name='" + name + "']";
  _series = _xml.select_node(path.c_str()).node();
  for (auto grid : _series.children("Grid"))
    ++_steps, (void)grid;
  // The mesh the last step holds or includes (xpointer(<mesh>/<what>)).
  if (_steps > 0)
  {
    pugi::xml_node last = step(_steps - 1);
    const std::string pointer = last.child("xi:include").attribute("xpointer").value();
    mesh = last.child("Topology") ? step_path(_steps - 1)
                                  : pointer.substr(9, pointer.rfind('/') - 9);
  }
  _h5 = HDF5Interface::open_file(comm, dolfinx::io::xdmf_utils::get_hdf5_filename(_xdmf),
                                 fresh ? "w" : "a", dolfinx::MPI::size(comm) > 1);
}

XdmfSeries::~XdmfSeries()
{
  if (_h5 >= 0)
    HDF5Interface::close_file(_h5);
}

pugi::xml_node XdmfSeries::step(int k) const
{
  auto grid = _series.child("Grid");
  for (int i = 0; i < k; ++i)
    grid = grid.next_sibling("Grid");
  return grid;
}

pugi::xml_node XdmfSeries::add_step(double time)
{
  if (!_series)
  {
    // After what the Domain holds already (a mesh), as dolfinx's XDMFFile writes it.
    _series = domain().append_child("Grid");
    _series.append_attribute("Name") = _name.c_str();
    _series.append_attribute("GridType") = "Collection";
    _series.append_attribute("CollectionType") = "Temporal";
  }
  pugi::xml_node grid = _series.append_child("Grid");
  grid.append_attribute("Name") = _name.c_str();
  grid.append_attribute("GridType") = "Uniform";
  char t[32];
  *std::to_chars(t, t + sizeof(t) - 1, time).ptr = '\0';
  grid.append_child("Time").append_attribute("Value") = t;
  return grid;
}

std::string XdmfSeries::step_path(int k) const
{
  return "/Xdmf/Domain/Grid[@CollectionType='Temporal']/Grid[" + std::to_string(k + 1) + "]";
}

void XdmfSeries::add_mesh_to_step(pugi::xml_node grid, const dolfinx::mesh::Mesh& m,
                                  bool geometry)
{
  const std::string path = "/Step/" + std::to_string(_steps);
  const int tdim = m.topology().dim();
  std::vector<std::int32_t> cells(m.topology().index_map(tdim)->size_local());
  std::iota(cells.begin(), cells.end(), 0);
  dolfinx::io::xdmf_mesh::add_topology_data(_comm, grid, _h5, path, m.topology(), m.geometry(),
                                            tdim, cells);
  if (geometry)
    dolfinx::io::xdmf_mesh::add_geometry_data(_comm, grid, _h5, path, m.geometry());
  mesh = step_path(_steps);
}

void XdmfSeries::include_mesh(pugi::xml_node grid, const std::string& what)
{
  grid.append_child("xi:include").append_attribute("xpointer")
      = ("xpointer(" + mesh + "/" + what + ")").c_str();
}

void XdmfSeries::commit()
{
  // The data on disk before the XML that refers to it.
  HDF5Interface::flush_file(_h5);
  ++_steps;
  if (dolfinx::MPI::rank(_comm) == 0)
  {
    std::ostringstream text;
    _xml.save(text, "  ");
    write_atomic(_xdmf, text.str());
  }
}

XdmfFiles::XdmfFiles(std::filesystem::path dir, std::shared_ptr<const dolfinx::mesh::Mesh> mesh)
    : _dir(std::move(dir)), _mesh(std::move(mesh))
{
}

XdmfSeries& XdmfFiles::open(const std::string& name, int keep)
{
  auto& series = _series[name];
  series = std::make_unique<XdmfSeries>(_mesh->comm(), _dir / (name + ".xdmf"), name, keep);
  return *series;
}

XdmfSeries& XdmfFiles::operator[](const std::string& name)
{
  auto it = _series.find(name);
  return it == _series.end() ? open(name, -1) : *it->second;
}

nlohmann::json XdmfFiles::state() const
{
  nlohmann::json files = nlohmann::json::object();
  for (const auto& [name, series] : _series)
    files[name] = series->steps();
  return {{"layout", layout()}, {"files", files}};
}

std::uint64_t XdmfFiles::layout() const
{
  if (!_layout)
    _layout = layout_fingerprint(*_mesh);
  return *_layout;
}

void XdmfFiles::resume(const nlohmann::json& state)
{
  const bool same_layout = state.at("layout").get<std::uint64_t>() == layout();
  for (const auto& [name, steps] : state.at("files").items())
  {
    XdmfSeries& series = open(name, steps.get<int>());
    if (!same_layout)
      series.mesh.clear();
  }
}

} // namespace nct::io
