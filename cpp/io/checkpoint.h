// Checkpoint files: a run's fields and a JSON document in HDF5, the fields
// keyed by the mesh's input ordering so that a checkpoint written on one
// rank count is read on another.
#pragma once

#include <cstdint>
#include <filesystem>
#include <map>
#include <span>
#include <stdexcept>
#include <string>
#include <vector>

#include <dolfinx/fem/Function.h>
#include <dolfinx/mesh/Mesh.h>
#include <mpi.h>
#include <nlohmann/json.hpp>

namespace nct::io
{

/// A checkpoint that cannot be used: missing, damaged, or written by
/// another scene, build or mesh; the message names the file and why.
class CheckpointError : public std::runtime_error
{
public:
  using std::runtime_error::runtime_error;
};

/// Keys of a function space's local dof blocks (owned, then ghosts) that do
/// not depend on the partition: a vertex's dof is its input node index n
/// (key n N + n), an edge's dof its two nodes' (key min N + max), N the
/// number of nodes; with m dofs per vertex (a mixed element's) the i-th of
/// an entity's has key m k + i. Lagrange spaces of degree 1 and 2, their
/// vector and mixed P1 versions, on a mesh of linear cells.
std::vector<std::int64_t> dof_keys(const dolfinx::fem::FunctionSpace& V);

/// A mesh as built, independent of the partition: its node and cell counts
/// and a sum of hashes of each node's input index and coordinates and of
/// each cell's nodes' input indices. Collective.
std::string mesh_fingerprint(const dolfinx::mesh::Mesh& mesh);

/// FNV-1a, 64 bits, of a byte string.
std::uint64_t fnv1a(const void* data, std::size_t bytes, std::uint64_t hash = 14695981039346656037ull);

/// A checkpoint being written: keyed fields gathered on rank 0, then one
/// HDF5 file with them and a JSON document (CBOR: doubles exact, NaN and
/// infinities kept), each dataset's checksum in the document.
class CheckpointWriter
{
public:
  explicit CheckpointWriter(MPI_Comm comm) : _comm(comm) {}
  /// The owned blocks (the first `owned` of `keys`) of `values`, `bs`
  /// numbers each; collective.
  void add(const std::string& name, std::span<const double> values, int bs,
           std::span<const std::int64_t> keys, std::int32_t owned);
  /// A function's owned dofs, keyed by dof_keys().
  void add(const std::string& name, const dolfinx::fem::Function<double>& f);
  /// dof_keys(V), computed once per space; collective on first use.
  const std::vector<std::int64_t>& keys(const dolfinx::fem::FunctionSpace& V);
  /// The mesh's node coordinates, keyed by their input index.
  void add_geometry(const std::string& name, const dolfinx::mesh::Mesh& mesh);

  /// Write dir/name whole or not at all (a temporary file renamed into
  /// place), then dir/latest naming it, then delete all but the newest
  /// `keep` checkpoints. Collective; returns the file's size [bytes].
  std::uintmax_t write(const std::filesystem::path& dir, const std::string& name,
                       nlohmann::json document, int keep);

private:
  struct Data
  {
    int bs = 1;
    std::vector<std::int64_t> keys; ///< rank 0: sorted
    std::vector<double> values;
  };
  MPI_Comm _comm;
  std::map<std::string, Data> _data;
  std::map<const dolfinx::fem::FunctionSpace*, std::vector<std::int64_t>> _keys;
};

/// The newest checkpoint of a folder (named by its file `latest`), read
/// whole and checked on every rank.
class CheckpointReader
{
public:
  /// Throws CheckpointError if there is none, or it cannot be read, or a
  /// checksum does not match.
  explicit CheckpointReader(const std::filesystem::path& dir);
  const nlohmann::json& document() const { return _document; }
  const std::filesystem::path& file() const { return _file; }

  /// Fill every local block (owned and ghost) of `values` by key; throws
  /// CheckpointError if a key is missing.
  void read(const std::string& name, std::span<double> values, int bs,
            std::span<const std::int64_t> keys) const;
  void read(const std::string& name, dolfinx::fem::Function<double>& f) const;
  /// dof_keys(V), computed once per space; collective on first use.
  const std::vector<std::int64_t>& keys(const dolfinx::fem::FunctionSpace& V) const;
  /// Move the mesh's nodes to the saved coordinates.
  void read_geometry(const std::string& name, dolfinx::mesh::Mesh& mesh) const;

private:
  struct Data
  {
    int bs = 1;
    std::vector<std::int64_t> keys; ///< sorted
    std::vector<double> values;
  };
  std::filesystem::path _file;
  nlohmann::json _document;
  std::map<std::string, Data> _data;
  mutable std::map<const dolfinx::fem::FunctionSpace*, std::vector<std::int64_t>> _keys;
};

} // namespace nct::io
