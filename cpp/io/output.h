// The run folder: log, atomically written text files, XDMF time series.
#pragma once

#include <filesystem>
#include <fstream>
#include <map>
#include <memory>
#include <string>

#include <dolfinx/fem/Function.h>
#include <mpi.h>
#include <nlohmann/json.hpp>

#include "io/xdmf_series.h"

namespace nct::io
{

/// Write `text` to `file` whole or not at all: a temporary file renamed
/// into place.
void write_atomic(const std::filesystem::path& file, const std::string& text);

/// A run folder on disk. Text files are written whole or not at all
/// (a temporary file renamed into place); only rank 0 writes them.
class RunFolder
{
public:
  /// `append`: continue its run.log (a resumed run) instead of starting it anew.
  RunFolder(MPI_Comm comm, std::filesystem::path dir, bool append = false);
  const std::filesystem::path& dir() const { return _dir; }
  /// Write `name` in the folder atomically.
  void write_text(const std::string& name, const std::string& text) const;
  /// A progress line: on rank 0's stdout and in run.log.
  void log(const std::string& line);

private:
  MPI_Comm _comm;
  std::filesystem::path _dir;
  std::ofstream _log;
};

/// One XDMF file per function, so ParaView opens each as a time series.
/// Functions that are neither DG0 nor on the nodes of the mesh's
/// coordinate element are interpolated to it (scalars to its scalar
/// counterpart) first. The mesh is written once per file, again only if a
/// resumed run's partition lays it out otherwise; files are valid after
/// every write (XdmfSeries).
class Fields
{
public:
  Fields(const RunFolder& folder, std::shared_ptr<const dolfinx::mesh::Mesh> mesh,
         std::shared_ptr<const dolfinx::fem::FunctionSpace> coordinate_space);
  /// Append `f` at `time` to <f.name>.xdmf. Collective.
  void write(const dolfinx::fem::Function<double>& f, double time);
  /// What a checkpoint keeps: each file's steps and the mesh's layout.
  /// Collective.
  nlohmann::json state() const;
  /// Continue the files as `state` left them: the steps after it deleted.
  /// Collective.
  void resume(const nlohmann::json& state);

private:
  std::shared_ptr<const dolfinx::mesh::Mesh> _mesh;
  std::shared_ptr<const dolfinx::fem::FunctionSpace> _coordinate_space;
  std::shared_ptr<const dolfinx::fem::FunctionSpace> _scalar_space; ///< made on first use
  XdmfFiles _files;
};

} // namespace nct::io
