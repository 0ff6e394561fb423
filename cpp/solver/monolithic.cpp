#include "solver/monolithic.h"

#include <algorithm>
#include <numeric>
#include <stdexcept>

namespace nct::solver
{

Monolithic::Monolithic(MPI_Comm comm, std::vector<Field> fields)
    : _comm(comm), _fields(std::move(fields))
{
  using dolfinx::common::IndexMap;
  const std::size_t n = _fields.size();
  // Each field's map of unknowns: its function's, or the submap of its
  // active nodes (with, per submap ghost, the ghost's place in the full map).
  std::vector<std::unique_ptr<IndexMap>> submaps(n);
  std::vector<std::vector<std::int32_t>> ghost_of(n);
  std::vector<std::pair<std::reference_wrapper<const IndexMap>, int>> maps;
  for (std::size_t f = 0; f < n; ++f)
  {
    const auto& dofmap = *_fields[f].function->function_space()->dofmap();
    if (_fields[f].active)
    {
      auto [sub, ghosts] = dofmap.index_map->create_submap(*_fields[f].active);
      submaps[f] = std::make_unique<IndexMap>(std::move(sub));
      ghost_of[f] = std::move(ghosts);
      maps.emplace_back(*submaps[f], dofmap.index_map_bs());
    }
    else
      maps.emplace_back(*dofmap.index_map, dofmap.index_map_bs());
  }
  auto [offset, local_offset, ghosts, owners] = dolfinx::common::stack_index_maps(maps);
  const std::int32_t owned_total = local_offset.back();
  std::vector<std::int64_t> all_ghosts;
  std::vector<int> all_owners;
  std::vector<std::int32_t> ghost_offset{0};
  for (std::size_t f = 0; f < n; ++f)
  {
    all_ghosts.insert(all_ghosts.end(), ghosts[f].begin(), ghosts[f].end());
    all_owners.insert(all_owners.end(), owners[f].begin(), owners[f].end());
    ghost_offset.push_back(static_cast<std::int32_t>(all_ghosts.size()));
  }
  _map = std::make_shared<IndexMap>(comm, owned_total, all_ghosts, all_owners);
  _x = std::make_unique<dolfinx::la::Vector<double>>(_map, 1);

  // Per local scalar entry of each function: global index and place in x.
  for (std::size_t f = 0; f < n; ++f)
  {
    const auto& dofmap = *_fields[f].function->function_space()->dofmap();
    const IndexMap& full = *dofmap.index_map;
    const int bs = dofmap.index_map_bs();
    const std::int32_t size_local = full.size_local(), num_ghosts = full.num_ghosts();
    std::vector<std::int32_t> node(size_local + num_ghosts, -1); // -> place in the field's map
    if (_fields[f].active)
    {
      const auto& active = *_fields[f].active;
      for (std::size_t p = 0; p < active.size(); ++p)
        node[active[p]] = static_cast<std::int32_t>(p);
      // A ghost's place, offset by size_local as a ghost's local index is.
      for (std::size_t j = 0; j < ghost_of[f].size(); ++j)
        node[size_local + ghost_of[f][j]] = static_cast<std::int32_t>(size_local + j);
    }
    else
      std::iota(node.begin(), node.end(), 0);
    auto& global = _global.emplace_back(bs * node.size(), -1);
    auto& local = _local.emplace_back(bs * node.size(), -1);
    for (std::size_t b = 0; b < node.size(); ++b)
    {
      if (node[b] < 0)
        continue;
      const bool ghost = static_cast<std::int32_t>(b) >= size_local;
      const std::int32_t p = ghost ? node[b] - size_local : node[b];
      for (int k = 0; k < bs; ++k)
      {
        if (!ghost)
        {
          global[bs * b + k] = offset + local_offset[f] + bs * p + k;
          local[bs * b + k] = local_offset[f] + bs * p + k;
        }
        else
        {
          global[bs * b + k] = ghosts[f][bs * p + k];
          local[bs * b + k] = owned_total + ghost_offset[f] + bs * p + k;
        }
      }
    }
  }
  for (std::size_t f = 0; f < n; ++f)
    _global_sizes.push_back(maps[f].first.get().size_global() * maps[f].second);
  pack();
}

void Monolithic::unpack()
{
  auto x = _x->array();
  for (std::size_t f = 0; f < _fields.size(); ++f)
  {
    auto values = _fields[f].function->x()->mutable_array();
    const auto& local = _local[f];
    for (std::size_t i = 0; i < local.size(); ++i)
      if (local[i] >= 0)
        values[i] = x[local[i]];
  }
}

void Monolithic::pack()
{
  auto x = _x->mutable_array();
  for (std::size_t f = 0; f < _fields.size(); ++f)
  {
    auto values = _fields[f].function->x()->array();
    const auto& local = _local[f];
    for (std::size_t i = 0; i < local.size(); ++i)
      if (local[i] >= 0)
        x[local[i]] = values[i];
  }
}

std::int32_t Monolithic::owned(std::size_t f) const
{
  const auto& dofmap = *_fields[f].function->function_space()->dofmap();
  return dofmap.index_map->size_local() * dofmap.index_map_bs();
}

std::int64_t Monolithic::size_global() const { return _map->size_global(); }

std::int64_t Monolithic::size_global(std::size_t f) const { return _global_sizes[f]; }

void Monolithic::insert(std::size_t f, std::span<const double> block,
                        dolfinx::la::Vector<double>& b) const
{
  auto out = b.mutable_array();
  const auto& local = _local[f];
  for (std::int32_t i = 0; i < owned(f); ++i)
    if (local[i] >= 0)
      out[local[i]] = block[i];
}

void Monolithic::extract(std::size_t f, const dolfinx::la::Vector<double>& b,
                         std::span<double> block) const
{
  auto in = b.array();
  const auto& local = _local[f];
  for (std::int32_t i = 0; i < owned(f); ++i)
    block[i] = local[i] >= 0 ? in[local[i]] : 0.0;
}

Mat Monolithic::create_matrix(const std::function<void(Mat)>& assemble) const
{
  const PetscInt n = _map->size_local(), N = _map->size_global();
  Mat P;
  MatCreate(_comm, &P);
  MatSetType(P, MATPREALLOCATOR);
  MatSetSizes(P, n, n, N, N);
  MatSetUp(P);
  assemble(P);
  MatAssemblyBegin(P, MAT_FINAL_ASSEMBLY);
  MatAssemblyEnd(P, MAT_FINAL_ASSEMBLY);
  Mat A;
  MatCreate(_comm, &A);
  MatSetType(A, MATAIJ);
  MatSetSizes(A, n, n, N, N);
  MatPreallocatorPreallocate(P, PETSC_TRUE, A);
  MatDestroy(&P);
  // The pattern is complete: an entry outside it is a bug, not a malloc.
  MatSetOption(A, MAT_NEW_NONZERO_LOCATION_ERR, PETSC_TRUE);
  return A;
}

IS Monolithic::index_set(std::size_t f) const
{
  std::vector<PetscInt> rows;
  const auto& global = _global[f];
  for (std::int32_t i = 0; i < owned(f); ++i)
    if (global[i] >= 0)
      rows.push_back(static_cast<PetscInt>(global[i]));
  IS is;
  ISCreateGeneral(_comm, static_cast<PetscInt>(rows.size()), rows.data(), PETSC_COPY_VALUES,
                  &is);
  return is;
}

std::function<int(std::span<const std::int32_t>, std::span<const std::int32_t>,
                  std::span<const double>)>
add_block(Mat A, const BlockIndices& indices)
{
  return [A, &indices, rows = std::vector<PetscInt>(), cols = std::vector<PetscInt>(),
          scaled = std::vector<double>()](std::span<const std::int32_t> r,
                                          std::span<const std::int32_t> c,
                                          std::span<const double> values) mutable
  {
    const int bs0 = indices.bs0, bs1 = indices.bs1;
    rows.resize(r.size() * bs0);
    cols.resize(c.size() * bs1);
    for (std::size_t i = 0; i < r.size(); ++i)
      for (int k = 0; k < bs0; ++k)
        rows[bs0 * i + k] = static_cast<PetscInt>(indices.rows[bs0 * r[i] + k]);
    for (std::size_t j = 0; j < c.size(); ++j)
      for (int k = 0; k < bs1; ++k)
        cols[bs1 * j + k] = static_cast<PetscInt>(indices.cols[bs1 * c[j] + k]);
    const double* v = values.data();
    if (!indices.row_factor.empty())
    {
      scaled.assign(values.begin(), values.end());
      for (std::size_t i = 0; i < r.size(); ++i)
        for (int k = 0; k < bs0; ++k)
        {
          const double f = indices.row_factor[bs0 * r[i] + k];
          if (f != 1.0)
            for (std::size_t j = 0; j < cols.size(); ++j)
              scaled[(bs0 * i + k) * cols.size() + j] *= f;
        }
      v = scaled.data();
    }
    return static_cast<int>(MatSetValues(A, static_cast<PetscInt>(rows.size()), rows.data(),
                                         static_cast<PetscInt>(cols.size()), cols.data(), v,
                                         ADD_VALUES));
  };
}

} // namespace nct::solver
