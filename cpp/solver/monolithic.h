// Several blocks' unknowns stacked into one vector, and one PETSc matrix
// over them: the linear algebra of a monolithic Newton system whose
// blocks live on different meshes.
#pragma once

#include <cstdint>
#include <functional>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include <dolfinx/common/IndexMap.h>
#include <dolfinx/fem/Function.h>
#include <dolfinx/la/Vector.h>
#include <petscis.h>
#include <petscmat.h>

namespace nct::solver
{

/// The unknowns of a monolithic system: the values of several functions
/// (each on its own space and mesh), stacked field by field. Each rank
/// holds its owned unknowns of every field, then its ghosts of every
/// field; a field may keep only some of its nodes (`active`), the rest
/// are fixed values that are not unknowns at all.
///
/// Matrices are assembled with global indices (MatSetValues), so a block
/// may add to rows that another rank owns, or another block's rows (the
/// interface of a coupled problem). Their pattern comes from one
/// assembly into a PETSc preallocator (create_matrix).
class Monolithic
{
public:
  struct Field
  {
    std::string name;
    std::shared_ptr<dolfinx::fem::Function<double>> function;
    /// Owned node (block) indices of the function's map that are
    /// unknowns, sorted; none: all of them.
    std::optional<std::vector<std::int32_t>> active;
  };

  Monolithic(MPI_Comm comm, std::vector<Field> fields);

  /// The stacked unknowns (scalar entries: a field's block size unrolled).
  dolfinx::la::Vector<double>& x() { return *_x; }
  /// x -> each field's function (owned and ghost entries); inactive
  /// entries keep their values.
  void unpack();
  /// Each field's function -> x.
  void pack();

  std::size_t fields() const { return _fields.size(); }
  const Field& field(std::size_t f) const { return _fields[f]; }
  /// Per local scalar entry (owned, then ghost) of field f's function:
  /// its global index in the system, -1 if inactive.
  const std::vector<std::int64_t>& global(std::size_t f) const { return _global[f]; }
  /// Per local scalar entry of field f's function: its place in x's
  /// array, -1 if inactive.
  const std::vector<std::int32_t>& local(std::size_t f) const { return _local[f]; }
  /// Number of owned scalar entries of field f's function (its map's
  /// size_local() times its block size).
  std::int32_t owned(std::size_t f) const;
  std::int64_t size_global() const;
  std::int64_t size_global(std::size_t f) const;

  /// Copy the owned entries of a field's block vector (laid out as its
  /// function's) into `b` (laid out as x); inactive entries are left out.
  void insert(std::size_t f, std::span<const double> block, dolfinx::la::Vector<double>& b) const;
  /// The field's part of `b` (owned entries; inactive ones zero) into `block`.
  void extract(std::size_t f, const dolfinx::la::Vector<double>& b, std::span<double> block) const;

  /// An AIJ matrix whose pattern is every entry `assemble(A)` sets (run
  /// once on a PETSc preallocator, with the same calls as later).
  Mat create_matrix(const std::function<void(Mat)>& assemble) const;
  /// The owned rows of field f as a PETSc index set (e.g. a fieldsplit block).
  IS index_set(std::size_t f) const;

private:
  MPI_Comm _comm;
  std::vector<Field> _fields;
  std::vector<std::vector<std::int64_t>> _global;
  std::vector<std::vector<std::int32_t>> _local;
  std::shared_ptr<dolfinx::common::IndexMap> _map;
  std::unique_ptr<dolfinx::la::Vector<double>> _x;
  std::vector<std::int64_t> _global_sizes;
};

/// The row and column indices of a block of a matrix assembled into a
/// Monolithic one, and a factor per row: per local scalar entry of the
/// test (rows) and trial (columns) function spaces, its global index, or
/// -1 to leave it out (a Dirichlet or constrained row, a fixed column).
struct BlockIndices
{
  std::vector<std::int64_t> rows, cols;
  std::vector<double> row_factor; ///< empty: 1 everywhere
  int bs0 = 1, bs1 = 1;           ///< block sizes of the two spaces
};

/// The function dolfinx's assemble_matrix calls with each cell's matrix
/// (block indices of the two spaces): adds it to A at the global places
/// `indices` gives, each row scaled by its factor. `indices` must outlive it.
std::function<int(std::span<const std::int32_t>, std::span<const std::int32_t>,
                  std::span<const double>)>
add_block(Mat A, const BlockIndices& indices);

} // namespace nct::solver
