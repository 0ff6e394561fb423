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

/// Vertices around which the cells are not connected through faces that
/// contain the vertex: two bodies touching along an edge or at a point.
std::vector<bool> non_manifold_vertices(const std::vector<std::int64_t>& cells,
                                        std::size_t num_vertices)
{
  std::vector<std::vector<std::size_t>> vertex_cells(num_vertices);
  for (std::size_t c = 0; c < cells.size() / 4; ++c)
    for (int i = 0; i < 4; ++i)
      vertex_cells[cells[4 * c + i]].push_back(c);
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
    std::map<std::array<std::int64_t, 2>, std::size_t> faces; // the other two vertices
    for (std::size_t k = 0; k < vc.size(); ++k)
    {
      std::array<std::int64_t, 3> others;
      for (int i = 0, j = 0; i < 4; ++i)
        if (cells[4 * vc[k] + i] != static_cast<std::int64_t>(v))
          others[j++] = cells[4 * vc[k] + i];
      for (int skip = 0; skip < 3; ++skip)
      {
        std::array<std::int64_t, 2> f{others[(skip + 1) % 3], others[(skip + 2) % 3]};
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

/// The face of tetrahedron `v` (4 node indices) opposite its node k, sorted.
std::array<std::int64_t, 3> face(const std::int64_t* v, int k)
{
  std::array<std::int64_t, 3> f;
  for (int i = 0, j = 0; i < 4; ++i)
    if (i != k)
      f[j++] = v[i];
  std::sort(f.begin(), f.end());
  return f;
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
      if (dim != 2)
        continue;
      std::set<int> volumes;
      std::vector<int> entities;
      gmsh::model::getEntitiesForPhysicalGroup(2, tag, entities);
      for (int e : entities)
      {
        std::vector<int> up, down;
        gmsh::model::getAdjacencies(2, e, up, down);
        for (int v : up)
        {
          std::vector<int> tags;
          gmsh::model::getPhysicalGroupsForEntity(3, v, tags);
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
    const int dim = std::stoi(first);
    std::string name;
    in >> tag >> name;
    if (dim == 3)
    {
      g.volumes[name] = tag;
      volume_names[tag] = name;
    }
    else if (dim == 2)
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

/// The current gmsh model's tetrahedra, facets and nodes into m (its
/// groups set); throws on a surface node that no tetrahedron uses.
static void read_mesh(Model& m);

Model extract(MPI_Comm comm, double size_max)
{
  Model m;
  m.groups = groups_of_current_model(comm);
  std::string error;
  if (rank(comm) == 0)
  {
    // A geometry without a mesh (a .geo) is meshed here.
    std::vector<int> types;
    gmsh::model::mesh::getElementTypes(types, 3);
    if (types.empty())
    {
      try
      {
        if (size_max > 0)
          gmsh::option::setNumber("Mesh.CharacteristicLengthMax", size_max);
        gmsh::model::mesh::generate(3);
      }
      catch (const std::string& e) // gmsh 4.8 throws strings
      {
        error = "gmsh could not mesh the geometry: " + e;
      }
      gmsh::model::mesh::getElementTypes(types, 3);
    }
    if (error.empty() && types != std::vector<int>{4})
      error = "the mesh must consist of linear tetrahedra (gmsh type 4)";
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
  for (auto [name, group] : m.groups.volumes)
  {
    std::vector<std::size_t> nodes;
    group_elements(3, group, 4, nodes);
    for (std::size_t n : nodes)
      m.cells.push_back(node_index(n));
    m.cell_groups.insert(m.cell_groups.end(), nodes.size() / 4, group);
  }
  for (auto [name, group] : m.groups.surfaces)
  {
    std::vector<std::size_t> nodes;
    group_elements(2, group, 2, nodes);
    for (std::size_t n : nodes)
    {
      auto it = index.find(n);
      if (it == index.end())
        throw std::runtime_error("surface group '" + name
                                 + "' has a node that no tetrahedron uses");
      m.facets.push_back(it->second);
    }
    m.facet_groups.insert(m.facet_groups.end(), nodes.size() / 3, group);
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
  std::vector<std::int64_t> index(model.x.size() / 3, -1);
  std::set<std::array<std::int64_t, 3>> faces;
  for (std::size_t c = 0; c < model.cell_groups.size(); ++c)
  {
    if (std::find(volume_groups.begin(), volume_groups.end(), model.cell_groups[c])
        == volume_groups.end())
      continue;
    const std::int64_t* v = &model.cells[4 * c];
    for (int k = 0; k < 4; ++k)
    {
      faces.insert(face(v, k));
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
    std::array<std::int64_t, 3> key{model.facets[3 * f], model.facets[3 * f + 1],
                                    model.facets[3 * f + 2]};
    std::sort(key.begin(), key.end());
    if (!faces.count(key))
      continue;
    for (int i = 0; i < 3; ++i)
      m.facets.push_back(index[model.facets[3 * f + i]]);
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
  std::map<std::array<std::int64_t, 3>, int> faces;
  for (std::size_t c = 0; c < model.cell_groups.size(); ++c)
  {
    const bool in_first = std::find(first.begin(), first.end(), model.cell_groups[c])
                          != first.end();
    const std::int64_t* v = &model.cells[4 * c];
    for (int k = 0; k < 4; ++k)
      faces[face(v, k)] |= in_first ? 1 : 2;
  }
  std::map<std::array<std::int64_t, 3>, std::int32_t> tagged;
  for (std::size_t f = 0; f < model.facet_groups.size(); ++f)
  {
    std::array<std::int64_t, 3> key{model.facets[3 * f], model.facets[3 * f + 1],
                                    model.facets[3 * f + 2]};
    std::sort(key.begin(), key.end());
    tagged[key] = model.facet_groups[f];
  }
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
    model.facets.insert(model.facets.end(), f.begin(), f.end());
    model.facet_groups.push_back(tag);
    ++count;
  }
  if (count == 0 && !model.cells.empty())
    throw std::invalid_argument("no face lies between the fluid's volume groups and the "
                                "others: the fluid and the solid must share faces (a "
                                "conforming mesh)");
  return tag;
}

int normal_axis(const dolfinx::mesh::Mesh& mesh,
                const dolfinx::mesh::MeshTags<std::int32_t>& facets, std::int32_t group)
{
  std::vector<std::int32_t> list = facets.find(group);
  auto geo = dolfinx::mesh::entities_to_geometry(mesh, 2, list, false);
  const auto& x = mesh.geometry().x();
  int axis = -1;
  bool ok = true;
  for (std::size_t f = 0; f < geo.size() / 3; ++f)
  {
    std::array<double, 3> a, b, n;
    for (int j = 0; j < 3; ++j)
    {
      a[j] = x[3 * geo[3 * f + 1] + j] - x[3 * geo[3 * f] + j];
      b[j] = x[3 * geo[3 * f + 2] + j] - x[3 * geo[3 * f] + j];
    }
    n = {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
         a[0] * b[1] - a[1] * b[0]};
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
  const auto nodes = dolfinx::mesh::entities_to_geometry(mesh, 2, list, false);
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
  topology.create_connectivity(2, 3);
  const auto f2c = topology.connectivity(2, 3);
  const auto& x = mesh.geometry().x();
  const auto& cell_nodes = mesh.geometry().dofmap();
  const std::int32_t owned = topology.index_map(2)->size_local();
  std::array<double, 3> sum{0, 0, 0};
  for (auto g : groups)
  {
    std::vector<std::int32_t> list = facets.find(g);
    list.erase(std::remove_if(list.begin(), list.end(), [&](auto f) { return f >= owned; }),
               list.end());
    auto geo = dolfinx::mesh::entities_to_geometry(mesh, 2, list, false);
    for (std::size_t k = 0; k < list.size(); ++k)
    {
      std::array<double, 3> a, b, n, c{0, 0, 0}, m{0, 0, 0};
      for (int j = 0; j < 3; ++j)
      {
        a[j] = x[3 * geo[3 * k + 1] + j] - x[3 * geo[3 * k] + j];
        b[j] = x[3 * geo[3 * k + 2] + j] - x[3 * geo[3 * k] + j];
        for (int i = 0; i < 3; ++i)
          m[j] += x[3 * geo[3 * k + i] + j] / 3;
      }
      n = {(a[1] * b[2] - a[2] * b[1]) / 2, (a[2] * b[0] - a[0] * b[2]) / 2,
           (a[0] * b[1] - a[1] * b[0]) / 2};
      for (auto node : cell_nodes.links(f2c->links(list[k])[0]))
        for (int j = 0; j < 3; ++j)
          c[j] += x[3 * node + j] / 4;
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
  const std::size_t num_cells = model.cells.size() / 4;
  std::vector<std::int32_t> offsets(num_cells + 1);
  for (std::size_t c = 0; c <= num_cells; ++c)
    offsets[c] = static_cast<std::int32_t>(4 * c);
  graph::AdjacencyList<std::int64_t> cells(model.cells, offsets);
  fem::CoordinateElement element(mesh::CellType::tetrahedron, 1);

  // dolfinx 0.5 finds the vertices shared between processes through the
  // ghost cells it sends across shared faces. Where two bodies touch only
  // along an edge or at a point (a non-manifold vertex), no face is shared,
  // the vertex would be duplicated and the bodies come apart. So every
  // cell at such a vertex also goes, as a ghost, to each process that owns
  // another cell there; ghosts are dropped once the sharing is known.
  const std::vector<bool> junction = non_manifold_vertices(model.cells, model.x.size() / 3);
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

  Tagged t;
  t.groups = model.groups;
  t.mesh = std::make_shared<mesh::Mesh>(mesh::create_mesh(
      comm, cells, element, model.x, {model.x.size() / 3, 3},
      mesh::GhostMode::none, partitioner));

  auto tags = [&](int dim, const std::vector<std::int64_t>& entities,
                  const std::vector<std::int32_t>& values, int nv)
  {
    auto [local, local_values] = io::xdmf_utils::distribute_entity_data(
        *t.mesh, dim, entities, values);
    t.mesh->topology_mutable().create_connectivity(dim, 0);
    t.mesh->topology_mutable().create_connectivity(dim, 3);
    std::vector<std::int32_t> off(local_values.size() + 1);
    for (std::size_t i = 0; i < off.size(); ++i)
      off[i] = static_cast<std::int32_t>(nv * i);
    graph::AdjacencyList<std::int32_t> adj(std::move(local), std::move(off));
    return std::make_shared<mesh::MeshTags<std::int32_t>>(mesh::create_meshtags(
        t.mesh, dim, adj, std::span<const std::int32_t>(local_values)));
  };
  t.cells = tags(3, model.cells, model.cell_groups, 4);
  t.facets = tags(2, model.facets, model.facet_groups, 3);
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
  dolfinx::geometry::BoundingBoxTree tree(mesh, 3, 1e-8);
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
