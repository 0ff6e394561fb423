#include "meshio/model.h"

#include <dolfinx/geometry/BoundingBoxTree.h>
#include <dolfinx/geometry/utils.h>

#include <gmsh.h>
#include <algorithm>
#include <cmath>
#include <array>
#include <set>
#include <map>
#include <limits>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include <dolfinx/fem/CoordinateElement.h>
#include <dolfinx/graph/AdjacencyList.h>
#include <dolfinx/io/xdmf_utils.h>
#include <dolfinx/mesh/utils.h>

namespace nct::meshio
{
namespace
{

int rank(MPI_Comm comm)
{
  int r = 0;
  MPI_Comm_rank(comm, &r);
  return r;
}

/// Elements of one gmsh type on every entity of a physical group.
void group_elements(int dim, int group, int type,
                    std::vector<std::size_t>& nodes)
{
  std::vector<int> entities;
  gmsh::model::getEntitiesForPhysicalGroup(dim, group, entities);
  for (int e : entities)
  {
    std::vector<std::size_t> tags, enodes;
    gmsh::model::mesh::getElementsByType(type, tags, enodes, e);
    nodes.insert(nodes.end(), enodes.begin(), enodes.end());
  }
}

/// Vertices around which the cells (`nv` vertices each) are not connected
/// through facets that contain the vertex: two bodies touching along an
/// edge or at a point.
std::vector<bool> non_manifold_vertices(const std::vector<std::int64_t>& cells, int nv,
                                        std::size_t num_vertices)
{
  std::vector<std::vector<std::size_t>> vertex_cells(num_vertices);
  for (std::size_t c = 0; c < cells.size() / nv; ++c)
    for (int i = 0; i < nv; ++i)
      vertex_cells[cells[nv * c + i]].push_back(c);
  std::vector<bool> flagged(num_vertices, false);
  for (std::size_t v = 0; v < num_vertices; ++v)
  {
    // Union-find over v's cells, joined through the faces that contain v.
    const auto& vc = vertex_cells[v];
    std::vector<std::size_t> up(vc.size());
    std::iota(up.begin(), up.end(), 0);
    auto find = [&](std::size_t i)
    {
      while (up[i] != i)
        i = up[i] = up[up[i]];
      return i;
    };
    // A facet through v, by its other vertices (nv - 2 of them; -1 pads).
    std::map<std::array<std::int64_t, 2>, std::size_t> faces;
    for (std::size_t k = 0; k < vc.size(); ++k)
    {
      std::array<std::int64_t, 3> others;
      for (int i = 0, j = 0; i < nv; ++i)
        if (cells[nv * vc[k] + i] != static_cast<std::int64_t>(v))
          others[j++] = cells[nv * vc[k] + i];
      for (int skip = 0; skip < nv - 1; ++skip)
      {
        std::array<std::int64_t, 2> f{-1, -1};
        for (int i = 0, j = 0; i < nv - 1; ++i)
          if (i != skip)
            f[j++] = others[i];
        std::sort(f.begin(), f.end());
        if (auto [it, fresh] = faces.emplace(f, k); !fresh)
          up[find(k)] = find(it->second);
      }
    }
    std::size_t clusters = 0;
    for (std::size_t k = 0; k < vc.size(); ++k)
      clusters += find(k) == k;
    flagged[v] = clusters > 1;
  }
  return flagged;
}

/// Sort a facet's first n (2 or 3) nodes; the rest stay -1.
void sort_facet(std::array<std::int64_t, 3>& f, int n)
{
  if (n == 3)
    std::sort(f.begin(), f.end());
  else if (f[0] > f[1])
    std::swap(f[0], f[1]);
}

/// The facet of a cell `v` (nv node indices) opposite its node k, sorted
/// (-1 pads a triangle's edge).
std::array<std::int64_t, 3> face(const std::int64_t* v, int nv, int k)
{
  std::array<std::int64_t, 3> f{-1, -1, -1};
  for (int i = 0, j = 0; i < nv; ++i)
    if (i != k)
      f[j++] = v[i];
  sort_facet(f, nv - 1);
  return f;
}

/// Model's facet f as face() gives it: its nodes sorted, -1 padded.
std::array<std::int64_t, 3> facet_key(const Model& model, std::size_t f)
{
  const int nf = model.groups.dimension;
  std::array<std::int64_t, 3> key{-1, -1, -1};
  std::copy_n(model.facets.begin() + nf * f, nf, key.begin());
  sort_facet(key, nf);
  return key;
}

/// The normal (not unit) of a facet with the geometry nodes `nodes`: a
/// triangle's (fdim 2), a segment's in the plane z = 0 (fdim 1).
std::array<double, 3> facet_normal(std::span<const double> x, const std::int32_t* nodes,
                                   int fdim)
{
  std::array<double, 3> a, b{0, 0, 1};
  for (int j = 0; j < 3; ++j)
  {
    a[j] = x[3 * nodes[1] + j] - x[3 * nodes[0] + j];
    if (fdim == 2)
      b[j] = x[3 * nodes[2] + j] - x[3 * nodes[0] + j];
  }
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}

} // namespace

std::string broadcast(MPI_Comm comm, std::string s)
{
  std::uint64_t n = s.size();
  MPI_Bcast(&n, 1, MPI_UINT64_T, 0, comm);
  s.resize(n);
  MPI_Bcast(s.data(), static_cast<int>(n), MPI_CHAR, 0, comm);
  return s;
}

Groups groups_of_current_model(MPI_Comm comm)
{
  std::ostringstream s;
  if (rank(comm) == 0)
  {
    gmsh::vectorpair groups;
    gmsh::model::getPhysicalGroups(groups);
    const int cell_dim = gmsh::model::getDimension() == 2 ? 2 : 3;
    s << "dimension " << cell_dim << '\n';
    std::array<double, 6> b;
    gmsh::model::getBoundingBox(-1, -1, b[0], b[1], b[2], b[3], b[4], b[5]);
    s.precision(17);
    s << "bounds";
    for (double v : b)
      s << ' ' << v;
    s << '\n';
    for (auto [dim, tag] : groups)
    {
      std::string name;
      gmsh::model::getPhysicalName(dim, tag, name);
      if (name.empty())
        name = "group_" + std::to_string(tag);
      s << dim << ' ' << tag << ' ' << name << '\n';
    }
    // The volume groups on either side of each surface group's entities.
    for (auto [dim, tag] : groups)
    {
      if (dim != cell_dim - 1)
        continue;
      std::set<int> volumes;
      std::vector<int> entities;
      gmsh::model::getEntitiesForPhysicalGroup(dim, tag, entities);
      for (int e : entities)
      {
        std::vector<int> up, down;
        gmsh::model::getAdjacencies(dim, e, up, down);
        for (int v : up)
        {
          std::vector<int> tags;
          gmsh::model::getPhysicalGroupsForEntity(cell_dim, v, tags);
          volumes.insert(tags.begin(), tags.end());
        }
      }
      for (int v : volumes)
        s << "side " << tag << ' ' << v << '\n';
    }
  }
  std::istringstream in(broadcast(comm, s.str()));
  Groups g;
  std::map<int, std::string> volume_names;
  std::vector<std::pair<int, int>> sides;
  std::string first;
  while (in >> first)
  {
    int tag, other;
    if (first == "side")
    {
      in >> tag >> other;
      sides.push_back({tag, other});
      continue;
    }
    if (first == "dimension")
    {
      in >> g.dimension;
      continue;
    }
    if (first == "bounds")
    {
      for (double& v : g.bounds)
        in >> v;
      continue;
    }
    const int dim = std::stoi(first);
    std::string name;
    in >> tag >> name;
    if (dim == g.dimension)
    {
      g.volumes[name] = tag;
      volume_names[tag] = name;
    }
    else if (dim == g.dimension - 1)
      g.surfaces[name] = tag;
  }
  for (auto [surface, volume] : sides)
    for (auto& [name, tag] : g.surfaces)
      if (tag == surface && volume_names.count(volume))
        g.sides[name].insert(volume_names[volume]);
  return g;
}

GmshSession::GmshSession()
{
  gmsh::initialize();
  gmsh::option::setNumber("General.Terminal", 0);
}

GmshSession::~GmshSession() { gmsh::finalize(); }

Groups open(MPI_Comm comm, const std::filesystem::path& file,
           const std::map<std::string, double>& parameters)
{
  std::string error;
  if (rank(comm) == 0)
  {
    try
    {
      gmsh::clear();
      gmsh::onelab::clear();
      gmsh::open(file.string());
      if (!parameters.empty())
      {
        // The parameters the file declares, then the file again with the values.
        std::vector<std::string> known;
        gmsh::onelab::getNames(known, "Parameters/.*");
        for (auto& [name, value] : parameters)
          if (std::find(known.begin(), known.end(), "Parameters/" + name) == known.end())
          {
            std::string list;
            for (auto& k : known)
              list += (list.empty() ? "" : ", ") + k.substr(11);
            throw std::invalid_argument(
                "it declares no parameter '" + name + "' (DefineConstant[" + name
                + " = {value, Name \"Parameters/" + name + "\"}]); it has: "
                + (list.empty() ? "none" : list));
          }
        gmsh::clear();
        for (auto& [name, value] : parameters)
          gmsh::onelab::setNumber("Parameters/" + name, {value});
        gmsh::open(file.string());
      }
    }
    catch (const std::invalid_argument& e)
    {
      error = file.string() + ": " + e.what();
    }
    catch (const std::exception& e)
    {
      error = file.string() + ": gmsh could not read it: " + e.what();
    }
    catch (const std::string& e) // gmsh 4.8 throws strings
    {
      error = file.string() + ": gmsh could not read it: " + e;
    }
  }
  error = broadcast(comm, error);
  if (!error.empty())
    throw std::runtime_error(error);
  return groups_of_current_model(comm);
}

/// The current gmsh model's cells, facets and nodes into m (its groups
/// set); throws on a facet node that no cell uses.
static void read_mesh(Model& m);

Model extract(MPI_Comm comm, double size_max)
{
  Model m;
  m.groups = groups_of_current_model(comm);
  std::string error;
  if (rank(comm) == 0)
  {
    // A geometry without a mesh (a .geo) is meshed here.
    const int dim = m.groups.dimension;
    std::vector<int> types;
    gmsh::model::mesh::getElementTypes(types, dim);
    if (types.empty())
    {
      try
      {
        if (size_max > 0)
          gmsh::option::setNumber("Mesh.CharacteristicLengthMax", size_max);
        gmsh::model::mesh::generate(dim);
      }
      catch (const std::string& e) // gmsh 4.8 throws strings
      {
        error = "gmsh could not mesh the geometry: " + e;
      }
      gmsh::model::mesh::getElementTypes(types, dim);
    }
    if (error.empty() && dim == 3 && types != std::vector<int>{4})
      error = "the mesh must consist of linear tetrahedra (gmsh type 4)";
    if (error.empty() && dim == 2 && types != std::vector<int>{2})
      error = "a 2D mesh must consist of linear triangles (gmsh type 2)";
  }
  if (error = broadcast(comm, error); !error.empty())
    throw std::runtime_error(error);
  // Rank 0 reads the mesh; what fails there stops every rank (no hang).
  if (rank(comm) == 0)
    try
    {
      read_mesh(m);
    }
    catch (const std::exception& e)
    {
      error = e.what();
    }
  if (error = broadcast(comm, error); !error.empty())
    throw std::runtime_error(error);
  return m;
}

static void read_mesh(Model& m)
{
  // Tetrahedra per volume group, then compact node numbering.
  std::unordered_map<std::size_t, std::int64_t> index;
  auto node_index = [&](std::size_t tag)
  {
    auto [it, fresh] = index.emplace(tag, static_cast<std::int64_t>(index.size()));
    return it->second;
  };
  // gmsh element types: tetrahedron 4, triangle 2, segment 1.
  const int dim = m.groups.dimension;
  const int cell_type = dim == 3 ? 4 : 2, facet_type = dim == 3 ? 2 : 1;
  for (auto [name, group] : m.groups.volumes)
  {
    std::vector<std::size_t> nodes;
    group_elements(dim, group, cell_type, nodes);
    for (std::size_t n : nodes)
      m.cells.push_back(node_index(n));
    m.cell_groups.insert(m.cell_groups.end(), nodes.size() / (dim + 1), group);
  }
  for (auto [name, group] : m.groups.surfaces)
  {
    std::vector<std::size_t> nodes;
    group_elements(dim - 1, group, facet_type, nodes);
    for (std::size_t n : nodes)
    {
      auto it = index.find(n);
      if (it == index.end())
        throw std::runtime_error(std::string(dim == 3 ? "surface" : "curve") + " group '"
                                 + name + "' has a node that no "
                                 + (dim == 3 ? "tetrahedron" : "triangle") + " uses");
      m.facets.push_back(it->second);
    }
    m.facet_groups.insert(m.facet_groups.end(), nodes.size() / dim, group);
  }

  std::vector<std::size_t> tags;
  std::vector<double> coord, param;
  gmsh::model::mesh::getNodes(tags, coord, param, -1, -1, true, false);
  m.x.assign(3 * index.size(), 0.0);
  for (std::size_t i = 0; i < tags.size(); ++i)
    if (auto it = index.find(tags[i]); it != index.end())
      std::copy_n(coord.begin() + 3 * i, 3, m.x.begin() + 3 * it->second);
}

Model keep(const Model& model, const std::vector<std::int32_t>& volume_groups)
{

  Model m;
  m.groups = model.groups;
  for (auto it = m.groups.volumes.begin(); it != m.groups.volumes.end();)
    it = std::find(volume_groups.begin(), volume_groups.end(), it->second) == volume_groups.end()
             ? m.groups.volumes.erase(it)
             : std::next(it);
  const int nv = model.groups.dimension + 1, nf = nv - 1;
  std::vector<std::int64_t> index(model.x.size() / 3, -1);
  std::set<std::array<std::int64_t, 3>> faces;
  for (std::size_t c = 0; c < model.cell_groups.size(); ++c)
  {
    if (std::find(volume_groups.begin(), volume_groups.end(), model.cell_groups[c])
        == volume_groups.end())
      continue;
    const std::int64_t* v = &model.cells[nv * c];
    for (int k = 0; k < nv; ++k)
    {
      faces.insert(face(v, nv, k));
      if (index[v[k]] < 0)
      {
        index[v[k]] = static_cast<std::int64_t>(m.x.size() / 3);
        m.x.insert(m.x.end(), model.x.begin() + 3 * v[k], model.x.begin() + 3 * v[k] + 3);
      }
      m.cells.push_back(index[v[k]]);
    }
    m.cell_groups.push_back(model.cell_groups[c]);
  }
  for (std::size_t f = 0; f < model.facet_groups.size(); ++f)
  {
    if (!faces.count(facet_key(model, f)))
      continue;
    for (int i = 0; i < nf; ++i)
      m.facets.push_back(index[model.facets[nf * f + i]]);
    m.facet_groups.push_back(model.facet_groups[f]);
  }
  return m;
}

std::int32_t add_interface(Model& model, const std::vector<std::int32_t>& first,
                           const std::string& name)
{
  std::int32_t tag = 1;
  for (auto& [n, t] : model.groups.surfaces)
    tag = std::max(tag, t + 1);
  model.groups.surfaces[name] = tag;
  // Each face: which sides it has (bit 0: a cell of `first`, bit 1: another).
  const int nv = model.groups.dimension + 1;
  std::map<std::array<std::int64_t, 3>, int> faces;
  for (std::size_t c = 0; c < model.cell_groups.size(); ++c)
  {
    const bool in_first = std::find(first.begin(), first.end(), model.cell_groups[c])
                          != first.end();
    const std::int64_t* v = &model.cells[nv * c];
    for (int k = 0; k < nv; ++k)
      faces[face(v, nv, k)] |= in_first ? 1 : 2;
  }
  std::map<std::array<std::int64_t, 3>, std::int32_t> tagged;
  for (std::size_t f = 0; f < model.facet_groups.size(); ++f)
    tagged[facet_key(model, f)] = model.facet_groups[f];
  std::size_t count = 0;
  for (auto& [f, sides] : faces)
  {
    if (sides != 3)
      continue;
    if (auto it = tagged.find(f); it != tagged.end())
    {
      std::string group = std::to_string(it->second);
      for (auto& [n, t] : model.groups.surfaces)
        if (t == it->second)
          group = n;
      throw std::invalid_argument("surface group '" + group + "' lies on the interface "
                                  "between the volume groups; name the interface itself "
                                  "or leave its faces out of other groups");
    }
    model.facets.insert(model.facets.end(), f.begin(), f.begin() + (nv - 1));
    model.facet_groups.push_back(tag);
    ++count;
  }
  if (count == 0 && !model.cells.empty())
    throw std::invalid_argument("no face lies between the fluid's volume groups and the "
                                "others: the fluid and the solid must share faces (a "
                                "conforming mesh)");
  return tag;
}

std::array<std::array<double, 3>, 3> cell_edges(const dolfinx::mesh::Mesh& mesh,
                                                std::int32_t cell)
{
  const int tdim = mesh.topology().dim();
  const auto x = mesh.geometry().x();
  auto g = mesh.geometry().dofmap().links(cell);
  std::array<std::array<double, 3>, 3> e{};
  e[2][2] = 1;
  for (int i = 0; i < tdim; ++i)
    for (int j = 0; j < 3; ++j)
      e[i][j] = x[3 * g[i + 1] + j] - x[3 * g[0] + j];
  return e;
}

double determinant(const std::array<std::array<double, 3>, 3>& m)
{
  return m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
         - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
         + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
}

int normal_axis(const dolfinx::mesh::Mesh& mesh,
                const dolfinx::mesh::MeshTags<std::int32_t>& facets, std::int32_t group)
{
  std::vector<std::int32_t> list = facets.find(group);
  const int fdim = mesh.topology().dim() - 1;
  auto geo = dolfinx::mesh::entities_to_geometry(mesh, fdim, list, false);
  const auto& x = mesh.geometry().x();
  int axis = -1;
  bool ok = true;
  for (std::size_t f = 0; f < list.size(); ++f)
  {
    const std::array<double, 3> n = facet_normal(x, &geo[(fdim + 1) * f], fdim);
    double norm = std::sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    int i = static_cast<int>(std::max_element(n.begin(), n.end(),
                                              [](double p, double q)
                                              { return std::abs(p) < std::abs(q); })
                             - n.begin());
    ok = ok && std::abs(n[i]) > (1 - 1e-8) * norm && (axis < 0 || axis == i);
    axis = i;
  }
  int lo = axis < 0 ? 3 : axis, hi = axis, all_ok = ok;
  MPI_Allreduce(MPI_IN_PLACE, &lo, 1, MPI_INT, MPI_MIN, mesh.comm());
  MPI_Allreduce(MPI_IN_PLACE, &hi, 1, MPI_INT, MPI_MAX, mesh.comm());
  MPI_Allreduce(MPI_IN_PLACE, &all_ok, 1, MPI_INT, MPI_MIN, mesh.comm());
  if (!all_ok || lo != hi || hi < 0)
    return -1;
  return hi;
}

std::pair<double, double> coordinate_range(const dolfinx::mesh::Mesh& mesh,
                                           const dolfinx::mesh::MeshTags<std::int32_t>& facets,
                                           std::int32_t group, int axis)
{
  const std::vector<std::int32_t> list = facets.find(group);
  const auto nodes
      = dolfinx::mesh::entities_to_geometry(mesh, mesh.topology().dim() - 1, list, false);
  const auto& x = mesh.geometry().x();
  double lo = std::numeric_limits<double>::infinity(), hi = -lo;
  for (auto n : nodes)
  {
    lo = std::min(lo, x[3 * n + axis]);
    hi = std::max(hi, x[3 * n + axis]);
  }
  MPI_Allreduce(MPI_IN_PLACE, &lo, 1, MPI_DOUBLE, MPI_MIN, mesh.comm());
  MPI_Allreduce(MPI_IN_PLACE, &hi, 1, MPI_DOUBLE, MPI_MAX, mesh.comm());
  return {lo, hi};
}

std::array<double, 3> outward_normal(const dolfinx::mesh::Mesh& mesh,
                                     const dolfinx::mesh::MeshTags<std::int32_t>& facets,
                                     const std::vector<std::int32_t>& groups)
{
  auto& topology = const_cast<dolfinx::mesh::Mesh&>(mesh).topology_mutable();
  const int tdim = topology.dim(), fdim = tdim - 1;
  topology.create_connectivity(fdim, tdim);
  const auto f2c = topology.connectivity(fdim, tdim);
  const auto& x = mesh.geometry().x();
  const auto& cell_nodes = mesh.geometry().dofmap();
  const std::int32_t owned = topology.index_map(fdim)->size_local();
  std::array<double, 3> sum{0, 0, 0};
  for (auto g : groups)
  {
    std::vector<std::int32_t> list = facets.find(g);
    list.erase(std::remove_if(list.begin(), list.end(), [&](auto f) { return f >= owned; }),
               list.end());
    auto geo = dolfinx::mesh::entities_to_geometry(mesh, fdim, list, false);
    for (std::size_t k = 0; k < list.size(); ++k)
    {
      const std::int32_t* nodes = &geo[tdim * k];
      const std::array<double, 3> n = facet_normal(x, nodes, fdim);
      std::array<double, 3> c{0, 0, 0}, m{0, 0, 0};
      for (int j = 0; j < 3; ++j)
        for (int i = 0; i < tdim; ++i)
          m[j] += x[3 * nodes[i] + j] / tdim;
      auto cell = cell_nodes.links(f2c->links(list[k])[0]);
      for (auto node : cell)
        for (int j = 0; j < 3; ++j)
          c[j] += x[3 * node + j] / cell.size();
      const double side = (m[0] - c[0]) * n[0] + (m[1] - c[1]) * n[1] + (m[2] - c[2]) * n[2];
      for (int j = 0; j < 3; ++j)
        sum[j] += side < 0 ? -n[j] : n[j];
    }
  }
  MPI_Allreduce(MPI_IN_PLACE, sum.data(), 3, MPI_DOUBLE, MPI_SUM, mesh.comm());
  const double norm = std::hypot(sum[0], sum[1], sum[2]);
  if (norm > 0)
    for (auto& v : sum)
      v /= norm;
  return sum;
}

Tagged distribute(MPI_Comm comm, const Model& model)
{
  using namespace dolfinx;
  const int dim = model.groups.dimension, nv = dim + 1;
  const std::size_t num_cells = model.cells.size() / nv;
  std::vector<std::int32_t> offsets(num_cells + 1);
  for (std::size_t c = 0; c <= num_cells; ++c)
    offsets[c] = static_cast<std::int32_t>(nv * c);
  graph::AdjacencyList<std::int64_t> cells(model.cells, offsets);
  fem::CoordinateElement element(
      dim == 3 ? mesh::CellType::tetrahedron : mesh::CellType::triangle, 1);

  // dolfinx 0.5 finds the vertices shared between processes through the
  // ghost cells it sends across shared faces. Where two bodies touch only
  // along an edge or at a point (a non-manifold vertex), no face is shared,
  // the vertex would be duplicated and the bodies come apart. So every
  // cell at such a vertex also goes, as a ghost, to each process that owns
  // another cell there; ghosts are dropped once the sharing is known.
  const std::vector<bool> junction
      = non_manifold_vertices(model.cells, nv, model.x.size() / 3);
  auto partitioner = [junction, default_partitioner = mesh::create_cell_partitioner()](
                         MPI_Comm comm, int nparts, int tdim,
                         const graph::AdjacencyList<std::int64_t>& cells,
                         mesh::GhostMode ghost_mode)
  {
    graph::AdjacencyList<std::int32_t> dest
        = default_partitioner(comm, nparts, tdim, cells, ghost_mode);
    // Only the rank that read the model holds cells (and `junction`).
    std::map<std::int64_t, std::set<std::int32_t>> owners; // junction vertex -> ranks
    for (std::int32_t c = 0; c < cells.num_nodes(); ++c)
      for (auto v : cells.links(c))
        if (static_cast<std::size_t>(v) < junction.size() && junction[v])
          owners[v].insert(dest.links(c)[0]);
    if (owners.empty())
      return dest;
    std::vector<std::int32_t> data, offsets{0};
    for (std::int32_t c = 0; c < cells.num_nodes(); ++c)
    {
      std::vector<std::int32_t> d(dest.links(c).begin(), dest.links(c).end());
      for (auto v : cells.links(c))
        if (auto it = owners.find(v); it != owners.end())
          for (std::int32_t r : it->second)
            if (std::find(d.begin(), d.end(), r) == d.end())
              d.push_back(r);
      data.insert(data.end(), d.begin(), d.end());
      offsets.push_back(static_cast<std::int32_t>(data.size()));
    }
    return graph::AdjacencyList<std::int32_t>(std::move(data), std::move(offsets));
  };

  // A section's nodes lie in the plane z = 0: its mesh has 2 coordinates.
  std::vector<double> x;
  for (std::size_t i = 0; i < model.x.size(); ++i)
    if (dim == 3 || i % 3 < 2)
      x.push_back(model.x[i]);
  Tagged t;
  t.groups = model.groups;
  t.mesh = std::make_shared<mesh::Mesh>(mesh::create_mesh(
      comm, cells, element, x, {model.x.size() / 3, static_cast<std::size_t>(dim)},
      mesh::GhostMode::none, partitioner));

  auto tags = [&](int dim, const std::vector<std::int64_t>& entities,
                  const std::vector<std::int32_t>& values, int nv)
  {
    auto [local, local_values] = io::xdmf_utils::distribute_entity_data(
        *t.mesh, dim, entities, values);
    t.mesh->topology_mutable().create_connectivity(dim, 0);
    t.mesh->topology_mutable().create_connectivity(dim, t.mesh->topology().dim());
    std::vector<std::int32_t> off(local_values.size() + 1);
    for (std::size_t i = 0; i < off.size(); ++i)
      off[i] = static_cast<std::int32_t>(nv * i);
    graph::AdjacencyList<std::int32_t> adj(std::move(local), std::move(off));
    return std::make_shared<mesh::MeshTags<std::int32_t>>(mesh::create_meshtags(
        t.mesh, dim, adj, std::span<const std::int32_t>(local_values)));
  };
  t.cells = tags(dim, model.cells, model.cell_groups, nv);
  t.facets = tags(dim - 1, model.facets, model.facet_groups, dim);
  return t;
}

dolfinx::mesh::MeshTags<std::int32_t>
retag(const dolfinx::mesh::MeshTags<std::int32_t>& tags,
      const std::map<std::int32_t, std::int32_t>& map)
{
  std::vector<std::int32_t> indices, values;
  for (std::size_t i = 0; i < tags.indices().size(); ++i)
    if (auto it = map.find(tags.values()[i]); it != map.end())
    {
      indices.push_back(tags.indices()[i]);
      values.push_back(it->second);
    }
  return dolfinx::mesh::MeshTags<std::int32_t>(tags.mesh(), tags.dim(),
                                               std::move(indices),
                                               std::move(values));
}

std::vector<std::array<double, 3>>
combine_points(MPI_Comm comm, std::vector<double> sums,
               const std::vector<std::array<double, 3>>& points)
{
  MPI_Allreduce(MPI_IN_PLACE, sums.data(), static_cast<int>(sums.size()), MPI_DOUBLE,
                MPI_SUM, comm);
  std::vector<std::array<double, 3>> out(points.size());
  for (std::size_t i = 0; i < points.size(); ++i)
  {
    if (sums[4 * i + 3] == 0)
      throw std::runtime_error("probe point (" + std::to_string(points[i][0]) + ", "
                               + std::to_string(points[i][1]) + ", "
                               + std::to_string(points[i][2]) + ") is outside the mesh");
    for (int j = 0; j < 3; ++j)
      out[i][j] = sums[4 * i + j] / sums[4 * i + 3];
  }
  return out;
}

Probes::Probes(const dolfinx::mesh::Mesh& mesh, std::vector<std::array<double, 3>> points)
    : _comm(mesh.comm()), _points(std::move(points)), _cells(_points.size(), -1)
{
  for (auto& p : _points)
    _x.insert(_x.end(), p.begin(), p.end());
  dolfinx::geometry::BoundingBoxTree tree(mesh, mesh.topology().dim(), 1e-8);
  auto candidates = dolfinx::geometry::compute_collisions(tree, _x);
  auto cells = dolfinx::geometry::compute_colliding_cells(mesh, candidates, _x);
  for (std::size_t i = 0; i < _points.size(); ++i)
    if (auto c = cells.links(static_cast<int>(i)); !c.empty())
      _cells[i] = c[0];
}

std::vector<std::array<double, 3>> Probes::values(const dolfinx::fem::Function<double>& f) const
{
  const int n = f.function_space()->element()->value_size();
  if (n > 3)
    throw std::invalid_argument("meshio::Probes: at most 3 components");
  std::vector<double> sum(4 * _points.size(), 0.0), value(n);
  for (std::size_t i = 0; i < _points.size(); ++i)
    if (_cells[i] >= 0)
    {
      f.eval(std::span<const double>(_x.data() + 3 * i, 3), {1, 3},
             std::span<const std::int32_t>(&_cells[i], 1), value,
             {1, static_cast<std::size_t>(n)});
      std::copy(value.begin(), value.end(), sum.begin() + 4 * i);
      sum[4 * i + 3] = 1;
    }
  return combine_points(_comm, std::move(sum), _points);
}

} // namespace nct::meshio
