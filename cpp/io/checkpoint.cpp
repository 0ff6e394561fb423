#include "io/checkpoint.h"

#include <algorithm>
#include <csignal>
#include <cstdlib>
#include <fcntl.h>
#include <numeric>
#include <unistd.h>

#include <dolfinx/mesh/cell_types.h>
#include <hdf5.h>

#include "io/format.h"
#include "io/output.h"

namespace nct::io
{
namespace
{

using dolfinx::mesh::Mesh;

int rank_of(MPI_Comm comm)
{
  int rank = 0;
  MPI_Comm_rank(comm, &rank);
  return rank;
}

/// The number of nodes (the largest input index + 1) of a mesh.
std::int64_t node_count(const Mesh& mesh)
{
  const auto& input = mesh.geometry().input_global_indices();
  std::int64_t n = input.empty() ? 0 : *std::max_element(input.begin(), input.end()) + 1;
  MPI_Allreduce(MPI_IN_PLACE, &n, 1, MPI_INT64_T, MPI_MAX, mesh.comm());
  return n;
}

/// The sum over ranks of a partition-independent sum of hashes.
std::uint64_t sum_over_ranks(std::uint64_t local, MPI_Comm comm)
{
  MPI_Allreduce(MPI_IN_PLACE, &local, 1, MPI_UINT64_T, MPI_SUM, comm);
  return local;
}

std::string hex(std::uint64_t h) { return format("%016llx", (unsigned long long)h); }

/// An HDF5 handle closed at scope exit.
struct Handle
{
  hid_t id;
  herr_t (*close)(hid_t);
  ~Handle()
  {
    if (id >= 0)
      close(id);
  }
};

void write_dataset(hid_t file, const std::string& path, hid_t type, const void* data,
                   std::vector<hsize_t> shape)
{
  Handle lcpl{H5Pcreate(H5P_LINK_CREATE), H5Pclose};
  H5Pset_create_intermediate_group(lcpl.id, 1);
  Handle space{H5Screate_simple(int(shape.size()), shape.data(), nullptr), H5Sclose};
  Handle set{H5Dcreate2(file, path.c_str(), type, space.id, lcpl.id, H5P_DEFAULT, H5P_DEFAULT),
             H5Dclose};
  const hsize_t size = std::accumulate(shape.begin(), shape.end(), hsize_t(1),
                                       std::multiplies<hsize_t>());
  if (set.id < 0 || (size > 0 && H5Dwrite(set.id, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data) < 0))
    throw std::runtime_error("cannot write the dataset " + path);
}

/// A dataset read whole; throws if it is missing or unreadable.
template <typename T>
std::vector<T> read_dataset(hid_t file, const std::string& path, hid_t type)
{
  Handle set{H5Dopen2(file, path.c_str(), H5P_DEFAULT), H5Dclose};
  if (set.id < 0)
    throw std::runtime_error("no dataset " + path);
  Handle space{H5Dget_space(set.id), H5Sclose};
  const hssize_t n = H5Sget_simple_extent_npoints(space.id);
  if (n < 0)
    throw std::runtime_error("unreadable dataset " + path);
  std::vector<T> data(n);
  if (n > 0 && H5Dread(set.id, type, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data()) < 0)
    throw std::runtime_error("unreadable dataset " + path);
  return data;
}

template <typename T>
std::uint64_t checksum(const std::vector<T>& v)
{
  return fnv1a(v.data(), v.size() * sizeof(T));
}

/// The local geometry nodes' keys (their input index) and coordinates.
std::span<const std::int64_t> node_keys(const Mesh& mesh)
{
  return mesh.geometry().input_global_indices();
}

} // namespace

std::uint64_t fnv1a(const void* data, std::size_t bytes, std::uint64_t hash)
{
  const auto* p = static_cast<const unsigned char*>(data);
  for (std::size_t i = 0; i < bytes; ++i)
    hash = (hash ^ p[i]) * 1099511628211ull;
  return hash;
}

std::vector<std::int64_t> dof_keys(const dolfinx::fem::FunctionSpace& V)
{
  const Mesh& mesh = *V.mesh();
  const auto& dofmap = *V.dofmap();
  const auto& layout = dofmap.element_dof_layout();
  const auto& geometry = mesh.geometry().dofmap();
  const auto& input = mesh.geometry().input_global_indices();
  const int tdim = mesh.topology().dim();
  const std::int64_t N = node_count(mesh);
  const auto map = dofmap.index_map;
  std::vector<std::int64_t> keys(map->size_local() + map->num_ghosts(), -1);
  std::vector<dolfinx::graph::AdjacencyList<int>> vertices;
  for (int d = 0; d <= tdim; ++d)
    vertices.push_back(dolfinx::mesh::get_entity_vertices(mesh.topology().cell_type(), d));
  // A vertex may hold several dofs (a mixed element's): the i-th is key m + i.
  const std::int64_t m = layout.num_entity_dofs(0) > 0 ? layout.num_entity_dofs(0) : 1;
  for (std::int32_t c = 0; c < geometry.num_nodes(); ++c)
  {
    const auto nodes = geometry.links(c);
    const auto dofs = dofmap.cell_dofs(c);
    for (int d = 0; d <= tdim; ++d)
      for (int e = 0; e < vertices[d].num_nodes(); ++e)
      {
        const auto& local = layout.entity_dofs(d, e);
        if (local.empty())
          continue;
        if (d > 1 || (d == 1 && local.size() > 1))
          throw std::runtime_error("checkpoint: a function space with dofs inside faces or "
                                   "cells, or several on an edge, has no node keys");
        const auto ends = vertices[d].links(e);
        std::int64_t a = input[nodes[ends.front()]], b = input[nodes[ends.back()]];
        if (a > b)
          std::swap(a, b);
        for (std::size_t i = 0; i < local.size(); ++i)
          keys[dofs[local[i]]] = (a * N + b) * m + std::int64_t(i);
      }
  }
  if (std::find(keys.begin(), keys.end(), -1) != keys.end())
    throw std::runtime_error("checkpoint: a dof of the function space belongs to no local cell");
  return keys;
}

std::string mesh_fingerprint(const Mesh& mesh)
{
  MPI_Comm comm = mesh.comm();
  const auto& geometry = mesh.geometry();
  const auto& input = geometry.input_global_indices();
  const std::int32_t owned_nodes = geometry.index_map()->size_local();
  std::uint64_t nodes = 0, cells = 0;
  for (std::int32_t i = 0; i < owned_nodes; ++i)
    nodes += fnv1a(&geometry.x()[3 * i], 3 * sizeof(double),
                   fnv1a(&input[i], sizeof(std::int64_t)));
  const auto& topology = mesh.topology();
  const std::int32_t owned_cells = topology.index_map(topology.dim())->size_local();
  for (std::int32_t c = 0; c < owned_cells; ++c)
  {
    std::vector<std::int64_t> ids;
    for (auto n : geometry.dofmap().links(c))
      ids.push_back(input[n]);
    std::sort(ids.begin(), ids.end());
    cells += fnv1a(ids.data(), ids.size() * sizeof(std::int64_t),
                   fnv1a(&topology.original_cell_index[c], sizeof(std::int64_t)));
  }
  return format("%lld nodes %s, %lld cells %s",
                (long long)geometry.index_map()->size_global(),
                hex(sum_over_ranks(nodes, comm)).c_str(),
                (long long)topology.index_map(topology.dim())->size_global(),
                hex(sum_over_ranks(cells, comm)).c_str());
}

void CheckpointWriter::add(const std::string& name, std::span<const double> values, int bs,
                           std::span<const std::int64_t> keys, std::int32_t owned)
{
  int ranks = 1;
  MPI_Comm_size(_comm, &ranks);
  const bool root = rank_of(_comm) == 0;
  int count = owned;
  std::vector<int> counts(ranks), offsets(ranks + 1, 0);
  MPI_Gather(&count, 1, MPI_INT, counts.data(), 1, MPI_INT, 0, _comm);
  std::partial_sum(counts.begin(), counts.end(), offsets.begin() + 1);
  std::vector<std::int64_t> all_keys(root ? offsets.back() : 0);
  MPI_Gatherv(keys.data(), count, MPI_INT64_T, all_keys.data(), counts.data(), offsets.data(),
              MPI_INT64_T, 0, _comm);
  for (int& c : counts)
    c *= bs;
  for (int& o : offsets)
    o *= bs;
  std::vector<double> all_values(root ? offsets.back() : 0);
  MPI_Gatherv(values.data(), count * bs, MPI_DOUBLE, all_values.data(), counts.data(),
              offsets.data(), MPI_DOUBLE, 0, _comm);
  if (!root)
    return;
  std::vector<std::size_t> order(all_keys.size());
  std::iota(order.begin(), order.end(), 0);
  std::sort(order.begin(), order.end(), [&](auto i, auto j) { return all_keys[i] < all_keys[j]; });
  Data& d = _data[name];
  d.bs = bs;
  d.keys.resize(order.size());
  d.values.resize(order.size() * bs);
  for (std::size_t i = 0; i < order.size(); ++i)
  {
    d.keys[i] = all_keys[order[i]];
    if (i > 0 && d.keys[i] == d.keys[i - 1])
      throw std::runtime_error("checkpoint: two ranks own the key of " + name);
    std::copy_n(&all_values[order[i] * bs], bs, &d.values[i * bs]);
  }
}

void CheckpointWriter::add(const std::string& name, const dolfinx::fem::Function<double>& f)
{
  const auto& V = *f.function_space();
  add(name, f.x()->array(), V.dofmap()->index_map_bs(), keys(V),
      V.dofmap()->index_map->size_local());
}

const std::vector<std::int64_t>& CheckpointWriter::keys(const dolfinx::fem::FunctionSpace& V)
{
  auto [it, fresh] = _keys.try_emplace(&V);
  if (fresh)
    it->second = dof_keys(V);
  return it->second;
}

void CheckpointWriter::add_geometry(const std::string& name, const Mesh& mesh)
{
  add(name, mesh.geometry().x(), 3, node_keys(mesh), mesh.geometry().index_map()->size_local());
}

std::uintmax_t CheckpointWriter::write(const std::filesystem::path& dir, const std::string& name,
                                       nlohmann::json document, int keep)
{
  std::uintmax_t bytes = 0;
  std::string error;
  if (rank_of(_comm) == 0)
  {
    try
    {
      std::filesystem::create_directories(dir);
      const auto file = dir / name;
      auto tmp = file;
      tmp += ".tmp";
      {
        Handle h{H5Fcreate(tmp.c_str(), H5F_ACC_TRUNC, H5P_DEFAULT, H5P_DEFAULT), H5Fclose};
        if (h.id < 0)
          throw std::runtime_error("cannot create " + tmp.string());
        for (const auto& [field, d] : _data)
        {
          const std::string path = "/fields/" + field;
          write_dataset(h.id, path + "/keys", H5T_NATIVE_INT64, d.keys.data(), {d.keys.size()});
          write_dataset(h.id, path + "/values", H5T_NATIVE_DOUBLE, d.values.data(),
                        {d.keys.size(), hsize_t(d.bs)});
          document["fields"][field] = {{"bs", d.bs},
                                       {"blocks", d.keys.size()},
                                       {"keys_fnv", hex(checksum(d.keys))},
                                       {"values_fnv", hex(checksum(d.values))}};
        }
        // A test's kill during the write (tests/checkpoint.py): the fields
        // are in the temporary file, the document not yet.
        static int writes = 0;
        if (const char* n = std::getenv("NCT_TEST_KILL_IN_CHECKPOINT"); n && ++writes == std::atoi(n))
        {
          H5Fflush(h.id, H5F_SCOPE_GLOBAL);
          std::raise(SIGKILL);
        }
        const std::vector<std::uint8_t> cbor = nlohmann::json::to_cbor(document);
        const std::uint64_t hash = checksum(cbor);
        write_dataset(h.id, "/document", H5T_NATIVE_UINT8, cbor.data(), {cbor.size()});
        write_dataset(h.id, "/document_fnv", H5T_NATIVE_UINT64, &hash, {1});
        if (H5Fflush(h.id, H5F_SCOPE_GLOBAL) < 0)
          throw std::runtime_error("cannot flush " + tmp.string());
      }
      // On disk before it takes the name, and the name before `latest`.
      if (int fd = ::open(tmp.c_str(), O_RDONLY); fd >= 0)
        ::fsync(fd), ::close(fd);
      std::filesystem::rename(tmp, file);
      bytes = std::filesystem::file_size(file);
      write_atomic(dir / "latest", name + "\n");
      // The newest `keep` checkpoints stay (names sort by step); a write
      // cut short before this one left a temporary file.
      std::vector<std::filesystem::path> old;
      for (const auto& entry : std::filesystem::directory_iterator(dir))
        if (entry.path().extension() == ".h5")
          old.push_back(entry.path());
        else if (entry.path().extension() == ".tmp")
          std::filesystem::remove(entry.path());
      std::sort(old.begin(), old.end());
      for (std::size_t i = 0; i + keep < old.size(); ++i)
        std::filesystem::remove(old[i]);
    }
    catch (const std::exception& e)
    {
      error = e.what();
    }
  }
  _data.clear();
  int failed = !error.empty();
  MPI_Bcast(&failed, 1, MPI_INT, 0, _comm);
  if (failed)
    throw std::runtime_error("checkpoint: " + (error.empty() ? "rank 0 failed" : error));
  return bytes;
}

CheckpointReader::CheckpointReader(const std::filesystem::path& dir)
{
  const auto latest = dir / "latest";
  std::ifstream named(latest);
  std::string name;
  if (!(named >> name))
    throw CheckpointError("no checkpoint to resume from: " + latest.string()
                          + " is missing (the run wrote none: checkpoint.steps = 0, or it "
                            "stopped before its first boundary)");
  _file = dir / name;
  auto damaged = [&](const std::string& why)
  { return CheckpointError("the checkpoint " + _file.string() + " is damaged: " + why); };
  H5E_auto2_t func;
  void* data;
  H5Eget_auto2(H5E_DEFAULT, &func, &data);
  H5Eset_auto2(H5E_DEFAULT, nullptr, nullptr); // our message, not HDF5's stack
  try
  {
    Handle h{H5Fopen(_file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT), H5Fclose};
    if (h.id < 0)
      throw damaged("HDF5 cannot open it");
    const auto cbor = read_dataset<std::uint8_t>(h.id, "/document", H5T_NATIVE_UINT8);
    const auto hash = read_dataset<std::uint64_t>(h.id, "/document_fnv", H5T_NATIVE_UINT64);
    if (hash.size() != 1 || hash[0] != checksum(cbor))
      throw damaged("the document's checksum does not match");
    _document = nlohmann::json::from_cbor(cbor);
    for (const auto& [field, meta] : _document.at("fields").items())
    {
      Data& d = _data[field];
      d.bs = meta.at("bs");
      const std::string path = "/fields/" + field;
      d.keys = read_dataset<std::int64_t>(h.id, path + "/keys", H5T_NATIVE_INT64);
      d.values = read_dataset<double>(h.id, path + "/values", H5T_NATIVE_DOUBLE);
      if (d.keys.size() != meta.at("blocks").get<std::size_t>()
          || d.values.size() != d.keys.size() * d.bs)
        throw damaged("the field " + field + " has the wrong size");
      if (hex(checksum(d.keys)) != meta.at("keys_fnv") || hex(checksum(d.values)) != meta.at("values_fnv"))
        throw damaged("the field " + field + "'s checksum does not match");
    }
  }
  catch (const CheckpointError&)
  {
    H5Eset_auto2(H5E_DEFAULT, func, data);
    throw;
  }
  catch (const std::exception& e)
  {
    H5Eset_auto2(H5E_DEFAULT, func, data);
    throw damaged(e.what());
  }
  H5Eset_auto2(H5E_DEFAULT, func, data);
}

void CheckpointReader::read(const std::string& name, std::span<double> values, int bs,
                            std::span<const std::int64_t> keys) const
{
  auto it = _data.find(name);
  if (it == _data.end() || it->second.bs != bs)
    throw CheckpointError("the checkpoint " + _file.string() + " has no field " + name);
  const Data& d = it->second;
  for (std::size_t i = 0; i < keys.size(); ++i)
  {
    auto at = std::lower_bound(d.keys.begin(), d.keys.end(), keys[i]);
    if (at == d.keys.end() || *at != keys[i])
      throw CheckpointError("the checkpoint " + _file.string() + "'s field " + name
                            + " does not cover this mesh (another mesh?)");
    std::copy_n(&d.values[(at - d.keys.begin()) * bs], bs, &values[i * bs]);
  }
}

void CheckpointReader::read(const std::string& name, dolfinx::fem::Function<double>& f) const
{
  const auto& V = *f.function_space();
  read(name, f.x()->mutable_array(), V.dofmap()->index_map_bs(), keys(V));
}

const std::vector<std::int64_t>& CheckpointReader::keys(const dolfinx::fem::FunctionSpace& V) const
{
  auto [it, fresh] = _keys.try_emplace(&V);
  if (fresh)
    it->second = dof_keys(V);
  return it->second;
}

void CheckpointReader::read_geometry(const std::string& name, Mesh& mesh) const
{
  read(name, mesh.geometry().x(), 3, node_keys(mesh));
}

} // namespace nct::io
