// XDMF time series that survive an interruption: every step leaves the
// HDF5 file flushed and the XML replaced whole, and a resumed run cuts a
// series back to the steps its checkpoint had.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <memory>
#include <optional>
#include <string>

#include <dolfinx/mesh/Mesh.h>
#include <hdf5.h>
#include <mpi.h>
#include <nlohmann/json.hpp>
#include <pugixml.hpp>

namespace nct::io
{

/// The layout of a mesh's topology and geometry as an XDMF file holds
/// them, which depends on the partition: a sum of hashes of each owned
/// geometry node's global and input indices and of each owned cell's
/// global index and its nodes' global indices. Meshes with equal layouts
/// write the same datasets, and so do functions on them. Collective.
std::uint64_t layout_fingerprint(const dolfinx::mesh::Mesh& mesh);

/// One XDMF file holding a Temporal collection of Grids named `name`, and
/// its HDF5 file (the .xdmf's name with .h5). After every commit() both
/// are valid on disk: the HDF5 data is flushed before the XML that refers
/// to it is replaced whole (rank 0 writes the XML).
class XdmfSeries
{
public:
  /// A new series in `xdmf`. With `keep` >= 0 (a resumed run): the series
  /// on disk cut back to its first `keep` steps; the later steps, the
  /// top-level Grids no kept step includes (by their Name), and every
  /// dataset the kept XML does not refer to are deleted. A resumed series
  /// whose .xdmf is gone starts anew. Throws CheckpointError if the files
  /// cannot be read or hold fewer steps. Collective.
  XdmfSeries(MPI_Comm comm, std::filesystem::path xdmf, const std::string& name, int keep = -1);
  ~XdmfSeries();
  XdmfSeries(const XdmfSeries&) = delete;
  XdmfSeries& operator=(const XdmfSeries&) = delete;

  hid_t h5() const { return _h5; }
  /// The Domain, where meshes go.
  pugi::xml_node domain() { return _xml.child("Xdmf").child("Domain"); }
  /// The steps on disk.
  int steps() const { return _steps; }
  /// The Grid of step `k` (k < steps()).
  pugi::xml_node step(int k) const;
  /// The XPath of step `k`'s Grid.
  std::string step_path(int k) const;
  /// A new step's Grid, with its Time; on disk at commit(). The first
  /// step's collection follows what the Domain holds by then.
  pugi::xml_node add_step(double time);
  /// The new step on disk: the HDF5 data flushed, then the XML. Collective.
  void commit();

  /// The XPath of the Grid holding the mesh the steps include (its
  /// Topology, and Geometry if it holds one); empty: none yet on this
  /// partition's layout. A resumed series takes its last step's.
  std::string mesh;
  /// The mesh's topology (all owned cells), and its geometry if
  /// `geometry`, into the new step's `grid` (HDF5 /Step/<k>/), which then
  /// holds the mesh. Collective.
  void add_mesh_to_step(pugi::xml_node grid, const dolfinx::mesh::Mesh& m, bool geometry);
  /// Include in `grid` the held mesh's children `what` (an XPath step:
  /// "Topology", or "*[self::Topology or self::Geometry]").
  void include_mesh(pugi::xml_node grid, const std::string& what);

private:
  MPI_Comm _comm;
  std::filesystem::path _xdmf;
  std::string _name;
  hid_t _h5 = -1;
  pugi::xml_document _xml;
  pugi::xml_node _series; ///< the Temporal collection, made by the first step
  int _steps = 0;
};

/// The series a writer keeps, one file <name>.xdmf per function in a
/// folder, on one mesh: what a checkpoint keeps of them (each file's steps
/// and the mesh's partition layout) and how a resumed run continues them.
class XdmfFiles
{
public:
  XdmfFiles(std::filesystem::path dir, std::shared_ptr<const dolfinx::mesh::Mesh> mesh);
  /// The series of `name`: made new on first use. Collective then.
  XdmfSeries& operator[](const std::string& name);
  /// Collective.
  nlohmann::json state() const;
  /// Continue the files as `state` left them (XdmfSeries with `keep`); on
  /// another partition layout each writes its mesh again. Collective.
  void resume(const nlohmann::json& state);

private:
  XdmfSeries& open(const std::string& name, int keep);
  /// layout_fingerprint(mesh), computed once (the numbering never changes).
  std::uint64_t layout() const;
  std::filesystem::path _dir;
  mutable std::optional<std::uint64_t> _layout;
  std::shared_ptr<const dolfinx::mesh::Mesh> _mesh;
  std::map<std::string, std::unique_ptr<XdmfSeries>> _series;
};

} // namespace nct::io
