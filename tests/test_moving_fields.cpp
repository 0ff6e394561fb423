// io::MovingFields: XDMF time series on a moving mesh. Three steps of a
// scalar and a vector on a box whose displacement changes per step, read
// back from the HDF5 file: each step's geometry is the reference plus the
// displacement, the values are the function's, the mesh is left alone; a
// field that is not P1 is refused.
#include <array>
#include <cmath>
#include <functional>
#include <numeric>
#include <gtest/gtest.h>
#include <pugixml.hpp>

#include <dolfinx/common/IndexMap.h>
#include <dolfinx/fem/utils.h>
#include <dolfinx/io/HDF5Interface.h>
#include <dolfinx/mesh/generation.h>

#include "helpers.h"
#include "io/moving_fields.h"
#include "mesh_motion_p1_full.h"
#include "solid_p1_full.h"

namespace
{

using Field = std::function<std::array<double, 3>(double, double, double)>;

/// The displacement at step s and two fields on the moving mesh.
std::array<double, 3> displacement(int s, double x, double y, double z)
{
  return {0.1 * (s + 1) * y * z, 0.2 * (s + 1) * std::sin(x), -0.3 * s * x * x};
}
double scalar(int s, double x, double y, double z) { return s + x + 2 * y + 3 * z; }
std::array<double, 3> vector(int s, double x, double y, double z) { return {x, -y, s * z}; }

/// A dof numbering unlike the geometry nodes' (the reverse of the
/// unreordered one): with dolfinx's default both are alike on a box.
std::vector<int> reverse(const dolfinx::graph::AdjacencyList<std::int32_t>& graph)
{
  std::vector<int> order(graph.num_nodes());
  std::iota(order.rbegin(), order.rend(), 0);
  return order;
}

/// Set `f` (P1) to `value` at its nodes, ghosts included.
void set(dolfinx::fem::Function<double>& f, const Field& value)
{
  const auto X = f.function_space()->tabulate_dof_coordinates(false);
  const int bs = f.function_space()->dofmap()->bs();
  auto u = f.x()->mutable_array();
  for (std::size_t i = 0; i < X.size() / 3; ++i)
  {
    const auto v = value(X[3 * i], X[3 * i + 1], X[3 * i + 2]);
    std::copy_n(v.begin(), bs, u.begin() + bs * i);
  }
}

} // namespace

TEST(MovingFields, GeometryAndValuesPerStep)
{
  auto mesh = std::make_shared<dolfinx::mesh::Mesh>(dolfinx::mesh::create_box(
      MPI_COMM_WORLD, {{{0, 0, 0}, {1, 2, 1}}}, {3, 4, 2}, dolfinx::mesh::CellType::tetrahedron,
      dolfinx::mesh::GhostMode::none));
  auto V = std::make_shared<dolfinx::fem::FunctionSpace>(dolfinx::fem::create_functionspace(
      functionspace_form_mesh_motion_p1_full_R_harmonic, "d", mesh, reverse));
  auto S = std::make_shared<dolfinx::fem::FunctionSpace>(dolfinx::fem::create_functionspace(
      functionspace_form_solid_p1_full_R, "press_profile", mesh, reverse));
  dolfinx::fem::Function<double> d(V), v(V), p(S);
  v.name = "velocity";
  p.name = "pressure";

  const auto dir = nct::test::out_dir("moving_fields");
  const std::vector<double> X(mesh->geometry().x().begin(), mesh->geometry().x().end());
  const std::array<double, 3> times = {0, 0.25, 0.5};
  {
    nct::io::RunFolder folder(MPI_COMM_WORLD, dir);
    nct::io::MovingFields fields(folder, mesh);
    // A DG0 field is refused before anything is written.
    dolfinx::fem::Function<double> c10(std::make_shared<dolfinx::fem::FunctionSpace>(
        dolfinx::fem::create_functionspace(functionspace_form_solid_p1_full_R, "c10", mesh)));
    c10.name = "c10";
    EXPECT_THROW(fields.write(c10, d, 0), std::runtime_error);
    EXPECT_FALSE(std::filesystem::exists(dir / "c10.h5"));
    for (int s = 0; s < 3; ++s)
    {
      set(d, [s](double x, double y, double z) { return displacement(s, x, y, z); });
      set(v, [s](double x, double y, double z) { return vector(s, x, y, z); });
      set(p, [s](double x, double y, double z)
          { return std::array<double, 3>{scalar(s, x, y, z), 0, 0}; });
      fields.write(p, d, times[s]);
      fields.write(v, d, times[s]);
    }
  }
  EXPECT_EQ(X, std::vector<double>(mesh->geometry().x().begin(), mesh->geometry().x().end()));

  // The XML: one Temporal collection of three Grids, the topology in the
  // first and included by the others.
  MPI_Barrier(MPI_COMM_WORLD);
  for (std::string name : {"pressure", "velocity"})
  {
    pugi::xml_document xml;
    ASSERT_TRUE(xml.load_file((dir / (name + ".xdmf")).c_str())) << name;
    auto series = xml.select_nodes("/Xdmf/Domain/Grid[@CollectionType='Temporal']/Grid");
    ASSERT_EQ(series.size(), 3u);
    EXPECT_EQ(xml.select_nodes("/Xdmf/Domain/*").size(), 1u);
    EXPECT_EQ(xml.select_nodes("//Topology").size(), 1u);
    for (int s = 0; s < 3; ++s)
    {
      auto grid = series[s].node();
      EXPECT_EQ(grid.child("Time").attribute("Value").as_double(), times[s]);
      EXPECT_EQ(grid.child("Topology").empty(), s > 0);
      EXPECT_EQ(grid.child("xi:include").empty(), s == 0);
      EXPECT_EQ(std::string(grid.child("Geometry").child_value("DataItem")),
                name + ".h5:/Step/" + std::to_string(s) + "/geometry");
    }
  }

  // The HDF5 data at this rank's nodes.
  const auto& nodes = *mesh->geometry().index_map();
  const std::int64_t offset = nodes.local_range()[0];
  using dolfinx::io::HDF5Interface;
  for (std::string name : {"pressure", "velocity"})
  {
    const hid_t h5 = HDF5Interface::open_file(MPI_COMM_SELF, dir / (name + ".h5"), "r", false);
    EXPECT_EQ(HDF5Interface::get_dataset_shape(h5, "/Step/0/topology"),
              (std::vector<std::int64_t>{3 * 4 * 2 * 6, 4}));
    const std::size_t width = name == "pressure" ? 1 : 3;
    for (int s = 0; s < 3; ++s)
    {
      const std::string step = "/Step/" + std::to_string(s);
      const auto x = HDF5Interface::read_dataset<double>(h5, step + "/geometry", {-1, -1});
      const auto u = HDF5Interface::read_dataset<double>(h5, step + "/values", {-1, -1});
      ASSERT_EQ(x.size(), 3 * nodes.size_global());
      ASSERT_EQ(u.size(), width * nodes.size_global());
      for (std::int32_t i = 0; i < nodes.size_local(); ++i)
      {
        const double* Xi = &X[3 * i];
        const double* xi = &x[3 * (offset + i)];
        const double* ui = &u[width * (offset + i)];
        const auto di = displacement(s, Xi[0], Xi[1], Xi[2]);
        for (int j = 0; j < 3; ++j)
          ASSERT_NEAR(xi[j], Xi[j] + di[j], 1e-14) << name << " step " << s << " node " << i;
        if (width == 1)
          ASSERT_NEAR(ui[0], scalar(s, Xi[0], Xi[1], Xi[2]), 1e-14);
        else
        {
          const auto vi = vector(s, Xi[0], Xi[1], Xi[2]);
          for (int j = 0; j < 3; ++j)
            ASSERT_NEAR(ui[j], vi[j], 1e-14) << name << " step " << s << " node " << i;
        }
      }
    }
    HDF5Interface::close_file(h5);
  }
}
