#include "io/moving_fields.h"

#include <charconv>
#include <numeric>
#include <sstream>

#include <dolfinx/common/IndexMap.h>
#include <dolfinx/common/MPI.h>
#include <dolfinx/fem/DofMap.h>
#include <dolfinx/io/HDF5Interface.h>
#include <dolfinx/io/xdmf_mesh.h>
#include <dolfinx/io/xdmf_utils.h>
#include <pugixml.hpp>

namespace nct::io
{

using dolfinx::io::HDF5Interface;

struct MovingFields::File
{
  hid_t h5 = -1;
  pugi::xml_document xml;
  pugi::xml_node series; ///< the Temporal collection of Grids
  int steps = 0;
  ~File()
  {
    if (h5 >= 0)
      HDF5Interface::close_file(h5);
  }
};

namespace
{

/// The values of `f` (continuous P1 on `mesh`, block size at most `width`)
/// at the mesh's owned geometry nodes, `width` per node, zero-padded. A P1
/// dof and a geometry node are the same local vertex of a cell.
std::vector<double> node_values(const dolfinx::fem::Function<double>& f,
                                const dolfinx::mesh::Mesh& mesh, int width)
{
  const auto& space = *f.function_space();
  const auto& dofmap = *space.dofmap();
  const auto& x_dofmap = mesh.geometry().dofmap();
  const auto& nodes = *mesh.geometry().index_map();
  const int bs = dofmap.bs();
  if (space.mesh().get() != &mesh || dofmap.index_map->size_global() != nodes.size_global()
      || bs > width)
    throw std::runtime_error("io::MovingFields: '" + f.name
                             + "' is not a continuous P1 scalar or vector on the mesh");
  std::span<const double> u = f.x()->array();
  std::vector<double> values(width * nodes.size_local(), 0.0);
  for (std::int32_t c = 0; c < x_dofmap.num_nodes(); ++c)
  {
    auto cell_nodes = x_dofmap.links(c);
    auto cell_dofs = dofmap.cell_dofs(c);
    for (std::size_t i = 0; i < cell_nodes.size(); ++i)
      if (cell_nodes[i] < nodes.size_local())
        std::copy_n(u.begin() + bs * cell_dofs[i], bs, values.begin() + width * cell_nodes[i]);
  }
  return values;
}

} // namespace

MovingFields::MovingFields(const RunFolder& folder,
                           std::shared_ptr<const dolfinx::mesh::Mesh> mesh)
    : _folder(folder), _mesh(std::move(mesh))
{
}

MovingFields::~MovingFields() = default;

void MovingFields::write(const dolfinx::fem::Function<double>& f,
                         const dolfinx::fem::Function<double>& displacement, double time)
{
  // The displaced nodes x = X + d and f's values at them, first: they check the input.
  const auto& geometry = _mesh->geometry();
  std::vector<double> x = node_values(displacement, *_mesh, 3);
  std::span<const double> X = geometry.x();
  for (std::size_t i = 0; i < x.size(); ++i)
    x[i] += X[i];
  const int width = f.function_space()->dofmap()->bs() == 1 ? 1 : 3;
  const std::vector<double> values = node_values(f, *_mesh, width);

  MPI_Comm comm = _mesh->comm();
  const bool mpi_io = dolfinx::MPI::size(comm) > 1;
  const auto xdmf = _folder.dir() / (f.name + ".xdmf");
  auto& file = _files[f.name];
  if (!file)
  {
    file = std::make_unique<File>();
    file->h5 = HDF5Interface::open_file(comm, dolfinx::io::xdmf_utils::get_hdf5_filename(xdmf),
                                        "w", mpi_io);
    file->xml.append_child(pugi::node_doctype).set_value("Xdmf SYSTEM \"Xdmf.dtd\" []");
    pugi::xml_node root = file->xml.append_child("Xdmf");
    root.append_attribute("Version") = "3.0";
    root.append_attribute("xmlns:xi") = "http://www.w3.org/2001/XInclude";
    file->series = root.append_child("Domain").append_child("Grid");
    file->series.append_attribute("Name") = f.name.c_str();
    file->series.append_attribute("GridType") = "Collection";
    file->series.append_attribute("CollectionType") = "Temporal";
  }

  pugi::xml_node grid = file->series.append_child("Grid");
  grid.append_attribute("Name") = f.name.c_str();
  grid.append_attribute("GridType") = "Uniform";
  char t[32];
  *std::to_chars(t, t + sizeof(t) - 1, time).ptr = '\0';
  grid.append_child("Time").append_attribute("Value") = t;

  // The topology: written in the first step, included by the others.
  if (file->steps == 0)
  {
    const int tdim = _mesh->topology().dim();
    std::vector<std::int32_t> cells(_mesh->topology().index_map(tdim)->size_local());
    std::iota(cells.begin(), cells.end(), 0);
    dolfinx::io::xdmf_mesh::add_topology_data(comm, grid, file->h5, "/Mesh", _mesh->topology(),
                                              geometry, tdim, cells);
  }
  else
    grid.append_child("xi:include").append_attribute("xpointer")
        = "xpointer(/Xdmf/Domain/Grid/Grid[1]/Topology)";

  const std::string step = "/Step/" + std::to_string(file->steps);
  const std::int64_t offset = geometry.index_map()->local_range()[0];
  const std::int64_t num_nodes = geometry.index_map()->size_global();
  pugi::xml_node geometry_node = grid.append_child("Geometry");
  geometry_node.append_attribute("GeometryType") = "XYZ";
  dolfinx::io::xdmf_utils::add_data_item(geometry_node, file->h5, step + "/geometry", x, offset,
                                         {num_nodes, 3}, "Float", mpi_io);
  // Doubles: ParaView reads 4-byte floats without both NumberType and Precision.
  geometry_node.child("DataItem").append_attribute("Precision") = 8;

  pugi::xml_node attribute = grid.append_child("Attribute");
  attribute.append_attribute("Name") = f.name.c_str();
  attribute.append_attribute("AttributeType") = width == 1 ? "Scalar" : "Vector";
  attribute.append_attribute("Center") = "Node";
  dolfinx::io::xdmf_utils::add_data_item(attribute, file->h5, step + "/values", values, offset,
                                         {num_nodes, width}, "Float", mpi_io);
  attribute.child("DataItem").append_attribute("Precision") = 8;

  // The data on disk before the XML that refers to it.
  HDF5Interface::flush_file(file->h5);
  ++file->steps;
  if (dolfinx::MPI::rank(comm) == 0)
  {
    std::ostringstream text;
    file->xml.save(text, "  ");
    write_atomic(xdmf, text.str());
  }
}

} // namespace nct::io
