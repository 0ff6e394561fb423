// gmsh models to distributed dolfinx meshes with group tags.
#pragma once

#include <array>
#include <cstdint>
#include <filesystem>
#include <map>
#include <set>
#include <memory>
#include <string>
#include <type_traits>
#include <utility>
#include <vector>

#include <dolfinx/fem/Function.h>
#include <dolfinx/mesh/Mesh.h>
#include <dolfinx/mesh/MeshTags.h>
#include <mpi.h>

namespace nct::meshio
{

/// Physical groups of a model: name -> tag, for volumes and surfaces (of
/// a 2D model: its surfaces and curves, the groups of cells and of facets).
struct Groups
{
  int dimension = 3; ///< of the model's cells: 3, or 2 for a section
  /// The model's bounding box: x, y, z smallest, then largest [mm].
  std::array<double, 6> bounds{0, 0, 0, 0, 0, 0};
  std::map<std::string, int> volumes;
  std::map<std::string, int> surfaces;
  /// Per surface group, the volume groups its geometric entities bound
  /// (one for a boundary, two for an interface; empty where the model has
  /// no such adjacency, e.g. a .msh without its entities).
  std::map<std::string, std::set<std::string>> sides;
};

/// A tetrahedral mesh with its tagged boundary triangles (2D: triangles
/// and tagged segments), held on one rank (empty elsewhere): the input of
/// `distribute`. Its dimension is groups.dimension.
struct Model
{
  std::vector<double> x;                 ///< 3 coordinates per node (z = 0 in 2D)
  std::vector<std::int64_t> cells;       ///< dimension + 1 node indices per cell
  std::vector<std::int32_t> cell_groups; ///< volume group tag per cell
  std::vector<std::int64_t> facets;      ///< dimension node indices per facet
  std::vector<std::int32_t> facet_groups; ///< surface group tag per facet
  Groups groups;                         ///< known on every rank
};

/// gmsh initialised for the span of a scope, quiet.
struct GmshSession
{
  GmshSession();
  ~GmshSession();
  GmshSession(const GmshSession&) = delete;
  GmshSession& operator=(const GmshSession&) = delete;
};

/// Broadcast a string from rank 0 (e.g. an error met there) to every rank.
std::string broadcast(MPI_Comm comm, std::string s);

/// Every rank's `local` values (double or std::int64_t), concatenated in
/// rank order, on every rank.
template <typename T>
std::vector<T> all_gather(MPI_Comm comm, const std::vector<T>& local)
{
  static_assert(std::is_same_v<T, double> || std::is_same_v<T, std::int64_t>);
  const MPI_Datatype type = std::is_same_v<T, double> ? MPI_DOUBLE : MPI_INT64_T;
  int ranks = 1, count = static_cast<int>(local.size());
  MPI_Comm_size(comm, &ranks);
  std::vector<int> counts(ranks), offsets(ranks + 1, 0);
  MPI_Allgather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, comm);
  for (int r = 0; r < ranks; ++r)
    offsets[r + 1] = offsets[r] + counts[r];
  std::vector<T> all(offsets[ranks]);
  MPI_Allgatherv(local.data(), count, type, all.data(), counts.data(), offsets.data(), type,
                 comm);
  return all;
}

/// The physical groups of the current gmsh model (rank 0), on every rank.
Groups groups_of_current_model(MPI_Comm comm);

/// Open a .msh or .geo file as the current gmsh model on rank 0 (a .geo is
/// parsed, not meshed); errors name the file. `parameters` set the .geo's
/// constants declared with the ONELAB name "Parameters/<name>" (an unknown
/// one is an error). Returns its groups on every rank.
Groups open(MPI_Comm comm, const std::filesystem::path& file,
            const std::map<std::string, double>& parameters = {});

/// Linear tetrahedra and tagged triangles of the current gmsh model (rank
/// 0; of a 2D model, linear triangles and tagged segments), meshing it
/// first if it has no mesh of its dimension yet (with elements no larger
/// than `size_max` if it is positive).
Model extract(MPI_Comm comm, double size_max = 0);

/// The part of a Model in the given volume groups: their cells, the nodes
/// they use (renumbered) and the tagged triangles that are faces of them.
Model keep(const Model& model, const std::vector<std::int32_t>& volume_groups);

/// The faces between a cell of `first` (volume groups) and a cell of any
/// other group, added to `model` as the surface group `name` with a new
/// tag (on every rank; the faces on the rank that holds the model).
/// Returns the tag. Throws std::invalid_argument naming the surface group
/// that already holds one of those faces, or when there are none.
std::int32_t add_interface(Model& model, const std::vector<std::int32_t>& first,
                           const std::string& name);

/// A distributed mesh with its physical-group tags.
struct Tagged
{
  std::shared_ptr<dolfinx::mesh::Mesh> mesh;
  std::shared_ptr<dolfinx::mesh::MeshTags<std::int32_t>> cells;
  std::shared_ptr<dolfinx::mesh::MeshTags<std::int32_t>> facets;
  Groups groups;
};

/// Partition a Model over `comm` and carry its tags along.
Tagged distribute(MPI_Comm comm, const Model& model);

/// New tags on the same entities with values mapped through `map`;
/// entities whose value is not in `map` are dropped.
dolfinx::mesh::MeshTags<std::int32_t>
retag(const dolfinx::mesh::MeshTags<std::int32_t>& tags,
      const std::map<std::int32_t, std::int32_t>& map);

/// The axis (0, 1, 2) that every facet of a group is normal to, or -1 if
/// they are not all normal to one axis (collective).
int normal_axis(const dolfinx::mesh::Mesh& mesh,
                const dolfinx::mesh::MeshTags<std::int32_t>& facets, std::int32_t group);

/// The edges of an affine cell from its first vertex, as rows (a
/// triangle's third row is e_z): the cell's Jacobian, transposed; its
/// determinant is 6 times a tetrahedron's signed volume, 2 times a
/// triangle's signed area.
std::array<std::array<double, 3>, 3> cell_edges(const dolfinx::mesh::Mesh& mesh,
                                                std::int32_t cell);

/// The determinant of a 3 x 3 matrix.
double determinant(const std::array<std::array<double, 3>, 3>& m);

/// The smallest and largest coordinate `axis` of the nodes of a facet
/// group (collective; an empty group gives (inf, -inf)).
std::pair<double, double> coordinate_range(const dolfinx::mesh::Mesh& mesh,
                                           const dolfinx::mesh::MeshTags<std::int32_t>& facets,
                                           std::int32_t group, int axis);

/// The area-weighted mean outward unit normal of the boundary facets in
/// these groups (the mesh's exterior: each facet has one cell; collective).
std::array<double, 3> outward_normal(const dolfinx::mesh::Mesh& mesh,
                                     const dolfinx::mesh::MeshTags<std::int32_t>& facets,
                                     const std::vector<std::int32_t>& groups);

/// Per-point values found on some ranks, combined on all: `sums` holds,
/// per point, 3 values and a count (0 where this rank did not find it).
/// Returns the mean over the ranks that found each point; throws for a
/// point no rank found.
std::vector<std::array<double, 3>>
combine_points(MPI_Comm comm, std::vector<double> sums,
               const std::vector<std::array<double, 3>>& points);

/// Values of functions at fixed points, their cells found once: the mesh
/// must not move while the object is in use.
class Probes
{
public:
  Probes(const dolfinx::mesh::Mesh& mesh, std::vector<std::array<double, 3>> points);
  /// The function's value (up to 3 components; the rest 0) at each point;
  /// collective, every rank gets every value. Throws for a point that no
  /// rank's cells hold.
  std::vector<std::array<double, 3>> values(const dolfinx::fem::Function<double>& f) const;
  const std::vector<std::array<double, 3>>& points() const { return _points; }

private:
  MPI_Comm _comm;
  std::vector<std::array<double, 3>> _points;
  std::vector<double> _x;           ///< the points, flattened
  std::vector<std::int32_t> _cells; ///< a local cell holding each point, or -1
};

} // namespace nct::meshio
