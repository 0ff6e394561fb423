#include "io/moving_fields.h"

#include <span>

#include <dolfinx/common/IndexMap.h>
#include <dolfinx/common/MPI.h>
#include <dolfinx/fem/DofMap.h>
#include <dolfinx/io/xdmf_utils.h>
#include <pugixml.hpp>

#include "io/xdmf_series.h"

namespace nct::io
{

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
    : _mesh(mesh), _files(folder.dir(), mesh)
{
}

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
  XdmfSeries& series = _files[f.name];
  const std::string step = "/Step/" + std::to_string(series.steps());
  pugi::xml_node grid = series.add_step(time);
  // The topology: written in the first step (on this partition), included by the others.
  if (series.mesh.empty())
    series.add_mesh_to_step(grid, *_mesh, false);
  else
    series.include_mesh(grid, "Topology");

  const std::int64_t offset = geometry.index_map()->local_range()[0];
  const std::int64_t num_nodes = geometry.index_map()->size_global();
  pugi::xml_node geometry_node = grid.append_child("Geometry");
  geometry_node.append_attribute("GeometryType") = "XYZ";
  dolfinx::io::xdmf_utils::add_data_item(geometry_node, series.h5(), step + "/geometry", x,
                                         offset, {num_nodes, 3}, "Float", mpi_io);
  // Doubles: ParaView reads 4-byte floats without both NumberType and Precision.
  geometry_node.child("DataItem").append_attribute("Precision") = 8;

  pugi::xml_node attribute = grid.append_child("Attribute");
  attribute.append_attribute("Name") = f.name.c_str();
  attribute.append_attribute("AttributeType") = width == 1 ? "Scalar" : "Vector";
  attribute.append_attribute("Center") = "Node";
  dolfinx::io::xdmf_utils::add_data_item(attribute, series.h5(), step + "/values", values, offset,
                                         {num_nodes, width}, "Float", mpi_io);
  attribute.child("DataItem").append_attribute("Precision") = 8;
  series.commit();
}

nlohmann::json MovingFields::state() const { return _files.state(); }

void MovingFields::resume(const nlohmann::json& state) { _files.resume(state); }

} // namespace nct::io
